//! Layer order of a flat-folded pattern: which face lies above which wherever faces
//! overlap once every ±π crease is folded. A pattern can hold Kawasaki and Maekawa at
//! every vertex and still have no layer order (two flaps that each cover the other's
//! hinge); it then cannot fold flat, and the maker should know before cutting.
//!
//! This follows Jason Ku's Flat-Folder (and the constraints of Jason Ku's and Erik
//! Demaine's work it builds on): one variable per pair of overlapping faces, fixed by the
//! creases' mountain/valley where the pair shares a crease, and tied by three kinds of
//! constraint —
//! - *taco–tortilla*: a face that crosses the folded line of a hinge (a crease, or a flat
//!   line joining two faces side by side) is not between the hinge's two faces;
//! - *taco–taco*: two creases folded onto the same line do not interleave their flaps;
//! - *transitivity*: three faces with a common overlap are not stacked in a cycle.
//!
//! The solver propagates forced values and searches the rest depth first, one
//! independent group of variables at a time. An unsatisfiable group is shrunk to a
//! smallest set of faces that still has no order, which the report names.

mod geometry;
mod search;

use super::budget::{Budget, OverBudget};
use super::flat_fold::{folds_flat, FlatFolded};
use crate::mesh::bounds;
use crate::mesh::{Assignment, Mesh, UnionFind, Vec2};
use geometry::{collinear_overlap, common_overlap, crosses, overlap};
use search::Search;
use std::collections::HashMap;

/// Overlaps thinner than this fraction of the pattern's size are contact, not overlap.
const OVERLAP_FRACTION: f64 = 1e-7;

/// The answer: an order, or the faces that admit none.
#[derive(Clone, Debug, PartialEq)]
pub enum LayerOrder {
    /// One valid order: FOLD `faceOrders` triples `[f, g, s]`, s = +1 when f lies above g
    /// (on the side g's normal points to), −1 below; one per overlapping pair.
    Found(Vec<[i64; 3]>),
    /// No order exists; these faces alone already have none.
    Conflict(Vec<usize>),
}

/// Why no layer order was computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LayerError {
    /// The flat-folded state itself is unavailable (partial targets, no crease pattern).
    #[error("{0}")]
    NotFlat(#[from] super::NotFlatFoldable),
    /// Too many overlaps to solve within the given budget.
    #[error("the search gave up after {0} decisions")]
    GaveUp(usize),
    /// The analysis ran out of its [`Budget`] (time, size, or cancelled).
    #[error("{0}")]
    OverBudget(#[from] OverBudget),
}

/// Decisions the search may take before giving up (a bound on time, not a verdict).
pub const SEARCH_BUDGET: usize = 2_000_000;

/// The first mountain or valley crease drawn at a fold other than its target: a pattern
/// drawn at partial folds (Origami Simulator's 90°) does not claim to fold flat.
pub fn partial_crease(mesh: &Mesh) -> Option<usize> {
    mesh.edges()
        .iter()
        .position(|e| e.assignment.is_folded() && (e.fold_angle - e.target).abs() > 1e-6)
}

/// Finds a layer order of `mesh`'s flat-folded state, or a smallest set of faces that
/// has none, within the default [`Budget`] (no deadline, a cap on memory).
pub fn layer_order(mesh: &Mesh) -> Result<LayerOrder, LayerError> {
    layer_order_within(mesh, &Budget::default())
}

/// [`layer_order`] within `budget`: the problem's size is checked as it is built and the
/// deadline between steps, so a pattern with thousands of faces stacked on one point ends
/// with [`LayerError::OverBudget`] instead of exhausting memory.
pub fn layer_order_within(mesh: &Mesh, budget: &Budget) -> Result<LayerOrder, LayerError> {
    let folded = super::flat_folded(mesh, None)?;
    let problem = Problem::build(mesh, &folded, budget)?;
    match problem.solve(None, budget)? {
        Ok(values) => Ok(LayerOrder::Found(problem.face_orders(&values, &folded))),
        Err(group) => Ok(LayerOrder::Conflict(
            problem.smallest_conflict(group, budget)?,
        )),
    }
}

/// `above[(i, j)]` with i < j: true when face i lies higher (toward +z of the folded
/// state) than face j.
pub(super) struct Problem {
    faces: usize,
    pairs: Vec<(usize, usize)>,
    index: HashMap<(usize, usize), usize>,
    /// Values the creases force: (variable, value).
    fixed: Vec<(usize, bool)>,
    pub(super) constraints: Vec<Constraint>,
}

/// A literal: variable `var` equals `value`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Lit {
    pub(super) var: usize,
    pub(super) value: bool,
}

#[derive(Clone, Debug)]
pub(super) enum Constraint {
    /// x == y (both literals true or both false).
    Same(Lit, Lit),
    /// x ⊕ y ⊕ z ⊕ w == false.
    Parity([Lit; 4]),
    /// Not all three literals true.
    NotAll([Lit; 3]),
}

impl Constraint {
    fn vars(&self) -> Vec<usize> {
        match self {
            Constraint::Same(a, b) => vec![a.var, b.var],
            Constraint::Parity(l) => l.iter().map(|x| x.var).collect(),
            Constraint::NotAll(l) => l.iter().map(|x| x.var).collect(),
        }
    }
}

impl Problem {
    /// The literal "face a lies above face b" (a ≠ b, the pair overlapping).
    fn above(&self, a: usize, b: usize) -> Option<Lit> {
        let key = (a.min(b), a.max(b));
        self.index.get(&key).map(|&var| Lit { var, value: a < b })
    }

    fn build(mesh: &Mesh, folded: &FlatFolded, budget: &Budget) -> Result<Problem, OverBudget> {
        let tri = &folded.triangles;
        let n = tri.len();
        let (lo, hi) = bounds(tri.as_flattened());
        // Rounded coordinates fold to images that miss each other by about the file's
        // rounding, compounded along the reflections (the closure gap measures it): a
        // sliver that thin is contact, not overlap.
        let eps = (OVERLAP_FRACTION * (hi - lo).norm())
            .max(2.0 * folded.mismatch + 8.0 * mesh.coordinate_precision)
            .max(1e-300);
        let pairs = overlapping_pairs(tri, eps, budget)?;
        let index: HashMap<(usize, usize), usize> =
            pairs.iter().enumerate().map(|(i, &p)| (p, i)).collect();
        let mut problem = Problem {
            faces: n,
            pairs,
            index,
            fixed: Vec::new(),
            constraints: Vec::new(),
        };
        let mut overlapping: Vec<Vec<usize>> = vec![Vec::new(); n];
        for &(a, b) in &problem.pairs {
            overlapping[a].push(b);
            overlapping[b].push(a);
        }
        let creases = problem.add_hinges(mesh, folded, &overlapping, eps, budget)?;
        problem.add_taco_taco(&creases, eps, budget)?;
        problem.add_transitivity(tri, &overlapping, eps, budget)?;
        Ok(problem)
    }

    /// Adds a constraint, failing when the problem outgrows the budget (checked with the
    /// deadline every few thousand constraints, where the loops that make them spend
    /// their time).
    fn push(&mut self, c: Constraint, budget: &Budget) -> Result<(), OverBudget> {
        self.constraints.push(c);
        if self.constraints.len().is_multiple_of(4096) {
            budget.check_size(self.constraints.len())?;
            budget.check()?;
        }
        Ok(())
    }

    /// Every interior edge is a hinge between its two faces: a folded crease fixes which
    /// lies above (valley brings the second face to the first's front, mountain behind),
    /// and a face crossing the hinge's folded line lies above both or below both
    /// (taco–tortilla). Returns the folded creases with their faces and folded lines.
    fn add_hinges(
        &mut self,
        mesh: &Mesh,
        folded: &FlatFolded,
        overlapping: &[Vec<usize>],
        eps: f64,
        budget: &Budget,
    ) -> Result<Vec<(usize, usize, Vec2, Vec2)>, OverBudget> {
        let topo = mesh.topology();
        let mut creases = Vec::new();
        for (e, edge) in mesh.edges().iter().enumerate() {
            let [Some(a), Some(b)] = topo.edge_faces[e] else {
                continue;
            };
            let (p, q) = edge_image(mesh, folded, a, e);
            let folded_crease =
                matches!(edge.assignment, Assignment::Mountain | Assignment::Valley)
                    && folds_flat(edge.target) == Some(true);
            if folded_crease {
                let b_above = (edge.assignment == Assignment::Valley) != folded.motions[a].flips();
                if let Some(l) = self.above(b, a) {
                    self.fixed.push((l.var, l.value == b_above));
                }
                creases.push((a, b, p, q));
            }
            for &c in overlapping[a].iter().filter(|&&c| c != b) {
                if !crosses(p, q, &folded.triangles[c], eps) {
                    continue;
                }
                if let (Some(x), Some(y)) = (self.above(a, c), self.above(b, c)) {
                    self.push(Constraint::Same(x, y), budget)?;
                }
            }
        }
        Ok(creases)
    }

    /// Taco–taco: creases folded onto the same line with their flaps on the same side
    /// nest or stay apart, never interleave.
    fn add_taco_taco(
        &mut self,
        creases: &[(usize, usize, Vec2, Vec2)],
        eps: f64,
        budget: &Budget,
    ) -> Result<(), OverBudget> {
        for (i, &(a, b, p, q)) in creases.iter().enumerate() {
            budget.check()?;
            for &(c, d, r, s) in &creases[i + 1..] {
                if !collinear_overlap(p, q, r, s, eps) {
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

    /// Transitivity: three faces with a common overlap are not stacked in a cycle.
    fn add_transitivity(
        &mut self,
        tri: &[[Vec2; 3]],
        overlapping: &[Vec<usize>],
        eps: f64,
        budget: &Budget,
    ) -> Result<(), OverBudget> {
        let neg = |l: Lit| Lit {
            var: l.var,
            value: !l.value,
        };
        for a in 0..tri.len() {
            budget.check()?;
            for (k, &b) in overlapping[a].iter().enumerate() {
                if b < a {
                    continue;
                }
                for &c in &overlapping[a][k + 1..] {
                    if c < a || self.above(b, c).is_none() {
                        continue;
                    }
                    if !common_overlap(&tri[a], &tri[b], &tri[c], eps) {
                        continue;
                    }
                    let ab = self.above(a, b).unwrap();
                    let bc = self.above(b, c).unwrap();
                    let ca = self.above(c, a).unwrap();
                    self.push(Constraint::NotAll([ab, bc, ca]), budget)?;
                    self.push(Constraint::NotAll([neg(ab), neg(bc), neg(ca)]), budget)?;
                }
            }
        }
        Ok(())
    }

    /// Values for every variable, or the faces of a group of variables with none. With
    /// `only`, faces outside that set are ignored (their variables left free).
    fn solve(
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
        let mut watching: Vec<Vec<usize>> = vec![Vec::new(); self.pairs.len()];
        let mut group = UnionFind::new(self.pairs.len());
        for (k, c) in self.constraints.iter().enumerate() {
            let vars = c.vars();
            if vars.iter().all(|&v| active(v)) {
                for &v in &vars {
                    watching[v].push(k);
                    group.union(vars[0], v);
                }
            }
        }
        let mut search = Search {
            problem: self,
            watching,
            value: vec![None; self.pairs.len()],
            trail: Vec::new(),
            decisions: 0,
            budget,
        };
        let faces_of = |vars: &[usize]| {
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
                return Ok(Err(faces_of(g)));
            }
        }
        // Groups share no constraint: each is decided on its own, and a group without
        // an order makes the whole pattern fail without searching the others again.
        for g in &groups {
            if !search.run(g)? {
                return Ok(Err(faces_of(g)));
            }
        }
        Ok(Ok(search.value.iter().map(|v| v.unwrap_or(true)).collect()))
    }

    /// Shrinks a group of faces without an order: drop faces one at a time while the
    /// rest still has none.
    fn smallest_conflict(
        &self,
        faces: Vec<usize>,
        budget: &Budget,
    ) -> Result<Vec<usize>, LayerError> {
        let mut keep = vec![false; self.faces];
        for &f in &faces {
            keep[f] = true;
        }
        for &f in &faces {
            budget.check()?;
            keep[f] = false;
            if self.solve(Some(&keep), budget)?.is_ok() {
                keep[f] = true;
            }
        }
        Ok((0..self.faces).filter(|&f| keep[f]).collect())
    }

    /// FOLD `faceOrders` from the values. The FOLD specification measures "above"
    /// along g's normal (as Rabbit Ear and Flat-Folder read it), so s = +1 when f lies
    /// on the side g's front faces.
    fn face_orders(&self, values: &[bool], folded: &FlatFolded) -> Vec<[i64; 3]> {
        self.pairs
            .iter()
            .zip(values)
            .map(|(&(f, g), &f_higher)| {
                let s = if f_higher != folded.motions[g].flips() {
                    1
                } else {
                    -1
                };
                [f as i64, g as i64, s]
            })
            .collect()
    }
}

/// Pairs of folded faces that overlap with positive area: sweep by x, then a
/// separating-axis test with margin `eps`.
fn overlapping_pairs(
    tri: &[[Vec2; 3]],
    eps: f64,
    budget: &Budget,
) -> Result<Vec<(usize, usize)>, OverBudget> {
    let n = tri.len();
    let boxes: Vec<(Vec2, Vec2)> = tri.iter().map(|t| bounds(t)).collect();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x));
    let mut pairs = Vec::new();
    for (k, &a) in order.iter().enumerate() {
        budget.check()?;
        // Each pair is a variable, and each becomes at least one constraint.
        budget.check_size(pairs.len())?;
        for &b in &order[k + 1..] {
            if boxes[b].0.x >= boxes[a].1.x - eps {
                break;
            }
            if boxes[b].0.y >= boxes[a].1.y - eps || boxes[a].0.y >= boxes[b].1.y - eps {
                continue;
            }
            if overlap(&tri[a], &tri[b], eps) {
                pairs.push((a.min(b), a.max(b)));
            }
        }
    }
    pairs.sort_unstable();
    Ok(pairs)
}

/// Where edge `e` lies in the folded state, seen from face `a`.
fn edge_image(mesh: &Mesh, folded: &FlatFolded, a: usize, e: usize) -> (Vec2, Vec2) {
    let cp = mesh
        .flat()
        .expect("a flat-folded state has a crease pattern");
    let [u, v] = mesh.edges()[e].vertices;
    let m = &folded.motions[a];
    (m.apply(cp[u]), m.apply(cp[v]))
}
