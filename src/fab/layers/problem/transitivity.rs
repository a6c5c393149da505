//! Transitivity: finding the triples of pieces that share an area once folded, and
//! walking them by their pair variables. [`super::Thirds`] stores them; the search
//! checks their "no cycle" constraints.

use super::super::geometry::{ClipScratch, FoldedTriangle, PairOverlap};
use super::super::pair_index::SpreadRow;
use super::super::thirds::{entry_bytes, ThirdsBuilder};
use super::Problem;
use crate::fab::budget::{layer_bytes, Budget, OverBudget};
use crate::mesh::Vec2;

/// Candidate triples examined per block of [`Problem::add_transitivity`]: bounds what a
/// block's findings hold in memory before they are filed (12 bytes each).
const TRIPLE_BLOCK: usize = 1 << 20;

/// What a thread examining pairs for their triples keeps from one pair to the next.
struct TripleScratch {
    clip: ClipScratch,
    /// The row of the pair's first piece, spread out.
    first: SpreadRow,
}

impl Problem {
    /// Transitivity: three pieces with a common overlap are not stacked in a cycle.
    /// Each triple a < b < c is found once, from the pair (a, b) and a piece c that
    /// overlaps both, and kept in [`Problem::thirds`]. Pairs are examined on every core a
    /// block at a time (each pair's triples are its own to find) and filed in pair order,
    /// so the lists, and the search that reads them, are the same on any number of cores.
    pub(super) fn add_transitivity(
        &mut self,
        tri: &[[Vec2; 3]],
        budget: &Budget,
    ) -> Result<(), OverBudget> {
        use rayon::prelude::*;
        // Per variable, its pairs of overlapping faces (lower piece's face first). Indexed,
        // not hashed: the loop below runs once per candidate triple.
        let mut touching: Vec<Vec<(usize, usize)>> = vec![Vec::new(); self.pairs.len()];
        for &(f, g, _) in &self.face_pairs {
            let (p, q) = (self.piece_of[f], self.piece_of[g]);
            let var = self
                .index
                .get(p, q)
                .expect("a pair of overlapping faces is a variable");
            touching[var].push(if p < q { (f, g) } else { (g, f) });
        }
        let faces: Vec<FoldedTriangle> = tri.iter().map(FoldedTriangle::new).collect();
        let mut found_so_far = ThirdsBuilder::new(self.pairs.len(), self.members.len());
        let mut block = 0;
        while block < self.pairs.len() {
            budget.check()?;
            // A block holds at most TRIPLE_BLOCK candidates (a pair's are at most the
            // shorter of its pieces' rows): what it finds waits in memory to be filed.
            let (mut end, mut candidates) = (block, 0usize);
            while end < self.pairs.len() && (end == block || candidates < TRIPLE_BLOCK) {
                let (a, b) = self.pairs[end];
                candidates += self.index.row(a).len().min(self.index.row(b).len());
                end += 1;
            }
            let found: Vec<Vec<[u32; 3]>> = (block..end)
                .into_par_iter()
                .map_init(
                    || TripleScratch {
                        clip: ClipScratch::default(),
                        first: SpreadRow::new(self.members.len()),
                    },
                    |scratch, ab| self.triples_of(ab, &faces, &touching, scratch),
                )
                .collect();
            found_so_far.add_block(&found);
            // Triples count against the cap by their memory; their time (a clipping
            // to find, a check at every decision) is the deadline's to bound.
            budget.check_size(layer_bytes(
                self.pairs.len(),
                self.constraints.len(),
                found_so_far.triples(),
                entry_bytes(self.members.len()),
            ))?;
            block = end;
        }
        // Each triple is filed under its other two pairs once all are found, so their
        // lists are allocated once, to their size.
        let (upper, mut lower) = found_so_far.finish_upper();
        self.thirds = upper;
        self.for_each_triple(None, |vars| lower.add(&self.pairs, vars));
        self.thirds.set_lower(lower);
        Ok(())
    }

    /// The triples of pair `ab` = (a, b) with a third piece c > b: each as c and the
    /// variables of (a, c) and (b, c). The three share an area when some face of c
    /// overlaps the region a face of a shares with a face of b.
    fn triples_of(
        &self,
        ab: usize,
        faces: &[FoldedTriangle],
        touching: &[Vec<(usize, usize)>],
        scratch: &mut TripleScratch,
    ) -> Vec<[u32; 3]> {
        let (a, b) = self.pairs[ab];
        let lb = self.index.row(b);
        // What a and b share, clipped once here and by each candidate c below.
        let shared: Vec<(usize, PairOverlap)> = touching[ab]
            .iter()
            .map(|&(fa, fb)| (fa, PairOverlap::new(&faces[fa], &faces[fb])))
            .collect();
        let mut found = Vec::new();
        // Pairs come in order of their first piece, so a's row stays spread out while a
        // thread takes a's pairs, and each c of b's row is looked up in it in one load
        // (a walk along both rows branched at every step).
        scratch.first.load(self, a);
        // Only pieces c > b: each triple once, from its two lowest pieces.
        let past_b = lb.partition_point(|x| x.0 as usize <= b);
        for &(c, bc) in &lb[past_b..] {
            let Some(ac) = scratch.first.above(self, a, c as usize) else {
                continue;
            };
            let ac = ac.var();
            let shares = shared.iter().any(|(fa, region)| {
                touching[ac].iter().any(|&(fa2, fc)| {
                    fa2 == *fa && region.shares_with(&faces[fc], self.eps, &mut scratch.clip)
                })
            });
            if shares {
                found.push([c, ac as u32, bc]);
            }
        }
        found
    }

    /// Calls `f` with the variables of (a, b), (b, c) and (a, c), for each triple of
    /// pieces a < b < c (all three in `only`, when given): once a triple, from its pair
    /// (a, b), in pair order.
    pub(in crate::fab::layers) fn for_each_triple(
        &self,
        only: Option<&[bool]>,
        mut f: impl FnMut([usize; 3]),
    ) {
        let kept = |p: usize| only.is_none_or(|keep| keep[p]);
        let mut rows = [0, 1].map(|_| SpreadRow::new(self.members.len()));
        let overlap = "a triple's pairs overlap";
        for (ab, &(a, b)) in self.pairs.iter().enumerate() {
            let upper = self.thirds.upper(ab);
            if upper.len() == 0 || !(kept(a) && kept(b)) {
                continue;
            }
            // Pairs are sorted by their first piece, so a's row is loaded once per piece.
            rows[0].load(self, a);
            if self.worth_spreading(ab, upper.len()) {
                rows[1].load(self, b);
            }
            for c in upper.filter(|&c| kept(c)) {
                let bc = rows[1].above(self, b, c).expect(overlap).var();
                let ac = rows[0].above(self, a, c).expect(overlap).var();
                f([ab, bc, ac]);
            }
        }
    }

    /// Whether `triples` of pair `ab` are looked up faster in its pieces' spread rows
    /// than by a binary search each (where the index has its table, loading a row does
    /// nothing: [`SpreadRow::load`]). Loading a row costs its length, but a row stays
    /// loaded while its piece keeps coming back, so the rows pay from a sixteenth of
    /// their length in triples (measured on Ryujin 2.1: 4 was slower by a second, 16
    /// and 64 alike).
    pub(in crate::fab::layers) fn worth_spreading(&self, ab: usize, triples: usize) -> bool {
        let (a, b) = self.pairs[ab];
        let rows = self.index.row(a).len() + self.index.row(b).len();
        16 * triples >= rows
    }
}
