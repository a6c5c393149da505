//! Looking up the variable of a pair of overlapping pieces, the layer search's most
//! frequent question: [`PairIndex`], and one piece's row spread out for loops that ask
//! about many pairs of it ([`SpreadRow`]).

use super::{Lit, Problem};

/// The variable of each overlapping pair of pieces, looked up for every triple the
/// search visits. Every piece keeps its overlapping pieces sorted, with the pair's
/// variable. When the pieces are few, a table of every pair answers a lookup in one load;
/// otherwise a lookup searches the row of its first piece, and loops that look up many
/// pairs of one piece spread its row out first ([`SpreadRow`]): a table of every pair of
/// a large design would take hundreds of MB, and a hashed map cost a third of the search
/// when it was used.
pub(super) struct PairIndex {
    /// Where each piece's row starts in `entries` (one more than the pieces).
    start: Vec<u32>,
    /// Per row, (other piece, variable), sorted by the other piece.
    entries: Vec<(u32, u32)>,
    /// With few pieces: `table[a * pieces + b]`, the variable of (a, b) or `u32::MAX`.
    table: Option<Vec<u32>>,
}

impl PairIndex {
    /// The index of `pairs` (lower piece first, each once) among `pieces` pieces.
    pub(super) fn new(pieces: usize, pairs: &[(usize, usize)]) -> PairIndex {
        let mut start = vec![0u32; pieces + 1];
        for &(a, b) in pairs {
            start[a + 1] += 1;
            start[b + 1] += 1;
        }
        for p in 0..pieces {
            start[p + 1] += start[p];
        }
        let mut fill = start.clone();
        let mut entries = vec![(0u32, 0u32); 2 * pairs.len()];
        for (var, &(a, b)) in pairs.iter().enumerate() {
            for (row, other) in [(a, b), (b, a)] {
                entries[fill[row] as usize] = (other as u32, var as u32);
                fill[row] += 1;
            }
        }
        for p in 0..pieces {
            entries[start[p] as usize..start[p + 1] as usize].sort_unstable();
        }
        let table = (pieces.saturating_mul(pieces) <= Self::TABLE_CELLS).then(|| {
            let mut table = vec![u32::MAX; pieces * pieces];
            for (var, &(a, b)) in pairs.iter().enumerate() {
                table[a * pieces + b] = var as u32;
                table[b * pieces + a] = var as u32;
            }
            table
        });
        PairIndex {
            start,
            entries,
            table,
        }
    }

    /// Pairs of pieces up to which the table is kept (16 MB).
    const TABLE_CELLS: usize = 1 << 22;

    /// The pieces `a` overlaps, with each pair's variable, sorted by piece.
    pub(super) fn row(&self, a: usize) -> &[(u32, u32)] {
        &self.entries[self.start[a] as usize..self.start[a + 1] as usize]
    }

    /// The variable of pieces `a` and `b` (either order), if they overlap; searched in
    /// `a`'s row, so pass first the piece a loop holds fixed.
    pub(super) fn get(&self, a: usize, b: usize) -> Option<usize> {
        if let Some(table) = &self.table {
            let pieces = self.start.len() - 1;
            return match table[a * pieces + b] {
                u32::MAX => None,
                var => Some(var as usize),
            };
        }
        let row = self.row(a);
        row.binary_search_by_key(&(b as u32), |&(other, _)| other)
            .ok()
            .map(|k| row[k].1 as usize)
    }
}

/// One piece's row of a [`PairIndex`] spread over an array indexed by piece, for a loop
/// that looks up many pairs of that piece (the triples of one pair, at every value the
/// search sets): one load each instead of a binary search. Loading a row costs its
/// length (and clearing the one before), so it is kept until another piece's is needed.
pub(super) struct SpreadRow {
    /// Per piece c, the variable of (piece, c) plus one; 0 where they do not overlap.
    slot: Vec<u32>,
    piece: Option<usize>,
}

impl SpreadRow {
    pub(super) fn new(pieces: usize) -> SpreadRow {
        SpreadRow {
            slot: vec![0; pieces],
            piece: None,
        }
    }

    /// Holds `piece`'s row (of `problem`'s index) from now on; nothing to hold where the
    /// index has its table, which answers every lookup in one load already.
    pub(super) fn load(&mut self, problem: &Problem, piece: usize) {
        if self.piece == Some(piece) || problem.index.table.is_some() {
            return;
        }
        if let Some(old) = self.piece {
            for &(c, _) in problem.index.row(old) {
                self.slot[c as usize] = 0;
            }
        }
        for &(c, var) in problem.index.row(piece) {
            self.slot[c as usize] = var + 1;
        }
        self.piece = Some(piece);
    }

    /// The literal "`piece` lies above piece c", as [`Problem::above`] gives it: from the
    /// spread row when it holds `piece`'s, else looked up in the index.
    pub(super) fn above(&self, problem: &Problem, piece: usize, c: usize) -> Option<Lit> {
        if self.piece != Some(piece) {
            return problem.above(piece, c);
        }
        match self.slot[c] {
            0 => None,
            v => Some(Lit::new(v as usize - 1, piece < c)),
        }
    }
}
