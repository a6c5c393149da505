//! Counting the flat-folded states: every assignment of the pair variables that keeps
//! every constraint is one layer order. After the creases' fixed values are propagated,
//! the variables still open fall into groups that share no constraint; the states are the
//! product of each group's count, and each group is enumerated depth first (up to a
//! cap, as Flat-Folder's 10,000 a component).

use super::problem::Constraint;
use super::search::Search;
use super::{LayerError, Problem};
use crate::fab::budget::Budget;
use crate::mesh::UnionFind;
use std::collections::HashMap;

/// The states of one independent group of open variables.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GroupCount {
    /// Layer orders of the group found (at most the cap).
    pub count: u64,
    /// Whether the enumeration stopped at the cap (the group has at least `count`).
    pub capped: bool,
}

impl Problem {
    /// The count of every independent group, or `None` when the fixed values already
    /// contradict each other (no state).
    pub(super) fn count_states(
        &self,
        budget: &Budget,
        cap: u64,
    ) -> Result<Option<Vec<GroupCount>>, LayerError> {
        let mut watching: Vec<Vec<u32>> = vec![Vec::new(); self.pairs.len()];
        for (k, c) in self.constraints.iter().enumerate() {
            for v in c.vars() {
                watching[v].push(k as u32);
            }
        }
        let mut search = Search::new(self, None, watching, budget);
        for &(var, v) in &self.fixed {
            if !search.assign(var, v) {
                return Ok(None);
            }
        }
        let open = |v: usize| search.value[v].is_none();
        // Groups of the open variables: joined by any constraint or triple that still
        // binds two of them.
        let mut group = UnionFind::new(self.pairs.len());
        let mut join = |vars: &[usize]| {
            let mut open_vars = vars.iter().copied().filter(|&v| open(v));
            if let Some(first) = open_vars.next() {
                for v in open_vars {
                    group.union(first, v);
                }
            }
        };
        for c in &self.constraints {
            join(&c.vars());
        }
        // A triple binds its variables only while its pieces can still form a cycle: an
        // equality the taco–tortilla constraints set between two of its pairs (a tortilla
        // under both faces of a crease, or over both) rules both cycles out, so the third
        // pair stays free of the other two, as in Flat-Folder's reduced transitivity.
        let mut equal = Relations::new(self.pairs.len());
        for c in &self.constraints {
            if let Constraint::Same(x, y) = c {
                if open(x.var()) && open(y.var()) {
                    equal.relate(x.var(), y.var(), x.value != y.value);
                }
            }
        }
        self.for_each_triple(None, |vars| {
            if self.can_cycle(vars, &search.value, &equal) {
                join(&vars);
            }
        });
        let mut members: HashMap<usize, Vec<usize>> = HashMap::new();
        for v in (0..self.pairs.len()).filter(|&v| open(v)) {
            members.entry(group.find(v)).or_default().push(v);
        }
        let mut groups: Vec<Vec<usize>> = members.into_values().collect();
        groups.sort_unstable();
        let mut counts = Vec::with_capacity(groups.len());
        for g in &groups {
            let (count, capped) = search.count(g, cap)?;
            if count == 0 {
                return Ok(None);
            }
            counts.push(GroupCount { count, capped });
        }
        Ok(Some(counts))
    }

    /// Whether the pieces of the triple whose pair variables are `[ab, bc, ac]` (as
    /// [`Problem::for_each_triple`] gives them) can still lie in a cycle a > b > c > a or
    /// its reverse, given the variables' fixed `value`s and the relations `equal` holds
    /// between open ones.
    fn can_cycle(
        &self,
        [ab, bc, ac]: [usize; 3],
        value: &[Option<bool>],
        equal: &Relations,
    ) -> bool {
        let (a, b) = self.pairs[ab];
        let (p, q) = self.pairs[ac];
        let c = if p == a { q } else { p };
        // Each variable is true when its pair's lower-numbered piece lies above.
        let forward = [(ab, true), (bc, b < c), (ac, c < a)];
        let backward = forward.map(|(var, up)| (var, !up));
        [forward, backward].iter().any(|cycle| {
            let values_allow = cycle
                .iter()
                .all(|&(var, up)| value[var].is_none_or(|v| v == up));
            let relations_allow = (0..3).all(|i| {
                (i + 1..3).all(|j| {
                    let ((u, up_u), (w, up_w)) = (cycle[i], cycle[j]);
                    equal.differ(u, w).is_none_or(|d| d == (up_u != up_w))
                })
            });
            values_allow && relations_allow
        })
    }
}

/// What equalities between variables imply: for two variables joined by a chain of
/// them, whether their values are equal or opposite (a union–find that keeps each
/// member's parity to its set's root).
struct Relations {
    parent: Vec<usize>,
    /// Whether a member's value is the opposite of its parent's.
    flipped: Vec<bool>,
    /// Members under each root: the smaller set goes under the larger, so no member is
    /// more than log₂ n steps from its root.
    size: Vec<u32>,
}

impl Relations {
    fn new(n: usize) -> Relations {
        Relations {
            parent: (0..n).collect(),
            flipped: vec![false; n],
            size: vec![1; n],
        }
    }

    /// The root of `v`'s set, and whether `v`'s value is the opposite of the root's.
    fn root(&self, mut v: usize) -> (usize, bool) {
        let mut flipped = false;
        while self.parent[v] != v {
            flipped ^= self.flipped[v];
            v = self.parent[v];
        }
        (v, flipped)
    }

    /// Records that `u` and `w` differ (`true`) or are equal (`false`); a relation that
    /// contradicts the known ones is left for the search to find.
    fn relate(&mut self, u: usize, w: usize, differ: bool) {
        let ((ru, fu), (rw, fw)) = (self.root(u), self.root(w));
        if ru != rw {
            let (child, root) = if self.size[ru] <= self.size[rw] {
                (ru, rw)
            } else {
                (rw, ru)
            };
            self.parent[child] = root;
            self.flipped[child] = fu ^ fw ^ differ;
            self.size[root] += self.size[child];
        }
    }

    /// Whether `u` and `w` are known to differ, to be equal, or neither.
    fn differ(&self, u: usize, w: usize) -> Option<bool> {
        let ((ru, fu), (rw, fw)) = (self.root(u), self.root(w));
        (ru == rw).then_some(fu != fw)
    }
}

/// A count of states as a decimal number of any size (products of group counts outgrow
/// any machine word: Ryujin 2.1 has about 1.5 × 10⁸³).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StateTotal {
    /// Base-10⁹ digits, least significant first.
    limbs: Vec<u32>,
}

impl StateTotal {
    /// The product of the groups' counts.
    pub fn product(groups: &[GroupCount]) -> StateTotal {
        let mut limbs = vec![1u32];
        for g in groups {
            let mut carry = 0u128;
            for limb in &mut limbs {
                let x = u128::from(*limb) * u128::from(g.count) + carry;
                *limb = (x % 1_000_000_000) as u32;
                carry = x / 1_000_000_000;
            }
            while carry > 0 {
                limbs.push((carry % 1_000_000_000) as u32);
                carry /= 1_000_000_000;
            }
        }
        StateTotal { limbs }
    }
}

impl std::fmt::Display for StateTotal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut limbs = self.limbs.iter().rev();
        write!(f, "{}", limbs.next().copied().unwrap_or(0))?;
        for limb in limbs {
            write!(f, "{limb:09}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Relations compose along chains: equal to equal is equal, differ then equal
    /// differs, differ twice is equal; unrelated variables say nothing. Checked against
    /// brute force over every assignment of eight variables a random chain of relations
    /// allows.
    #[test]
    fn relations_compose_along_chains_as_brute_force_finds() {
        let mut rng = crate::random::Rng::new(7);
        for _ in 0..50 {
            let n = 8;
            let mut relations = Relations::new(n);
            let mut facts = Vec::new();
            for _ in 0..5 {
                let (u, w) = (rng.below(n), rng.below(n));
                let differ = rng.below(2) == 1;
                if u != w && relations.differ(u, w).is_none() {
                    relations.relate(u, w, differ);
                    facts.push((u, w, differ));
                }
            }
            let allowed: Vec<u32> = (0..1u32 << n)
                .filter(|bits| {
                    let v = |i: usize| bits >> i & 1 == 1;
                    facts.iter().all(|&(u, w, d)| (v(u) != v(w)) == d)
                })
                .collect();
            for u in 0..n {
                for w in 0..n {
                    let seen: std::collections::HashSet<bool> = allowed
                        .iter()
                        .map(|bits| (bits >> u & 1) != (bits >> w & 1))
                        .collect();
                    let forced = (seen.len() == 1).then(|| *seen.iter().next().unwrap());
                    assert_eq!(relations.differ(u, w), forced, "{facts:?}: {u} {w}");
                }
            }
        }
    }

    #[test]
    fn a_product_of_counts_is_exact_past_any_word() {
        let g = |count| GroupCount {
            count,
            capped: false,
        };
        assert_eq!(StateTotal::product(&[]).to_string(), "1");
        assert_eq!(StateTotal::product(&[g(16), g(3)]).to_string(), "48");
        // 10000^5 = 10^20, past u64.
        let big = StateTotal::product(&[g(10_000); 5]);
        assert_eq!(big.to_string(), format!("1{}", "0".repeat(20)));
        assert_eq!(
            StateTotal::product(&[g(u64::MAX), g(u64::MAX)]).to_string(),
            (u128::MAX - 2 * u128::from(u64::MAX)).to_string()
        );
    }
}
