//! The layer problem ([`Problem`]): the pieces (faces joined across lines that stay
//! flat), one variable per overlapping pair of pieces, and the constraints between them
//! — taco–tortilla, taco–taco and transitivity — built from the flat-folded state.

mod transitivity;

use super::geometry::{collinear_overlap, crosses, overlap_depth};
use super::pair_index::PairIndex;
use super::search::Search;
use super::thirds::Thirds;
use super::{contact_allowance, folds_completely, LayerConflict, LayerError};
use crate::fab::budget::{layer_bytes, Budget, OverBudget};
use crate::fab::flat_fold::FlatFolded;
use crate::mesh::bounds;
use crate::mesh::{Assignment, Mesh, UnionFind, Vec2};
use std::collections::HashMap;

/// The layer problem. Faces joined across a line that stays flat (F, or U with a zero
/// target) lie side by side in one plane once folded: they are one rigid *piece*, as
/// Flat-Folder and Rabbit Ear treat them, so a face lying over one of them lies over the
/// other the same way. The variables are pairs of overlapping pieces:
/// `above[(i, j)]` with i < j is true when piece i lies higher (toward +z of the folded
/// state) than piece j.
pub(super) struct Problem {
    /// The piece each face (triangle) belongs to.
    piece_of: Vec<usize>,
    /// The faces of each piece.
    pub(super) members: Vec<Vec<usize>>,
    /// Overlapping pairs of faces in different pieces, with their overlap depth (mm).
    face_pairs: Vec<(usize, usize, f64)>,
    pub(super) pairs: Vec<(usize, usize)>,
    pub(super) index: PairIndex,
    /// Values the creases force: (variable, value).
    pub(super) fixed: Vec<(usize, bool)>,
    pub(super) constraints: Vec<Constraint>,
    /// Transitivity, stored compactly: for each pair variable (a, b), the pieces c with
    /// which a and b share a region. The two "no cycle" constraints of each triple are
    /// checked when one of its variables is set, never built (a deep stack of n pieces has
    /// n³/6 triples: twelve bytes each here, not two boxed constraints).
    pub(super) thirds: Thirds,
    /// Whether each face's front (its normal) faces +z once folded.
    front_up: Vec<bool>,
    /// A folded crease with one piece on both sides (it would have to fold onto itself).
    pub(super) self_hinged: Option<usize>,
    /// Overlaps thinner than this (mm) are contact.
    eps: f64,
}

/// A literal: variable `var` equals `value`. The variable is kept in 32 bits: a large
/// design's constraints and learnt clauses hold millions of literals.
#[derive(Clone, Copy, Debug)]
pub(super) struct Lit {
    var: u32,
    pub(super) value: bool,
}

impl Lit {
    /// The statement "variable `var` is `value`".
    pub(super) fn new(var: usize, value: bool) -> Lit {
        debug_assert!(var <= u32::MAX as usize, "variables are counted in 32 bits");
        Lit {
            var: var as u32,
            value,
        }
    }

    /// The variable.
    pub(super) fn var(self) -> usize {
        self.var as usize
    }

    /// The opposite statement ("b above a" for "a above b").
    pub(super) fn negated(self) -> Lit {
        Lit {
            value: !self.value,
            ..self
        }
    }
}

#[derive(Clone, Debug)]
pub(super) enum Constraint {
    /// x == y (both literals true or both false).
    Same(Lit, Lit),
    /// x ⊕ y ⊕ z ⊕ w == false.
    Parity([Lit; 4]),
}

impl Constraint {
    pub(super) fn vars(&self) -> Vec<usize> {
        match self {
            Constraint::Same(a, b) => vec![a.var(), b.var()],
            Constraint::Parity(l) => l.iter().map(|x| x.var()).collect(),
        }
    }
}

/// A folded crease: the pieces on either side and its folded line.
struct Hinge {
    pieces: (usize, usize),
    line: (Vec2, Vec2),
}

impl Problem {
    /// The literal "piece a lies above piece b" (a ≠ b, the pair overlapping), looked up
    /// in a's row of the index.
    pub(super) fn above(&self, a: usize, b: usize) -> Option<Lit> {
        self.index.get(a, b).map(|var| Lit::new(var, a < b))
    }

    pub(super) fn build(
        mesh: &Mesh,
        folded: &FlatFolded,
        budget: &Budget,
    ) -> Result<Problem, OverBudget> {
        let tri = &folded.triangles;
        let eps = contact_allowance(mesh, folded);
        let (piece_of, members) = pieces(mesh);
        let face_pairs: Vec<(usize, usize, f64)> = overlapping_pairs(tri, eps, budget)?
            .into_iter()
            .filter(|&(a, b, _)| piece_of[a] != piece_of[b])
            .collect();
        let mut pairs: Vec<(usize, usize)> = face_pairs
            .iter()
            .map(|&(a, b, _)| {
                let (p, q) = (piece_of[a], piece_of[b]);
                (p.min(q), p.max(q))
            })
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        let index = PairIndex::new(members.len(), &pairs);
        let front_up = folded.front_up.clone();
        let mut problem = Problem {
            piece_of,
            members,
            face_pairs,
            pairs,
            index,
            fixed: Vec::new(),
            constraints: Vec::new(),
            thirds: Thirds::default(),
            front_up,
            self_hinged: None,
            eps,
        };
        let hinges = problem.add_hinges(mesh, folded, budget)?;
        problem.add_taco_taco(&hinges, budget)?;
        problem.add_transitivity(tri, budget)?;
        Ok(problem)
    }

    /// Adds a constraint, failing when the problem outgrows the budget (checked with the
    /// deadline every few thousand constraints, where the loops that make them spend
    /// their time).
    fn push(&mut self, c: Constraint, budget: &Budget) -> Result<(), OverBudget> {
        self.constraints.push(c);
        if self.constraints.len().is_multiple_of(4096) {
            budget.check_size(layer_bytes(self.pairs.len(), self.constraints.len(), 0, 0))?;
            budget.check()?;
        }
        Ok(())
    }

    /// Every folded crease is a hinge between two pieces: its mountain/valley fixes which
    /// lies above (valley brings the second face onto the first's front, mountain behind
    /// it), and a piece crossing the hinge's folded line lies above both or below both
    /// (taco–tortilla). Returns the hinges.
    fn add_hinges(
        &mut self,
        mesh: &Mesh,
        folded: &FlatFolded,
        budget: &Budget,
    ) -> Result<Vec<Hinge>, OverBudget> {
        let topo = mesh.topology();
        // Each piece's inner lines (its flat joins), where a hinge's line can run through
        // the piece without crossing any one of its faces.
        let mut inner: Vec<Vec<(Vec2, Vec2)>> = vec![Vec::new(); self.members.len()];
        let mut hinges = Vec::new();
        for (e, edge) in mesh.edges().iter().enumerate() {
            let [Some(a), Some(b)] = topo.edge_faces[e] else {
                continue;
            };
            let line = edge_image(mesh, folded, a, e);
            if folds_completely(edge) {
                let (pa, pb) = (self.piece_of[a], self.piece_of[b]);
                if pa == pb {
                    self.self_hinged = Some(e);
                    continue;
                }
                // An unassigned crease's side is the search's to find.
                let b_above = (edge.assignment == Assignment::Valley) == self.front_up[a];
                if let Some(l) = self
                    .above(pb, pa)
                    .filter(|_| edge.assignment != Assignment::Unassigned)
                {
                    self.fixed.push((l.var(), l.value == b_above));
                }
                hinges.push(Hinge {
                    pieces: (pa, pb),
                    line,
                });
            } else {
                inner[self.piece_of[a]].push(line);
            }
        }
        let mut seen = std::collections::HashSet::new();
        for h in &hinges {
            budget.check()?;
            let (pa, pb) = h.pieces;
            let (p, q) = h.line;
            let others: Vec<usize> = self
                .index
                .row(pa)
                .iter()
                .map(|&(c, _)| c as usize)
                .collect();
            for c in others.into_iter().filter(|&c| c != pb) {
                let crosses_piece = self.members[c]
                    .iter()
                    .any(|&t| crosses(p, q, &folded.triangles[t], self.eps))
                    || inner[c]
                        .iter()
                        .any(|&(r, s)| collinear_overlap(p, q, r, s, self.eps));
                if !crosses_piece || !seen.insert((pa.min(pb), pa.max(pb), c)) {
                    continue;
                }
                if let (Some(x), Some(y)) = (self.above(pa, c), self.above(pb, c)) {
                    self.push(Constraint::Same(x, y), budget)?;
                }
            }
        }
        Ok(hinges)
    }

    /// Taco–taco: creases folded onto the same line with their flaps on the same side
    /// nest or stay apart, never interleave.
    fn add_taco_taco(&mut self, hinges: &[Hinge], budget: &Budget) -> Result<(), OverBudget> {
        for (i, h) in hinges.iter().enumerate() {
            budget.check()?;
            let ((a, b), (p, q)) = (h.pieces, h.line);
            for k in &hinges[i + 1..] {
                let ((c, d), (r, s)) = (k.pieces, k.line);
                // Two hinges sharing a piece are one crease split by a vertex (or a
                // piece's two edges, which cannot lie on one line).
                if a == c || a == d || b == c || b == d {
                    continue;
                }
                if !collinear_overlap(p, q, r, s, self.eps) {
                    continue;
                }
                let lits = [
                    self.above(a, c),
                    self.above(b, c),
                    self.above(a, d),
                    self.above(b, d),
                ];
                if let [Some(w), Some(x), Some(y), Some(z)] = lits {
                    self.push(Constraint::Parity([w, x, y, z]), budget)?;
                }
            }
        }
        Ok(())
    }

    /// Values for every variable, or the pieces of a group of variables with none. With
    /// `only`, pieces outside that set are ignored (their variables left free).
    pub(super) fn solve(
        &self,
        only: Option<&[bool]>,
        budget: &Budget,
    ) -> Result<Result<Vec<bool>, Vec<usize>>, LayerError> {
        let active = |var: usize| {
            only.is_none_or(|keep| {
                let (a, b) = self.pairs[var];
                keep[a] && keep[b]
            })
        };
        let mut watching: Vec<Vec<u32>> = vec![Vec::new(); self.pairs.len()];
        let mut group = UnionFind::new(self.pairs.len());
        for (k, c) in self.constraints.iter().enumerate() {
            let vars = c.vars();
            if vars.iter().all(|&v| active(v)) {
                for &v in &vars {
                    watching[v].push(k as u32);
                    group.union(vars[0], v);
                }
            }
        }
        self.for_each_triple(only, |[ab, bc, ac]| {
            group.union(ab, bc);
            group.union(ab, ac);
        });
        let mut search = Search::new(self, only, watching, budget);
        let pieces_of = |vars: &[usize]| {
            let mut f: Vec<usize> = vars
                .iter()
                .flat_map(|&v| [self.pairs[v].0, self.pairs[v].1])
                .collect();
            f.sort_unstable();
            f.dedup();
            f
        };
        let mut members: HashMap<usize, Vec<usize>> = HashMap::new();
        for v in (0..self.pairs.len()).filter(|&v| active(v)) {
            members.entry(group.find(v)).or_default().push(v);
        }
        let mut groups: Vec<Vec<usize>> = members.into_values().collect();
        groups.sort_unstable();
        for &(var, v) in &self.fixed {
            if active(var) && !search.assign(var, v) {
                let r = group.find(var);
                let g = groups.iter().find(|g| group.find(g[0]) == r).unwrap();
                return Ok(Err(pieces_of(g)));
            }
        }
        // Groups share no constraint: each is decided on its own, and a group without
        // an order makes the whole pattern fail without searching the others again.
        for g in &groups {
            if !search.run(g)? {
                return Ok(Err(pieces_of(g)));
            }
        }
        Ok(Ok(search.value.iter().map(|v| v.unwrap_or(true)).collect()))
    }

    /// Shrinks a group of pieces without an order to a smallest one: drop pieces while
    /// the rest still has none — halves of the candidates first, then quarters, down to
    /// single pieces, so a small conflict inside a large group costs a few solves per
    /// piece it keeps, not one per piece it drops; an unsolvable rest is narrowed at once
    /// to its own unsolvable group. The conflict is already proved: shrinking only names
    /// fewer faces, so it stops after `work` units of search (or at the budget's end)
    /// with the set it has, never turning the verdict undecided.
    pub(super) fn smallest_conflict(
        &self,
        pieces: Vec<usize>,
        budget: &Budget,
        work: u64,
    ) -> Vec<usize> {
        let shrink = budget.with_work(work);
        let mut keep = vec![false; self.members.len()];
        for &p in &pieces {
            keep[p] = true;
        }
        let mut candidates = pieces;
        let mut chunk = candidates.len().div_ceil(2).max(1);
        loop {
            let mut i = 0;
            while i < candidates.len() {
                let end = (i + chunk).min(candidates.len());
                for &p in &candidates[i..end] {
                    keep[p] = false;
                }
                // Each solve sets up its watch lists over every constraint.
                let solved = shrink
                    .spend((self.constraints.len() + self.pairs.len()) as u64)
                    .map_err(LayerError::from)
                    .and_then(|()| self.solve(Some(&keep), &shrink));
                match solved {
                    Ok(Err(group)) => {
                        // Still no order: the dropped pieces go, and so does whatever
                        // lies outside the group that has none.
                        let next = candidates.get(end).copied().unwrap_or(usize::MAX);
                        keep.iter_mut().for_each(|k| *k = false);
                        for &p in &group {
                            keep[p] = true;
                        }
                        candidates.retain(|&p| keep[p]);
                        i = candidates.partition_point(|&p| p < next);
                    }
                    Ok(Ok(_)) => {
                        for &p in &candidates[i..end] {
                            keep[p] = true;
                        }
                        i = end;
                    }
                    Err(_) => {
                        for &p in &candidates[i..end] {
                            keep[p] = true;
                        }
                        return candidates;
                    }
                }
            }
            if chunk == 1 {
                return candidates;
            }
            chunk = chunk.div_ceil(2);
        }
    }

    /// The conflict among `pieces`, as their faces with the overlaps among them.
    pub(super) fn conflict(&self, pieces: &[usize]) -> LayerConflict {
        let mut faces: Vec<usize> = pieces
            .iter()
            .flat_map(|&p| self.members[p].iter().copied())
            .collect();
        faces.sort_unstable();
        let chosen = |f: usize| pieces.contains(&self.piece_of[f]);
        let depths: Vec<f64> = self
            .face_pairs
            .iter()
            .filter(|&&(a, b, _)| chosen(a) && chosen(b))
            .map(|&(_, _, d)| d)
            .collect();
        LayerConflict {
            faces,
            thinnest: depths
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min)
                .min(f64::MAX),
            thickest: depths.iter().copied().fold(0.0, f64::max),
            contact: self.eps,
            vertex: None,
        }
    }

    /// The side each unassigned hinge folds to in the order `values`: a valley brings the
    /// second face onto the first's front ([`Problem::add_hinges`]'s rule, read back).
    pub(super) fn hinge_assignments(
        &self,
        mesh: &Mesh,
        values: &[bool],
    ) -> Vec<(usize, Assignment)> {
        let topo = mesh.topology();
        mesh.edges()
            .iter()
            .enumerate()
            .filter(|(_, edge)| edge.assignment == Assignment::Unassigned && folds_completely(edge))
            .filter_map(|(e, _)| {
                let [Some(a), Some(b)] = topo.edge_faces[e] else {
                    return None;
                };
                let lit = self.above(self.piece_of[b], self.piece_of[a])?;
                let b_above = values[lit.var()] == lit.value;
                Some((
                    e,
                    if b_above == self.front_up[a] {
                        Assignment::Valley
                    } else {
                        Assignment::Mountain
                    },
                ))
            })
            .collect()
    }

    /// FOLD `faceOrders` from the values, one per overlapping pair of faces in different
    /// pieces. The FOLD specification measures "above" along g's normal (as Rabbit Ear
    /// and Flat-Folder read it), so s = +1 when f lies on the side g's front faces.
    pub(super) fn face_orders(&self, values: &[bool]) -> Vec<[i64; 3]> {
        self.face_pairs
            .iter()
            .map(|&(f, g, _)| {
                let lit = self
                    .above(self.piece_of[f], self.piece_of[g])
                    .expect("overlapping faces make overlapping pieces");
                let f_higher = values[lit.var()] == lit.value;
                let s = if f_higher == self.front_up[g] { 1 } else { -1 };
                [f as i64, g as i64, s]
            })
            .collect()
    }
}

/// Faces joined across interior edges that are not folded creases, as pieces: the piece
/// of each face, and the faces of each piece.
fn pieces(mesh: &Mesh) -> (Vec<usize>, Vec<Vec<usize>>) {
    let topo = mesh.topology();
    let mut joined = UnionFind::new(mesh.faces().len());
    for (e, edge) in mesh.edges().iter().enumerate() {
        if let [Some(a), Some(b)] = topo.edge_faces[e] {
            if !folds_completely(edge) {
                joined.union(a, b);
            }
        }
    }
    let mut id = HashMap::new();
    let mut members: Vec<Vec<usize>> = Vec::new();
    let piece_of = (0..mesh.faces().len())
        .map(|f| {
            let root = joined.find(f);
            let p = *id.entry(root).or_insert_with(|| {
                members.push(Vec::new());
                members.len() - 1
            });
            members[p].push(f);
            p
        })
        .collect();
    (piece_of, members)
}

/// Pairs of folded faces that overlap with positive area: sweep by x, then a
/// separating-axis test with margin `eps`.
fn overlapping_pairs(
    tri: &[[Vec2; 3]],
    eps: f64,
    budget: &Budget,
) -> Result<Vec<(usize, usize, f64)>, OverBudget> {
    let n = tri.len();
    let boxes: Vec<(Vec2, Vec2)> = tri.iter().map(|t| bounds(t)).collect();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x));
    let mut pairs = Vec::new();
    for (k, &a) in order.iter().enumerate() {
        budget.check()?;
        // Pairs of faces become pairs of pieces, variables, at most one each.
        budget.check_size(layer_bytes(pairs.len(), 0, 0, 0))?;
        for &b in &order[k + 1..] {
            if boxes[b].0.x >= boxes[a].1.x - eps {
                break;
            }
            if boxes[b].0.y >= boxes[a].1.y - eps || boxes[a].0.y >= boxes[b].1.y - eps {
                continue;
            }
            if let Some(depth) = overlap_depth(&tri[a], &tri[b], eps) {
                pairs.push((a.min(b), a.max(b), depth));
            }
        }
    }
    pairs.sort_unstable_by_key(|&(a, b, _)| (a, b));
    Ok(pairs)
}

/// Where edge `e` lies in the folded state, seen from face `a` (its corners there, as
/// [`FlatFolded::snapped`] left them, so a hinge lies exactly along its faces).
fn edge_image(mesh: &Mesh, folded: &FlatFolded, a: usize, e: usize) -> (Vec2, Vec2) {
    let face = mesh.faces()[a];
    let corner = |v: usize| {
        let k = face
            .iter()
            .position(|&w| w == v)
            .expect("an edge of a face has its corners in the face");
        folded.triangles[a][k]
    };
    let [u, v] = mesh.edges()[e].vertices;
    (corner(u), corner(v))
}
