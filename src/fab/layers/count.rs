//! Counting the flat-folded states: every assignment of the pair variables that keeps
//! every constraint is one layer order. After the creases' fixed values are propagated,
//! the variables still open fall into groups that share no constraint; the states are the
//! product of each group's count, and each group is enumerated depth first (up to a
//! cap, as Flat-Folder's 10,000 a component).

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
        let mut watching: Vec<Vec<usize>> = vec![Vec::new(); self.pairs.len()];
        for (k, c) in self.constraints.iter().enumerate() {
            for v in c.vars() {
                watching[v].push(k);
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
        self.for_each_triple(None, |vars| join(&vars));
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
