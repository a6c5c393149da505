//! Disjoint sets of indices (union–find with path halving), for grouping faces or
//! variables joined by some relation.

/// Sets over `0..n`; each set is named by its smallest member, so the result does not
/// depend on the order of the unions.
#[derive(Clone, Debug)]
pub struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    /// Every index in a set of its own.
    pub fn new(n: usize) -> UnionFind {
        UnionFind {
            parent: (0..n).collect(),
        }
    }

    /// The smallest member of `i`'s set.
    pub fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    /// Joins the sets of `a` and `b`.
    pub fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent[ra.max(rb)] = ra.min(rb);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_are_named_by_their_smallest_member_whatever_the_union_order() {
        let mut u = UnionFind::new(6);
        u.union(5, 3);
        u.union(3, 4);
        u.union(1, 0);
        assert_eq!([0, 1, 2, 3, 4, 5].map(|i| u.find(i)), [0, 0, 2, 3, 3, 3]);
        u.union(4, 1);
        assert!((0..6).filter(|&i| i != 2).all(|i| u.find(i) == 0));
        assert_eq!(u.find(2), 2);
    }
}
