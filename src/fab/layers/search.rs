//! The search for values of the pair variables: propagation of what each constraint
//! forces, and conflict-driven decisions with clause learning (CDCL, as SAT solvers do).
//!
//! A plain depth-first search undoes only its latest decision when it meets a
//! contradiction, so a wrong early choice is paid for by every arrangement of the
//! choices after it: exponential on the patterns where the layers' constraints chain
//! round a closed loop (a tube folded flat, Tarantula's stacked flaps). Here each
//! contradiction is traced back through the constraints that forced it to the decisions
//! that caused it (the first unique implication point), the negation of those causes is
//! kept as a learnt clause, and the search jumps back to where that clause first forces
//! something. Variables seen in recent contradictions are decided first (VSIDS), each
//! keeps the side it last had (phase saving), and the search restarts on Luby's
//! sequence; all three are standard and none changes what is decided, only how fast.

use super::{Constraint, LayerError, Lit, Problem, SpreadRow, SEARCH_BUDGET};
use crate::fab::budget::Budget;
use std::collections::BinaryHeap;

/// Why a variable has its value: what [`Search::causes`] traces a contradiction through.
#[derive(Clone, Copy, Debug)]
enum Reason {
    /// Decided (or given: a crease's side, a count's branch).
    Decision,
    /// Forced by constraint `k` of the problem.
    Constraint(u32),
    /// Forced by the "no cycle" rule of the triple of pair `x` with piece `c`.
    Triple(u32, u32),
    /// Forced by learnt clause `k`.
    Learnt(u32),
}

/// Conflicts between restarts, times Luby's sequence (1, 1, 2, 1, 1, 2, 4, …).
const RESTART_UNIT: u64 = 100;
/// VSIDS: each conflict's bump grows by this factor, so older bumps fade.
const ACTIVITY_GROWTH: f64 = 1.0 / 0.95;

/// Propagation, decisions, learning and an undo trail over a [`Problem`]'s variables.
pub(super) struct Search<'a> {
    problem: &'a Problem,
    /// The pieces taken into account (all when `None`).
    only: Option<&'a [bool]>,
    /// Per variable, the constraints it takes part in.
    watching: Vec<Vec<u32>>,
    pub(super) value: Vec<Option<bool>>,
    /// Variables in the order they were set.
    trail: Vec<usize>,
    /// Trail entries whose consequences are propagated.
    propagated: usize,
    /// Per decision level above the run's start, where it begins on the trail.
    level_starts: Vec<usize>,
    level: Vec<u32>,
    reason: Vec<Reason>,
    learnt: Vec<Vec<Lit>>,
    /// Per variable, the learnt clauses watching it (their first two literals).
    learnt_watch: Vec<Vec<u32>>,
    activity: Vec<f64>,
    bump: f64,
    /// Each variable's last value, tried first when it is decided again.
    phase: Vec<bool>,
    /// [`Search::analyse`]'s marks, all false between analyses (kept here, not
    /// allocated per group: a pattern may have thousands of groups).
    seen: Vec<bool>,
    decisions: usize,
    /// Work done since the budget was last told ([`Budget::spend`]): the constraints,
    /// triples and learnt clauses propagation visited.
    unspent: u64,
    budget: &'a Budget,
    /// The rows of the two pieces of the pair whose triples were last propagated.
    rows: [SpreadRow; 2],
}

impl<'a> Search<'a> {
    /// A search with nothing set; `watching` lists each variable's constraints.
    pub(super) fn new(
        problem: &'a Problem,
        only: Option<&'a [bool]>,
        watching: Vec<Vec<u32>>,
        budget: &'a Budget,
    ) -> Search<'a> {
        let n = problem.pairs.len();
        Search {
            problem,
            only,
            watching,
            value: vec![None; n],
            trail: Vec::new(),
            propagated: 0,
            level_starts: Vec::new(),
            level: vec![0; n],
            reason: vec![Reason::Decision; n],
            learnt: Vec::new(),
            learnt_watch: vec![Vec::new(); n],
            activity: vec![0.0; n],
            bump: 1.0,
            phase: vec![true; n],
            seen: vec![false; n],
            decisions: 0,
            unspent: 0,
            budget,
            rows: [0, 1].map(|_| SpreadRow::new(problem.members.len())),
        }
    }

    /// Tells the budget the work done since the last checkpoint, and checks it.
    fn checkpoint(&mut self) -> Result<(), LayerError> {
        let units = std::mem::take(&mut self.unspent);
        Ok(self.budget.spend(units)?)
    }

    fn lit(&self, l: Lit) -> Option<bool> {
        self.value[l.var()].map(|v| v == l.value)
    }

    /// Of some literals: how many are true, how many unknown, and the last unknown one
    /// (counted in place: this runs for every constraint a new value touches).
    fn tally(&self, lits: &[Lit]) -> (usize, usize, Option<Lit>) {
        let (mut trues, mut unknown, mut last) = (0, 0, None);
        for &l in lits {
            match self.lit(l) {
                Some(true) => trues += 1,
                Some(false) => {}
                None => {
                    unknown += 1;
                    last = Some(l);
                }
            }
        }
        (trues, unknown, last)
    }

    /// Sets an unset variable, recording why, at the current level.
    fn set(&mut self, var: usize, v: bool, why: Reason) {
        self.value[var] = Some(v);
        self.level[var] = self.level_starts.len() as u32;
        self.reason[var] = why;
        self.trail.push(var);
    }

    /// Sets a variable and everything it forces; false on a contradiction (the trail
    /// keeps what was set, for undoing).
    pub(super) fn assign(&mut self, var: usize, v: bool) -> bool {
        match self.value[var] {
            Some(old) => old == v,
            None => {
                self.set(var, v, Reason::Decision);
                self.propagate().is_none()
            }
        }
    }

    /// Propagates every value on the trail not yet propagated; on a contradiction, the
    /// variables of the constraint it breaks (all set).
    fn propagate(&mut self) -> Option<Vec<usize>> {
        while self.propagated < self.trail.len() {
            let x = self.trail[self.propagated];
            self.propagated += 1;
            self.unspent += (1
                + self.watching[x].len()
                + self.problem.thirds.len(x)
                + self.learnt_watch[x].len()) as u64;
            if let Some(conflict) = self
                .transitive(x)
                .or_else(|| self.constraints_of(x))
                .or_else(|| self.learnt_of(x))
            {
                return Some(conflict);
            }
        }
        None
    }

    /// The problem's constraints through `x`.
    fn constraints_of(&mut self, x: usize) -> Option<Vec<usize>> {
        for i in 0..self.watching[x].len() {
            let k = self.watching[x][i];
            let why = Reason::Constraint(k);
            match self.problem.constraints[k as usize] {
                Constraint::Same(a, b) => {
                    for (p, q) in [(a, b), (b, a)] {
                        let Some(t) = self.lit(p) else { continue };
                        match self.lit(q) {
                            None => self.set(q.var(), t == q.value, why),
                            Some(u) if u != t => return Some(vec![a.var(), b.var()]),
                            Some(_) => {}
                        }
                    }
                }
                Constraint::Parity(l) => match self.tally(&l) {
                    (ones, 0, _) if ones % 2 == 1 => return Some(l.map(|x| x.var()).to_vec()),
                    (ones, 1, Some(u)) => self.set(u.var(), (ones % 2 == 1) == u.value, why),
                    _ => {}
                },
            }
        }
        None
    }

    /// The three literals of the triple of pair `x` = (a, b) with piece `c`, "a above
    /// b above c above a": a cycle when all three hold, or none does. Looked up in the
    /// spread rows when they hold a's and b's, else in the index.
    fn triple(&self, x: usize, c: usize) -> [Lit; 3] {
        let p = self.problem;
        let (a, b) = p.pairs[x];
        let overlap = "a triple's pairs overlap";
        [
            Lit::new(x, true),
            self.rows[1].above(p, b, c).expect(overlap),
            // "c above a", looked up in a's row (a and b are this loop's, c varies).
            self.rows[0].above(p, a, c).expect(overlap).negated(),
        ]
    }

    /// The "no cycle" constraints of the triples through pair `x` (both of each: not a
    /// above b above c above a, nor the reverse), setting what they force.
    ///
    /// `x` is set, so of each triple's two constraints only the one whose literal of `x`
    /// holds can be broken or force anything: the cycle through the triple's other two
    /// literals in the sense `x` now runs. Both hold in that sense: a contradiction; one
    /// does and the other is unknown: the unknown one runs the other way.
    fn transitive(&mut self, x: usize) -> Option<Vec<usize>> {
        let problem = self.problem;
        if problem.worth_spreading(x, problem.thirds.len(x)) {
            let (a, b) = problem.pairs[x];
            self.rows[0].load(problem, a);
            self.rows[1].load(problem, b);
        }
        let runs = self.value[x].expect("a propagated variable is set");
        for c in problem.thirds.of(x) {
            if self.only.is_some_and(|keep| !keep[c]) {
                continue;
            }
            let [_, y, z] = self.triple(x, c);
            let forced = match (self.lit(y), self.lit(z)) {
                (Some(s), Some(t)) if s == runs && t == runs => {
                    return Some(vec![x, y.var(), z.var()]);
                }
                (Some(s), None) if s == runs => z,
                (None, Some(t)) if t == runs => y,
                _ => continue,
            };
            // The unknown literal takes the other sense from x's, so the cycle stays open.
            self.set(
                forced.var(),
                forced.value != runs,
                Reason::Triple(x as u32, c as u32),
            );
        }
        None
    }

    /// The learnt clauses watching `x`, now set: each moves its watch to a literal not
    /// yet false, or forces its other watched literal, or is broken.
    fn learnt_of(&mut self, x: usize) -> Option<Vec<usize>> {
        let mut watchers = std::mem::take(&mut self.learnt_watch[x]);
        let mut conflict = None;
        let mut i = 0;
        while i < watchers.len() {
            let k = watchers[i] as usize;
            let value = |l: Lit| self.value[l.var()].map(|v| v == l.value);
            let clause = &mut self.learnt[k];
            if clause[0].var() == x {
                clause.swap(0, 1);
            }
            let first = clause[0];
            if value(clause[1]) != Some(false) || value(first) == Some(true) {
                i += 1;
                continue;
            }
            if let Some(j) = (2..clause.len()).find(|&j| value(clause[j]) != Some(false)) {
                clause.swap(1, j);
                let moved_to = clause[1].var();
                self.learnt_watch[moved_to].push(k as u32);
                watchers.swap_remove(i);
                continue;
            }
            if value(first).is_some() {
                conflict = Some(clause.iter().map(|l| l.var()).collect());
                break;
            }
            self.set(first.var(), first.value, Reason::Learnt(k as u32));
            i += 1;
        }
        // Watches moved onto x itself while it was taken out stay too.
        watchers.append(&mut self.learnt_watch[x]);
        self.learnt_watch[x] = watchers;
        conflict
    }

    /// The variables whose values forced `var`'s (none for a decision).
    fn causes(&self, var: usize) -> Vec<usize> {
        let others = |vars: &[usize]| vars.iter().copied().filter(|&v| v != var).collect();
        match self.reason[var] {
            Reason::Decision => Vec::new(),
            Reason::Constraint(k) => match self.problem.constraints[k as usize] {
                Constraint::Same(a, b) => others(&[a.var(), b.var()]),
                Constraint::Parity(l) => others(&l.map(|x| x.var())),
            },
            Reason::Triple(x, c) => others(&self.triple(x as usize, c as usize).map(|l| l.var())),
            Reason::Learnt(k) => {
                let vars: Vec<usize> = self.learnt[k as usize].iter().map(|l| l.var()).collect();
                others(&vars)
            }
        }
    }

    /// From a contradiction among `conflict`'s variables, the clause to learn (its
    /// first literal the one it will force) and the level to jump back to: the causes
    /// traced back on the trail to the first unique implication point.
    fn analyse(&mut self, conflict: Vec<usize>) -> (Vec<Lit>, usize) {
        let mut seen = std::mem::take(&mut self.seen);
        let current = self.level_starts.len() as u32;
        let mut earlier: Vec<usize> = Vec::new();
        let mut open = 0usize;
        let mut at = self.trail.len();
        let mut causes = conflict;
        let uip = loop {
            for v in causes {
                if seen[v] || self.level[v] == 0 {
                    continue;
                }
                seen[v] = true;
                self.activity[v] += self.bump;
                if self.level[v] == current {
                    open += 1;
                } else {
                    earlier.push(v);
                }
            }
            let v = loop {
                at -= 1;
                if seen[self.trail[at]] {
                    break self.trail[at];
                }
            };
            seen[v] = false;
            open -= 1;
            if open == 0 {
                break v;
            }
            causes = self.causes(v);
        };
        for &v in &earlier {
            seen[v] = false;
        }
        self.seen = seen;
        self.bump *= ACTIVITY_GROWTH;
        if self.bump > 1e100 {
            self.activity.iter_mut().for_each(|a| *a *= 1e-100);
            self.bump *= 1e-100;
        }
        // The clause says: not all of these values again.
        let negated = |v: usize| Lit::new(v, !self.value[v].expect("a cause is set"));
        let mut clause = vec![negated(uip)];
        earlier.sort_by_key(|&v| std::cmp::Reverse(self.level[v]));
        let back_to = earlier.first().map_or(0, |&v| self.level[v] as usize);
        clause.extend(earlier.into_iter().map(negated));
        (clause, back_to)
    }

    /// Undoes every value set from trail position `mark` on.
    pub(super) fn undo_to(&mut self, mark: usize) {
        for x in self.trail.drain(mark..) {
            self.phase[x] = self.value[x].expect("the trail holds set variables");
            self.value[x] = None;
        }
        self.propagated = self.propagated.min(mark);
    }

    /// Back to decision `level` (0: the run's start), returning the freed variables.
    fn back_to(&mut self, level: usize, free: &mut BinaryHeap<(Activity, usize)>) {
        if level < self.level_starts.len() {
            let mark = self.level_starts[level];
            for &x in &self.trail[mark..] {
                free.push((Activity(self.activity[x]), x));
            }
            self.undo_to(mark);
            self.level_starts.truncate(level);
        }
    }

    /// How many assignments of the variables in `order` not yet set keep every
    /// constraint, counted up to `cap` (then `true`: there are at least that many). Depth
    /// first over both branches of every decision; the values are left as they were.
    pub(super) fn count(&mut self, order: &[usize], cap: u64) -> Result<(u64, bool), LayerError> {
        let base = self.trail.len();
        let mut count = 0u64;
        let mut stack: Vec<(usize, usize, bool)> = Vec::new();
        let mut pos = 0;
        loop {
            while pos < order.len() && self.value[order[pos]].is_some() {
                pos += 1;
            }
            let mut descended = false;
            if pos == order.len() {
                count += 1;
                if count >= cap {
                    self.undo_to(base);
                    return Ok((count, true));
                }
            } else {
                self.decisions += 1;
                if self.decisions.is_multiple_of(1024) {
                    self.checkpoint()?;
                }
                let mark = self.trail.len();
                for (value, tried_both) in [(true, false), (false, true)] {
                    if self.assign(order[pos], value) {
                        stack.push((pos, mark, tried_both));
                        descended = true;
                        break;
                    }
                    self.undo_to(mark);
                }
            }
            if descended {
                continue;
            }
            // Back to the latest decision with its "below" branch left.
            loop {
                let Some((p, m, tried_both)) = stack.pop() else {
                    self.undo_to(base);
                    return Ok((count, false));
                };
                self.undo_to(m);
                if !tried_both && self.assign(order[p], false) {
                    stack.push((p, m, true));
                    pos = p;
                    break;
                }
                self.undo_to(m);
            }
        }
    }

    /// Decides the variables in `order` not yet set (one independent group: no
    /// constraint joins them to a variable outside it): true when all could be, false
    /// when the group has no values, proved by a contradiction that no decision caused.
    /// What was set before stays set.
    pub(super) fn run(&mut self, order: &[usize]) -> Result<bool, LayerError> {
        let decided = self.decide(order)?;
        // Under a work budget every unit is told, so searches that share it stop at the
        // same point on any machine.
        if self.budget.work.is_some() {
            self.checkpoint()?;
        }
        Ok(decided)
    }

    /// [`Search::run`]'s conflict-driven search.
    fn decide(&mut self, order: &[usize]) -> Result<bool, LayerError> {
        self.level_starts.clear();
        let mut free: BinaryHeap<(Activity, usize)> = order
            .iter()
            .map(|&v| (Activity(self.activity[v]), v))
            .collect();
        let (mut conflicts, mut restart) = (0u64, 1u64);
        let mut next_restart = RESTART_UNIT;
        loop {
            if let Some(conflict) = self.propagate() {
                if self.level_starts.is_empty() {
                    return Ok(false);
                }
                let (clause, level) = self.analyse(conflict);
                self.back_to(level, &mut free);
                let (var, value) = (clause[0].var(), clause[0].value);
                let k = self.learnt.len() as u32;
                if clause.len() > 1 {
                    self.learnt_watch[clause[0].var()].push(k);
                    self.learnt_watch[clause[1].var()].push(k);
                }
                self.learnt.push(clause);
                self.set(var, value, Reason::Learnt(k));
                conflicts += 1;
                // A conflict can cost a long propagation: the deadline is watched here
                // as well as between decisions.
                if conflicts.is_multiple_of(64) {
                    self.checkpoint()?;
                }
                if conflicts >= next_restart {
                    restart += 1;
                    next_restart = conflicts + RESTART_UNIT * luby(restart);
                    self.back_to(0, &mut free);
                }
                continue;
            }
            let Some(var) = std::iter::from_fn(|| free.pop())
                .map(|(_, v)| v)
                .find(|&v| self.value[v].is_none())
            else {
                return Ok(true);
            };
            self.decisions += 1;
            if self.decisions > SEARCH_BUDGET {
                return Err(LayerError::GaveUp(SEARCH_BUDGET));
            }
            if self.decisions.is_multiple_of(1024) {
                self.checkpoint()?;
            }
            self.level_starts.push(self.trail.len());
            self.set(var, self.phase[var], Reason::Decision);
        }
    }
}

/// A variable's activity, ordered (activities are finite and never negative).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Activity(f64);

impl Eq for Activity {}

impl PartialOrd for Activity {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Activity {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// Luby's sequence, 1-based: 1, 1, 2, 1, 1, 2, 4, 1, 1, 2, 1, 1, 2, 4, 8, …
fn luby(i: u64) -> u64 {
    let mut k = 1;
    while (1u64 << k) - 1 < i {
        k += 1;
    }
    if (1u64 << k) - 1 == i {
        1 << (k - 1)
    } else {
        luby(i - (1u64 << (k - 1)) + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::luby;

    #[test]
    fn luby_sequence_starts_as_published() {
        let first: Vec<u64> = (1..=15).map(luby).collect();
        assert_eq!(first, [1, 1, 2, 1, 1, 2, 4, 1, 1, 2, 1, 1, 2, 4, 8]);
    }
}
