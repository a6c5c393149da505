//! The transitivity triples of a layer problem, stored packed ([`Thirds`]).
//!
//! Three pieces a < b < c with a common overlap give two "no cycle" constraints, which
//! the search checks when one of the triple's three pair variables is set, never builds.
//! So each pair keeps the third piece of every triple it takes part in. A large design has
//! hundreds of millions of such entries. A list per pair, grown as triples were found,
//! left a third of its memory unused, and the allocator keeps what a grown array leaves
//! behind (`allocator::keep_freed_memory`): the Japanese Spiny Lobster v2's 403 million
//! entries took 2.5 GB. Here every array is allocated once, to its size, and an entry
//! takes two bytes where the pieces are fewer than 65,537 (four beyond): 0.8 GB.

/// Entries at most in one chunk of a [`Packed`] that is allocated whole (a row's start
/// within its chunk is a `u32`).
const CHUNK: usize = 1 << 30;

/// Pieces that a two-byte entry numbers: below this many, [`Thirds`] keeps its entries
/// as `u16`s, half the memory of `u32`s (every design in Flat-Folder's community set has
/// at most a few thousand pieces).
const NARROW_PIECES: usize = 1 << 16;

/// Bytes one entry of a [`Thirds`] takes in a problem of `pieces` pieces (a triple has
/// three entries, one under each of its pairs).
pub(super) fn entry_bytes(pieces: usize) -> usize {
    if pieces <= NARROW_PIECES {
        2
    } else {
        4
    }
}

/// A piece number as a [`Thirds`] entry keeps it.
trait Entry: Copy + Default {
    fn new(piece: u32) -> Self;
}

impl Entry for u16 {
    fn new(piece: u32) -> u16 {
        debug_assert!(piece < NARROW_PIECES as u32);
        piece as u16
    }
}

impl Entry for u32 {
    fn new(piece: u32) -> u32 {
        piece
    }
}

/// Rows of entries packed one after another in chunks, each chunk allocated once to its
/// size; a row lies within one chunk.
#[derive(Default)]
struct Packed<E> {
    chunks: Vec<Vec<E>>,
    /// Per row, its chunk and where it starts there. It ends where the next row starts,
    /// or at its chunk's end.
    at: Vec<(u32, u32)>,
}

impl<E: Entry> Packed<E> {
    fn row(&self, i: usize) -> &[E] {
        let (k, start) = self.at[i];
        let chunk = &self.chunks[k as usize];
        let end = match self.at.get(i + 1) {
            Some(&(next_k, next)) if next_k == k => next as usize,
            _ => chunk.len(),
        };
        &chunk[start as usize..end]
    }

    /// Appends `rows`, `size` entries in all, as one chunk of that size.
    fn push_chunk(&mut self, size: usize, rows: impl Iterator<Item = impl Iterator<Item = u32>>) {
        let mut chunk = Vec::with_capacity(size);
        let k = self.chunks.len() as u32;
        for row in rows {
            self.at.push((k, chunk.len() as u32));
            chunk.extend(row.map(E::new));
        }
        debug_assert_eq!(chunk.len(), size, "a chunk is allocated to its size");
        self.chunks.push(chunk);
    }

    /// Rows of the lengths `lens`, zeroed, in chunks of at most [`CHUNK`] entries (or
    /// one row, where a row is longer).
    fn zeroed(lens: &[u32]) -> Packed<E> {
        let mut packed = Packed {
            chunks: Vec::new(),
            at: Vec::with_capacity(lens.len()),
        };
        let mut sizes = Vec::new();
        let mut size = 0usize;
        for &n in lens {
            if size > 0 && size + n as usize > CHUNK {
                sizes.push(std::mem::take(&mut size));
            }
            packed.at.push((sizes.len() as u32, size as u32));
            size += n as usize;
        }
        sizes.push(size);
        packed.chunks = sizes.into_iter().map(|n| vec![E::default(); n]).collect();
        packed
    }

    /// Writes `piece` where `cursor` (a chunk and a place in it, as [`Packed::at`]
    /// gives a row's start) points, and moves the cursor on.
    fn put(&mut self, cursor: &mut (u32, u32), piece: u32) {
        self.chunks[cursor.0 as usize][cursor.1 as usize] = E::new(piece);
        cursor.1 += 1;
    }
}

/// A [`Packed`] of two-byte entries where the pieces allow ([`entry_bytes`]), else of
/// four.
enum Rows {
    Narrow(Packed<u16>),
    Wide(Packed<u32>),
}

impl Rows {
    fn new(pieces: usize) -> Rows {
        match entry_bytes(pieces) {
            2 => Rows::Narrow(Packed::default()),
            _ => Rows::Wide(Packed::default()),
        }
    }

    fn row(&self, i: usize) -> Pieces<'_> {
        match self {
            Rows::Narrow(p) => Pieces::Narrow(p.row(i).iter()),
            Rows::Wide(p) => Pieces::Wide(p.row(i).iter()),
        }
    }

    fn push_chunk(&mut self, size: usize, rows: impl Iterator<Item = impl Iterator<Item = u32>>) {
        match self {
            Rows::Narrow(p) => p.push_chunk(size, rows),
            Rows::Wide(p) => p.push_chunk(size, rows),
        }
    }

    /// Zeroed rows of the lengths `lens`, as wide as the pieces need.
    fn zeroed(pieces: usize, lens: &[u32]) -> Rows {
        match entry_bytes(pieces) {
            2 => Rows::Narrow(Packed::zeroed(lens)),
            _ => Rows::Wide(Packed::zeroed(lens)),
        }
    }

    /// Per row, where it starts: a cursor for [`Rows::put`].
    fn starts(&self) -> Vec<(u32, u32)> {
        match self {
            Rows::Narrow(p) => p.at.clone(),
            Rows::Wide(p) => p.at.clone(),
        }
    }

    fn put(&mut self, cursor: &mut (u32, u32), piece: u32) {
        match self {
            Rows::Narrow(p) => p.put(cursor, piece),
            Rows::Wide(p) => p.put(cursor, piece),
        }
    }
}

/// The pieces of one row of a [`Thirds`], in order.
#[derive(Clone)]
pub(super) enum Pieces<'a> {
    Narrow(std::slice::Iter<'a, u16>),
    Wide(std::slice::Iter<'a, u32>),
}

impl Iterator for Pieces<'_> {
    type Item = usize;

    fn next(&mut self) -> Option<usize> {
        match self {
            Pieces::Narrow(i) => i.next().map(|&c| c as usize),
            Pieces::Wide(i) => i.next().map(|&c| c as usize),
        }
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = match self {
            Pieces::Narrow(i) => i.len(),
            Pieces::Wide(i) => i.len(),
        };
        (n, Some(n))
    }
}

impl ExactSizeIterator for Pieces<'_> {}

/// For each pair variable (a, b), the third pieces of the triples it takes part in, in
/// two parts: `upper`, the pieces c > b of the triples found from the pair itself (its
/// two pieces the triple's lowest), and `lower`, the third piece of the triples found
/// from a lower pair (a, b′) or (a′, a), where this pair is the triple's (a, c) or
/// (b, c). A pair's lower part lists what earlier pairs found, in their order, so the two
/// parts read lower then upper are the order in which the triples were found.
pub(super) struct Thirds {
    upper: Rows,
    lower: Rows,
}

impl Default for Thirds {
    fn default() -> Thirds {
        Thirds {
            upper: Rows::new(0),
            lower: Rows::new(0),
        }
    }
}

impl Thirds {
    /// The third pieces of every triple through pair `ab`.
    pub(super) fn of(&self, ab: usize) -> impl Iterator<Item = usize> + '_ {
        self.lower.row(ab).chain(self.upper.row(ab))
    }

    /// How many triples pass through pair `ab`.
    pub(super) fn len(&self, ab: usize) -> usize {
        self.lower.row(ab).len() + self.upper.row(ab).len()
    }

    /// The pieces c > b of the triples found from pair `ab` = (a, b): each triple once.
    pub(super) fn upper(&self, ab: usize) -> Pieces<'_> {
        self.upper.row(ab)
    }

    /// Completes the triples with their lower part, once every triple is filed in it.
    pub(super) fn set_lower(&mut self, fill: LowerFill) {
        debug_assert!({
            let starts = fill.rows.starts();
            (0..fill.next.len())
                .all(|v| (fill.next[v].1 - starts[v].1) as usize == fill.rows.row(v).len())
        });
        self.lower = fill.rows;
    }
}

/// Collects the triples as they are found, a block of pairs at a time in pair order,
/// each block's upper rows one chunk; then [`ThirdsBuilder::finish_upper`] sizes the
/// lower part, filled from each triple once.
pub(super) struct ThirdsBuilder {
    pieces: usize,
    upper: Rows,
    /// Per pair, how many triples found so far will list it in their lower part.
    lower_count: Vec<u32>,
    triples: usize,
}

impl ThirdsBuilder {
    /// A builder for the triples of `pairs` pair variables over `pieces` pieces.
    pub(super) fn new(pairs: usize, pieces: usize) -> ThirdsBuilder {
        ThirdsBuilder {
            pieces,
            upper: Rows::new(pieces),
            lower_count: vec![0; pairs],
            triples: 0,
        }
    }

    /// Files the triples of the next block of pairs: per pair, each triple as its third
    /// piece c and the variables of (a, c) and (b, c).
    pub(super) fn add_block(&mut self, found: &[Vec<[u32; 3]>]) {
        for &[_, ac, bc] in found.iter().flatten() {
            self.lower_count[ac as usize] += 1;
            self.lower_count[bc as usize] += 1;
        }
        let size = found.iter().map(Vec::len).sum();
        self.upper
            .push_chunk(size, found.iter().map(|list| list.iter().map(|t| t[0])));
        self.triples += size;
    }

    /// How many triples have been added.
    pub(super) fn triples(&self) -> usize {
        self.triples
    }

    /// The upper part, as [`Thirds`] without its lower part yet, and the lower part to
    /// fill ([`LowerFill`]) from each triple of it.
    pub(super) fn finish_upper(self) -> (Thirds, LowerFill) {
        let thirds = Thirds {
            upper: self.upper,
            lower: Rows::new(self.pieces),
        };
        (thirds, LowerFill::new(self.pieces, self.lower_count))
    }
}

/// The lower part of a [`Thirds`], allocated to its size and filled a triple at a time,
/// in the order the upper part lists them ([`Thirds::set_lower`]).
pub(super) struct LowerFill {
    rows: Rows,
    /// Per pair, where its row's next entry goes. One cursor, not a row start and a
    /// count beside it: filing reaches the pairs in no order, and each array it reads
    /// there is a cache miss (filing took 7.5 % of Ryujin 2.1's samples with the two,
    /// 5.3 % with the cursor).
    next: Vec<(u32, u32)>,
}

impl LowerFill {
    fn new(pieces: usize, count: Vec<u32>) -> LowerFill {
        let rows = Rows::zeroed(pieces, &count);
        let next = rows.starts();
        LowerFill { rows, next }
    }

    /// Files the triple whose pair variables are `[ab, bc, ac]` (a < b < c; `pairs`
    /// gives ab's pieces): pair (a, c) lists b, and (b, c) lists a.
    pub(super) fn add(&mut self, pairs: &[(usize, usize)], [ab, bc, ac]: [usize; 3]) {
        let (a, b) = pairs[ab];
        for (var, third) in [(ac, b), (bc, a)] {
            self.rows.put(&mut self.next[var], third as u32);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pieces 0..4 all overlapping: pairs in order (0,1) (0,2) (0,3) (1,2) (1,3) (2,3),
    /// and every triple of pieces. Each pair must list the third piece of exactly the
    /// triples it is in, lower parts first in the order their triples were found.
    #[test]
    fn every_pair_lists_the_third_piece_of_each_of_its_triples_in_the_order_found() {
        // Numbered in two bytes, and in four as a problem of more pieces would be.
        for pieces in [4, NARROW_PIECES + 1] {
            assert_eq!(entry_bytes(pieces), if pieces == 4 { 2 } else { 4 });
            lists_every_triple_in_the_order_found(pieces);
        }
    }

    fn lists_every_triple_in_the_order_found(pieces: usize) {
        let pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
        let var = |p: usize, q: usize| pairs.iter().position(|&x| x == (p, q)).unwrap();
        let mut builder = ThirdsBuilder::new(pairs.len(), pieces);
        let found: Vec<Vec<[u32; 3]>> = pairs
            .iter()
            .map(|&(a, b)| {
                (b + 1..4)
                    .map(|c| [c as u32, var(a, c) as u32, var(b, c) as u32])
                    .collect()
            })
            .collect();
        // Two blocks, so that rows are read across a chunk's end.
        builder.add_block(&found[..3]);
        builder.add_block(&found[3..]);
        assert_eq!(builder.triples(), 4);
        let (mut thirds, mut lower) = builder.finish_upper();
        for (ab, &(a, b)) in pairs.iter().enumerate() {
            for c in thirds.upper(ab) {
                lower.add(&pairs, [ab, var(b, c), var(a, c)]);
            }
        }
        thirds.set_lower(lower);
        // Brute force: the thirds of (p, q) are the other pieces, each once, those below
        // q (from lower pairs, found in pair order) before those above.
        for (ab, &(p, q)) in pairs.iter().enumerate() {
            let listed: Vec<u32> = thirds.of(ab).map(|c| c as u32).collect();
            let mut below: Vec<(usize, u32)> = (0..4)
                .filter(|&r| r != p && r != q && r < q)
                .map(|r| {
                    let lowest = if r < p { (r, p) } else { (p, r) };
                    (var(lowest.0, lowest.1), r as u32)
                })
                .collect();
            below.sort_unstable();
            let expected: Vec<u32> = below
                .into_iter()
                .map(|(_, r)| r)
                .chain((q as u32 + 1)..4)
                .collect();
            assert_eq!(listed, expected, "pair {:?}", (p, q));
            assert_eq!(thirds.len(ab), 2);
        }
        assert_eq!(
            (0..pairs.len())
                .map(|ab| thirds.upper(ab).len())
                .sum::<usize>(),
            4
        );
    }
}
