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

use super::flat_fold::FlatFolded;
use crate::mesh::{Assignment, Mesh, Vec2};
use std::collections::HashMap;

/// Overlaps thinner than this fraction of the pattern's size are contact, not overlap.
const OVERLAP_FRACTION: f64 = 1e-7;

/// The answer: an order, or the faces that admit none.
#[derive(Clone, Debug, PartialEq)]
pub enum LayerOrder {
    /// One valid order: FOLD `faceOrders` triples `[f, g, s]`, s = +1 when f lies above g
    /// on f's front side (its normal), −1 below; one per overlapping pair.
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
/// has none.
pub fn layer_order(mesh: &Mesh) -> Result<LayerOrder, LayerError> {
    let folded = super::flat_folded(mesh, None)?;
    let problem = Problem::build(mesh, &folded);
    match problem.solve(None)? {
        Ok(values) => Ok(LayerOrder::Found(problem.face_orders(&values, &folded))),
        Err(group) => Ok(LayerOrder::Conflict(problem.smallest_conflict(group)?)),
    }
}

/// `above[(i, j)]` with i < j: true when face i lies higher (toward +z of the folded
/// state) than face j.
struct Problem {
    faces: usize,
    pairs: Vec<(usize, usize)>,
    index: HashMap<(usize, usize), usize>,
    /// Values the creases force: (variable, value).
    fixed: Vec<(usize, bool)>,
    constraints: Vec<Constraint>,
}

/// A literal: variable `var` equals `value`.
#[derive(Clone, Copy, Debug)]
struct Lit {
    var: usize,
    value: bool,
}

#[derive(Clone, Debug)]
enum Constraint {
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

    fn build(mesh: &Mesh, folded: &FlatFolded) -> Problem {
        let tri = &folded.triangles;
        let n = tri.len();
        let (lo, hi) = bounds(tri.iter().flatten().copied());
        // Rounded coordinates fold to images that miss each other by about the file's
        // rounding, compounded along the reflections (the closure gap measures it): a
        // sliver that thin is contact, not overlap.
        let eps = (OVERLAP_FRACTION * (hi - lo).norm())
            .max(2.0 * folded.mismatch + 8.0 * mesh.coordinate_precision)
            .max(1e-300);
        // Overlapping pairs: sweep by x, then a separating-axis test with margin.
        let boxes: Vec<(Vec2, Vec2)> = tri.iter().map(|t| bounds(t.iter().copied())).collect();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x));
        let mut pairs = Vec::new();
        for (k, &a) in order.iter().enumerate() {
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
        let topo = mesh.topology();
        let mut creases_on_lines: Vec<(usize, usize, usize, Vec2, Vec2)> = Vec::new();
        for (e, edge) in mesh.edges().iter().enumerate() {
            let [Some(a), Some(b)] = topo.edge_faces[e] else {
                continue;
            };
            let (p, q) = edge_image(mesh, folded, a, e);
            let folded_crease =
                matches!(edge.assignment, Assignment::Mountain | Assignment::Valley)
                    && (edge.target.abs() / std::f64::consts::PI).round() as i64 % 2 != 0;
            if folded_crease {
                // b folds onto a: valley brings it to a's front, mountain behind.
                let b_above = (edge.assignment == Assignment::Valley) != folded.motions[a].flips();
                if let Some(l) = problem.above(b, a) {
                    problem.fixed.push((l.var, l.value == b_above));
                }
                creases_on_lines.push((e, a, b, p, q));
            }
            // Taco–tortilla: a face crossing this hinge's line is above both or below both.
            for &c in overlapping[a].iter().filter(|&&c| c != b) {
                if !crosses(p, q, &tri[c], eps) {
                    continue;
                }
                if let (Some(x), Some(y)) = (problem.above(a, c), problem.above(b, c)) {
                    problem.constraints.push(Constraint::Same(x, y));
                }
            }
        }
        // Taco–taco: creases folded onto the same line with flaps on the same side.
        for (i, &(_, a, b, p, q)) in creases_on_lines.iter().enumerate() {
            for &(_, c, d, r, s) in &creases_on_lines[i + 1..] {
                if !collinear_overlap(p, q, r, s, eps) {
                    continue;
                }
                let lits = [
                    problem.above(a, c),
                    problem.above(b, c),
                    problem.above(a, d),
                    problem.above(b, d),
                ];
                if let [Some(w), Some(x), Some(y), Some(z)] = lits {
                    problem.constraints.push(Constraint::Parity([w, x, y, z]));
                }
            }
        }
        // Transitivity over triples with a common overlap.
        for a in 0..n {
            for (k, &b) in overlapping[a].iter().enumerate() {
                if b < a {
                    continue;
                }
                for &c in &overlapping[a][k + 1..] {
                    if c < a || problem.above(b, c).is_none() {
                        continue;
                    }
                    if !common_overlap(&tri[a], &tri[b], &tri[c], eps) {
                        continue;
                    }
                    let ab = problem.above(a, b).unwrap();
                    let bc = problem.above(b, c).unwrap();
                    let ca = problem.above(c, a).unwrap();
                    let neg = |l: Lit| Lit {
                        var: l.var,
                        value: !l.value,
                    };
                    problem.constraints.push(Constraint::NotAll([ab, bc, ca]));
                    problem
                        .constraints
                        .push(Constraint::NotAll([neg(ab), neg(bc), neg(ca)]));
                }
            }
        }
        problem
    }

    /// Values for every variable, or the faces of a group of variables with none. With
    /// `only`, faces outside that set are ignored (their variables left free).
    fn solve(&self, only: Option<&[bool]>) -> Result<Result<Vec<bool>, Vec<usize>>, LayerError> {
        let active = |var: usize| {
            only.is_none_or(|keep| {
                let (a, b) = self.pairs[var];
                keep[a] && keep[b]
            })
        };
        let mut watching: Vec<Vec<usize>> = vec![Vec::new(); self.pairs.len()];
        let mut group: Vec<usize> = (0..self.pairs.len()).collect();
        fn root(g: &mut [usize], mut i: usize) -> usize {
            while g[i] != i {
                g[i] = g[g[i]];
                i = g[i];
            }
            i
        }
        for (k, c) in self.constraints.iter().enumerate() {
            let vars = c.vars();
            if vars.iter().all(|&v| active(v)) {
                for &v in &vars {
                    watching[v].push(k);
                    let (r, s) = (root(&mut group, vars[0]), root(&mut group, v));
                    group[r.max(s)] = r.min(s);
                }
            }
        }
        let mut search = Search {
            problem: self,
            watching,
            value: vec![None; self.pairs.len()],
            trail: Vec::new(),
            decisions: 0,
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
            members.entry(root(&mut group, v)).or_default().push(v);
        }
        let mut groups: Vec<Vec<usize>> = members.into_values().collect();
        groups.sort_unstable();
        for &(var, v) in &self.fixed {
            if active(var) && !search.assign(var, v) {
                let r = root(&mut group, var);
                let g = groups.iter().find(|g| root(&mut group, g[0]) == r).unwrap();
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
    fn smallest_conflict(&self, faces: Vec<usize>) -> Result<Vec<usize>, LayerError> {
        let mut keep = vec![false; self.faces];
        for &f in &faces {
            keep[f] = true;
        }
        for &f in &faces {
            keep[f] = false;
            if self.solve(Some(&keep))?.is_ok() {
                keep[f] = true;
            }
        }
        Ok((0..self.faces).filter(|&f| keep[f]).collect())
    }

    /// FOLD `faceOrders` from the values: s relative to f's own normal.
    fn face_orders(&self, values: &[bool], folded: &FlatFolded) -> Vec<[i64; 3]> {
        self.pairs
            .iter()
            .zip(values)
            .map(|(&(f, g), &f_higher)| {
                let s = if f_higher != folded.motions[f].flips() {
                    1
                } else {
                    -1
                };
                [f as i64, g as i64, s]
            })
            .collect()
    }
}

/// Depth-first search with propagation and an undo trail.
struct Search<'a> {
    problem: &'a Problem,
    watching: Vec<Vec<usize>>,
    value: Vec<Option<bool>>,
    trail: Vec<usize>,
    decisions: usize,
}

impl Search<'_> {
    fn lit(&self, l: Lit) -> Option<bool> {
        self.value[l.var].map(|v| v == l.value)
    }

    /// Sets a variable and everything it forces; false on a contradiction (the trail
    /// keeps what was set, for undoing).
    fn assign(&mut self, var: usize, v: bool) -> bool {
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
                        let unknown: Vec<Lit> = l
                            .iter()
                            .copied()
                            .filter(|x| self.lit(*x).is_none())
                            .collect();
                        let ones = l.iter().filter(|x| self.lit(**x) == Some(true)).count();
                        match unknown.len() {
                            0 if ones % 2 == 1 => return false,
                            1 => {
                                let need_true = ones % 2 == 1;
                                let u = unknown[0];
                                queue.push((u.var, need_true == u.value));
                            }
                            _ => {}
                        }
                    }
                    Constraint::NotAll(l) => {
                        let trues = l.iter().filter(|x| self.lit(**x) == Some(true)).count();
                        let unknown: Vec<Lit> = l
                            .iter()
                            .copied()
                            .filter(|x| self.lit(*x).is_none())
                            .collect();
                        if trues == 3 {
                            return false;
                        }
                        if trues == 2 && unknown.len() == 1 {
                            let u = unknown[0];
                            queue.push((u.var, !u.value));
                        }
                    }
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

    /// Decides the variables in `order` not yet set: true when all could be. Depth
    /// first: each decision tries "above" then "below"; a contradiction undoes back to the
    /// latest decision with a branch left.
    fn run(&mut self, order: &[usize]) -> Result<bool, LayerError> {
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

fn bounds(points: impl Iterator<Item = Vec2>) -> (Vec2, Vec2) {
    points.fold(
        (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.inf(&p), hi.sup(&p)),
    )
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

/// Two triangles overlap with positive area: no separating axis among their sides, by
/// more than `eps`.
fn overlap(s: &[Vec2; 3], t: &[Vec2; 3], eps: f64) -> bool {
    for poly in [s, t] {
        for k in 0..3 {
            let d = poly[(k + 1) % 3] - poly[k];
            let n = Vec2::new(-d.y, d.x) / d.norm().max(1e-300);
            let span = |p: &[Vec2; 3]| {
                p.iter()
                    .map(|q| n.dot(q))
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                        (lo.min(x), hi.max(x))
                    })
            };
            let (a, b) = (span(s), span(t));
            if a.1 <= b.0 + eps || b.1 <= a.0 + eps {
                return false;
            }
        }
    }
    true
}

/// Segment p–q passes through the interior of triangle t for a length above `eps`.
fn crosses(p: Vec2, q: Vec2, t: &[Vec2; 3], eps: f64) -> bool {
    let d = q - p;
    let len = d.norm();
    if len <= eps {
        return false;
    }
    let area = (t[1] - t[0]).perp(&(t[2] - t[0]));
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for k in 0..3 {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let e = b - a;
        // Inward distance of x from side a→b, for a counter-clockwise or clockwise t.
        let inward = |x: Vec2| e.perp(&(x - a)) * area.signum() / e.norm();
        let (fp, fd) = (inward(p) - eps, inward(q) - inward(p));
        // Need fp + fd·s > 0.
        if fd.abs() < 1e-300 {
            if fp <= 0.0 {
                return false;
            }
        } else if fd > 0.0 {
            lo = lo.max(-fp / fd);
        } else {
            hi = hi.min(-fp / fd);
        }
    }
    (hi - lo) * len > eps
}

/// Segments p–q and r–s lie on one line and share a stretch longer than `eps`.
fn collinear_overlap(p: Vec2, q: Vec2, r: Vec2, s: Vec2, eps: f64) -> bool {
    let d = q - p;
    let len = d.norm();
    let u = d / len;
    let off = |x: Vec2| u.perp(&(x - p)).abs();
    if off(r) > eps || off(s) > eps {
        return false;
    }
    let (a, b) = ((r - p).dot(&u), (s - p).dot(&u));
    let (a, b) = (a.min(b), a.max(b));
    b.min(len) - a.max(0.0) > eps
}

/// Three triangles share a region of positive area.
fn common_overlap(a: &[Vec2; 3], b: &[Vec2; 3], c: &[Vec2; 3], eps: f64) -> bool {
    let ab = clip(a.to_vec(), b);
    let abc = clip(ab, c);
    area(&abc) > eps * eps
}

/// Sutherland–Hodgman: the part of `poly` inside triangle `t`.
fn clip(mut poly: Vec<Vec2>, t: &[Vec2; 3]) -> Vec<Vec2> {
    let orient = (t[1] - t[0]).perp(&(t[2] - t[0])).signum();
    for k in 0..3 {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let side = |x: Vec2| (b - a).perp(&(x - a)) * orient;
        let input = std::mem::take(&mut poly);
        for i in 0..input.len() {
            let (p, q) = (input[i], input[(i + 1) % input.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                poly.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                poly.push(p + (q - p) * (sp / (sp - sq)));
            }
        }
        if poly.is_empty() {
            break;
        }
    }
    poly
}

fn area(poly: &[Vec2]) -> f64 {
    (0..poly.len())
        .map(|i| poly[i].perp(&poly[(i + 1) % poly.len()]))
        .sum::<f64>()
        .abs()
        / 2.0
}
