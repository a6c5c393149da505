//! The search for values of the pair variables: propagation of what each constraint
//! forces, and depth-first decisions with an undo trail.

use super::{Constraint, LayerError, Lit, Problem, SEARCH_BUDGET};
use crate::fab::budget::Budget;

/// Depth-first search with propagation and an undo trail.
pub(super) struct Search<'a> {
    pub(super) problem: &'a Problem,
    /// The pieces taken into account (all when `None`).
    pub(super) only: Option<&'a [bool]>,
    pub(super) watching: Vec<Vec<usize>>,
    pub(super) value: Vec<Option<bool>>,
    pub(super) trail: Vec<usize>,
    pub(super) decisions: usize,
    pub(super) budget: &'a Budget,
}

impl Search<'_> {
    fn lit(&self, l: Lit) -> Option<bool> {
        self.value[l.var].map(|v| v == l.value)
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

    /// Sets a variable and everything it forces; false on a contradiction (the trail
    /// keeps what was set, for undoing).
    pub(super) fn assign(&mut self, var: usize, v: bool) -> bool {
        let mut queue = vec![(var, v)];
        while let Some((x, v)) = queue.pop() {
            match self.value[x] {
                Some(old) if old == v => continue,
                Some(_) => return false,
                None => {
                    self.value[x] = Some(v);
                    self.trail.push(x);
                }
            }
            if !self.transitive(x, &mut queue) {
                return false;
            }
            for &k in &self.watching[x] {
                match self.problem.constraints[k] {
                    Constraint::Same(a, b) => {
                        for (p, q) in [(a, b), (b, a)] {
                            if let Some(t) = self.lit(p) {
                                // q must have the same truth.
                                queue.push((q.var, t == q.value));
                            }
                        }
                    }
                    Constraint::Parity(l) => {
                        let (ones, unknown, last) = self.tally(&l);
                        match (unknown, last) {
                            (0, _) if ones % 2 == 1 => return false,
                            (1, Some(u)) => {
                                let need_true = ones % 2 == 1;
                                queue.push((u.var, need_true == u.value));
                            }
                            _ => {}
                        }
                    }
                }
            }
        }
        true
    }

    /// The "no cycle" constraints of the triples through variable `x` (both of each:
    /// not a above b above c above a, nor the reverse), pushing what they force. `x` is
    /// the pair a < b, so "a above b" is `x` itself; the other two pairs are looked up.
    fn transitive(&self, x: usize, queue: &mut Vec<(usize, bool)>) -> bool {
        let p = self.problem;
        let (a, b) = p.pairs[x];
        let ab = Lit {
            var: x,
            value: true,
        };
        for &c in &p.thirds[x] {
            let c = c as usize;
            if self.only.is_some_and(|keep| !keep[c]) {
                continue;
            }
            let lits = [
                ab,
                p.above(b, c).expect("a triple's pairs overlap"),
                p.above(c, a).expect("a triple's pairs overlap"),
            ];
            for negate in [false, true] {
                let l = lits.map(|l| Lit {
                    var: l.var,
                    value: l.value != negate,
                });
                let (trues, unknown, last) = self.tally(&l);
                if trues == 3 {
                    return false;
                }
                if let (2, 1, Some(u)) = (trues, unknown, last) {
                    queue.push((u.var, !u.value));
                }
            }
        }
        true
    }

    fn undo_to(&mut self, mark: usize) {
        for x in self.trail.drain(mark..) {
            self.value[x] = None;
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
                    self.budget.check()?;
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

    /// Decides the variables in `order` not yet set: true when all could be. Depth
    /// first: each decision tries "above" then "below"; a contradiction undoes back to the
    /// latest decision with a branch left.
    pub(super) fn run(&mut self, order: &[usize]) -> Result<bool, LayerError> {
        let mut stack: Vec<(usize, usize, bool)> = Vec::new();
        let mut pos = 0;
        loop {
            while pos < order.len() && self.value[order[pos]].is_some() {
                pos += 1;
            }
            if pos == order.len() {
                return Ok(true);
            }
            self.decisions += 1;
            if self.decisions > SEARCH_BUDGET {
                return Err(LayerError::GaveUp(SEARCH_BUDGET));
            }
            if self.decisions.is_multiple_of(1024) {
                self.budget.check()?;
            }
            let mark = self.trail.len();
            if self.assign(order[pos], true) {
                stack.push((pos, mark, false));
                continue;
            }
            self.undo_to(mark);
            if self.assign(order[pos], false) {
                stack.push((pos, mark, true));
                continue;
            }
            self.undo_to(mark);
            loop {
                let Some((p, m, tried_both)) = stack.pop() else {
                    return Ok(false);
                };
                self.undo_to(m);
                if !tried_both {
                    if self.assign(order[p], false) {
                        stack.push((p, m, true));
                        pos = p;
                        break;
                    }
                    self.undo_to(m);
                }
            }
        }
    }
}
