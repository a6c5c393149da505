//! Mesh modification (paper §4): when a large deformation makes an edge degenerate, collapse
//! it (in the spirit of Hoppe et al.) under the rules that keep the flat-folded state
//! valid, or flip a crease that stays unfolded. The crease pattern's topology changes and
//! new origami patterns appear. [`Solver::remesh`] keeps a change only when Newton's
//! method restores the conditions afterwards.
//!
//! The rules of §4, as checked here:
//! - only a ±π crease between two interior, flat-foldable vertices collapses;
//! - merged edges take the sum of their targets;
//! - the sum of target angles around the merged vertex is ±2π (Maekawa), which allows
//!   exactly the paper's two cases: (±2π, ±2π) joined by a ±π edge, and (2π, −2π) joined
//!   by either;
//! - the merged vertex keeps at least four creases;
//! - the two rings meet only at the two opposite vertices (the link condition), so the
//!   mesh stays a manifold.

use super::{free_columns, NormalSolver, Solver};
use crate::constraints::Reference;
use crate::mesh::{edge_key, Assignment, Edge, Mesh, MeshParts, Vec3};
use crate::tolerance::SAME_ANGLE_RADIANS;
use std::collections::{BTreeSet, HashMap};
use std::f64::consts::PI;

/// Why a collapse or flip was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Refusal {
    /// The design locks its topology (Resch, §6.4).
    #[error("the design locks its topology")]
    Locked,
    /// An end of the edge lies on the boundary, or the edge has one face.
    #[error("edge {0} touches the boundary")]
    Boundary(usize),
    /// Only ±π creases collapse (§4).
    #[error("edge {0} is not a ±π crease")]
    NotAFold(usize),
    /// An end is not a flat-foldable vertex (target sum ±2π).
    #[error("vertex {vertex} has target sum {sum:.3} rad, not ±2π")]
    NotFlatFoldable {
        /// The vertex.
        vertex: usize,
        /// Its target sum.
        sum: f64,
    },
    /// The merged vertex would break Maekawa.
    #[error("merging would give a vertex with target sum {0:.3} rad (Maekawa needs ±2π)")]
    Maekawa(f64),
    /// The merged vertex would keep too few creases.
    #[error("merging would leave {0} creases at the vertex (at least 4 are needed)")]
    TooFewCreases(usize),
    /// The rings of the two ends share more than the two opposite vertices.
    #[error("collapsing edge {0} would make the mesh non-manifold")]
    LinkCondition(usize),
    /// A vertex the user holds or drags would disappear.
    #[error("vertex {0} is held or dragged")]
    Protected(usize),
    /// A flip is only for unfolded, untwisting creases (target 0, α = 0).
    #[error("edge {0} is not a flat crease with α = 0")]
    NotFlippable(usize),
    /// The result failed validation.
    #[error("the result is not a valid mesh: {0}")]
    Invalid(#[source] crate::mesh::MeshError),
}

/// A planned change: the new mesh parts, positions, and where each old vertex went.
#[derive(Clone, Debug)]
pub struct Change {
    /// The new mesh.
    pub mesh: Mesh,
    /// New positions (3D).
    pub positions: Vec<Vec3>,
    /// Old vertex index → new index.
    pub old_to_new: Vec<usize>,
}

fn target_sum(mesh: &Mesh, v: usize) -> f64 {
    mesh.topology().fans[v]
        .spokes
        .iter()
        .map(|&e| mesh.edges()[e].target)
        .sum()
}

fn is_pm(x: f64, value: f64) -> bool {
    (x.abs() - value).abs() < SAME_ANGLE_RADIANS
}

fn neighbours(mesh: &Mesh, v: usize) -> BTreeSet<usize> {
    mesh.topology().fans[v]
        .spokes
        .iter()
        .map(|&e| mesh.edges()[e].other(v))
        .collect()
}

fn assignment_for(target: f64, old: Assignment) -> Assignment {
    if target > SAME_ANGLE_RADIANS {
        Assignment::Mountain
    } else if target < -SAME_ANGLE_RADIANS {
        Assignment::Valley
    } else if old.is_folded() {
        Assignment::Flat
    } else {
        old
    }
}

/// Plans the collapse of edge `e` of `mesh` at positions `x` into its midpoint. Vertices
/// in `protected` may not disappear (they stay as the merged vertex only if both ends are
/// unprotected).
pub fn collapse_edge(
    mesh: &Mesh,
    x: &[Vec3],
    e: usize,
    protected: &[usize],
) -> Result<Change, Refusal> {
    let [u, v] = collapsible(mesh, e, protected)?;
    // Renumber: v disappears, u becomes the merged vertex at the midpoint.
    let n = mesh.vertex_count();
    let old_to_new: Vec<usize> = (0..n)
        .map(|w| {
            let w = if w == v { u } else { w };
            if w > v {
                w - 1
            } else {
                w
            }
        })
        .collect();
    let mut positions: Vec<Vec3> = (0..n).filter(|&w| w != v).map(|w| x[w]).collect();
    positions[old_to_new[u]] = (x[u] + x[v]) / 2.0;
    let flat = mesh.crease_pattern().map(|f| {
        let mut out: Vec<_> = (0..n).filter(|&w| w != v).map(|w| f[w]).collect();
        out[old_to_new[u]] = (f[u] + f[v]) / 2.0;
        out
    });
    let faces: Vec<[usize; 3]> = mesh
        .faces()
        .iter()
        .filter(|f| !(f.contains(&u) && f.contains(&v)))
        .map(|f| f.map(|w| old_to_new[w]))
        .collect();
    let has_3d = mesh.has_3d();
    let mut new = Mesh::new(MeshParts {
        positions: Some(positions.clone()),
        flat,
        faces,
        edges: merged_edges(mesh, e, &old_to_new),
    })
    .map_err(Refusal::Invalid)?;
    if !has_3d {
        new.set_positions(positions.clone());
    }
    new.title = mesh.title.clone();
    new.lock_topology = mesh.lock_topology;
    new.coordinate_precision = mesh.coordinate_precision;
    new.source = mesh.source.clone();
    Ok(Change {
        mesh: new,
        positions,
        old_to_new,
    })
}

/// Whether edge `e` may collapse under the rules of §4 (an interior fold between two
/// flat-foldable vertices whose merge still satisfies Maekawa, the link condition, and
/// at least four creases at the merged vertex); its ends if so.
fn collapsible(mesh: &Mesh, e: usize, protected: &[usize]) -> Result<[usize; 2], Refusal> {
    // Coincidence groups (§6.4) name vertices by index, which a collapse renumbers.
    if mesh.lock_topology || !mesh.coincident.is_empty() {
        return Err(Refusal::Locked);
    }
    let edge = &mesh.edges()[e];
    let [u, v] = edge.vertices;
    let topo = mesh.topology();
    if !mesh.is_interior(u)
        || !mesh.is_interior(v)
        || topo.edge_faces[e].iter().any(Option::is_none)
    {
        return Err(Refusal::Boundary(e));
    }
    if let Some(&p) = [u, v].iter().find(|w| protected.contains(w)) {
        return Err(Refusal::Protected(p));
    }
    let t = edge.target;
    if !is_pm(t, PI) {
        return Err(Refusal::NotAFold(e));
    }
    let (su, sv) = (target_sum(mesh, u), target_sum(mesh, v));
    for (vertex, sum) in [(u, su), (v, sv)] {
        if !is_pm(sum, 2.0 * PI) {
            return Err(Refusal::NotFlatFoldable { vertex, sum });
        }
    }
    let merged_sum = su + sv - 2.0 * t;
    if !is_pm(merged_sum, 2.0 * PI) {
        return Err(Refusal::Maekawa(merged_sum));
    }
    // The link condition: the rings share exactly the two vertices opposite the edge.
    let opposite: BTreeSet<usize> = topo.edge_faces[e]
        .iter()
        .flatten()
        .map(|&f| {
            *mesh.faces()[f]
                .iter()
                .find(|&&w| w != u && w != v)
                .expect("triangle")
        })
        .collect();
    let (nu, nv) = (neighbours(mesh, u), neighbours(mesh, v));
    let shared: BTreeSet<usize> = nu.intersection(&nv).copied().collect();
    if shared != opposite {
        return Err(Refusal::LinkCondition(e));
    }
    // Creases at the merged vertex, with merged edges' targets summed.
    let mut at_w: HashMap<usize, f64> = HashMap::new();
    for (end, ring) in [(u, &nu), (v, &nv)] {
        for &n in ring.iter().filter(|&&n| n != u && n != v) {
            let ed = topo.edge_between(end, n).expect("spoke");
            *at_w.entry(n).or_default() += mesh.edges()[ed].target;
        }
    }
    let creases = at_w
        .values()
        .filter(|t| t.abs() > SAME_ANGLE_RADIANS)
        .count();
    if creases < 4 {
        return Err(Refusal::TooFewCreases(creases));
    }
    Ok([u, v])
}

/// The edges after `e` collapses: renumbered, and the two pairs of spokes that become
/// one edge each merged (targets and fold angles summed, the assignment the sum implies).
fn merged_edges(mesh: &Mesh, e: usize, old_to_new: &[usize]) -> Vec<Edge> {
    let mut edges: Vec<Edge> = Vec::with_capacity(mesh.edges().len());
    let mut index: HashMap<(usize, usize), usize> = HashMap::new();
    for (i, ed) in mesh.edges().iter().enumerate() {
        if i == e {
            continue;
        }
        let [a, b] = ed.vertices.map(|w| old_to_new[w]);
        let key = edge_key(a, b);
        match index.get(&key) {
            Some(&j) => {
                let m = &mut edges[j];
                m.target += ed.target;
                m.fold_angle += ed.fold_angle;
                m.alpha = m.alpha.max(ed.alpha);
                m.assignment = assignment_for(m.target, m.assignment.max(ed.assignment));
                m.synthetic = false;
            }
            None => {
                let mut ne = ed.clone();
                ne.vertices = [a, b];
                index.insert(key, edges.len());
                edges.push(ne);
            }
        }
    }
    edges
}

/// Plans flipping edge `e` (a flat crease with α = 0) to the other diagonal of its two
/// triangles, when that is a better triangulation (larger smallest angle in 3D) and
/// both new triangles keep their orientation.
pub fn flip_edge(mesh: &Mesh, x: &[Vec3], e: usize) -> Result<Change, Refusal> {
    if mesh.lock_topology {
        return Err(Refusal::Locked);
    }
    let edge = &mesh.edges()[e];
    if edge.target != 0.0
        || edge.alpha != 0.0
        || !matches!(edge.assignment, Assignment::Flat | Assignment::Join)
    {
        return Err(Refusal::NotFlippable(e));
    }
    let [Some(fl), Some(fr)] = mesh.topology().edge_faces[e] else {
        return Err(Refusal::Boundary(e));
    };
    let [u, v] = edge.vertices;
    let third = |f: usize| {
        *mesh.faces()[f]
            .iter()
            .find(|&&w| w != u && w != v)
            .expect("triangle")
    };
    let (a, b) = (third(fl), third(fr));
    if mesh.topology().edge_between(a, b).is_some() {
        return Err(Refusal::LinkCondition(e));
    }
    // Left face (u, v, a), right face (v, u, b): the quad runs u → b → v → a
    // counter-clockwise, so the faces on the other diagonal are (u, b, a) and (b, v, a).
    let min_angle = |t: [usize; 3]| {
        (0..3)
            .map(|k| crate::geometry::sector_angle(x, t, k))
            .fold(f64::INFINITY, f64::min)
    };
    let before = min_angle([u, v, a]).min(min_angle([v, u, b]));
    let (t1, t2) = ([u, b, a], [b, v, a]);
    let after = min_angle(t1).min(min_angle(t2));
    if after <= before {
        return Err(Refusal::NotFlippable(e));
    }
    // Orientation kept: the new normals agree with the old ones.
    let n_old =
        crate::geometry::face_normal(x, [u, v, a]) + crate::geometry::face_normal(x, [v, u, b]);
    if crate::geometry::face_normal(x, t1).dot(&n_old) <= 0.0
        || crate::geometry::face_normal(x, t2).dot(&n_old) <= 0.0
    {
        return Err(Refusal::NotFlippable(e));
    }
    let faces: Vec<[usize; 3]> = mesh
        .faces()
        .iter()
        .enumerate()
        .map(|(i, f)| {
            if i == fl {
                t1
            } else if i == fr {
                t2
            } else {
                *f
            }
        })
        .collect();
    let mut edges = mesh.edges().to_vec();
    edges[e].vertices = [a, b];
    let mut new = Mesh::new(MeshParts {
        positions: Some(x.to_vec()),
        flat: mesh.crease_pattern().map(<[_]>::to_vec),
        faces,
        edges,
    })
    .map_err(Refusal::Invalid)?;
    new.title = mesh.title.clone();
    new.coordinate_precision = mesh.coordinate_precision;
    new.source = mesh.source.clone();
    Ok(Change {
        mesh: new,
        positions: x.to_vec(),
        old_to_new: (0..x.len()).collect(),
    })
}

/// What one remeshing pass changed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RemeshOutcome {
    /// Edges collapsed.
    pub collapses: usize,
    /// Flat creases flipped.
    pub flips: usize,
    /// Degenerate edges whose collapse the rules refused.
    pub refused: usize,
    /// Old vertex index → new, when vertices were renumbered.
    pub renumbered: Option<Vec<usize>>,
}

impl Solver {
    /// Takes over a changed mesh: adjacency, references, fixed vertices and the linear
    /// algebra are rebuilt; fold-angle branches are read off the current positions.
    fn adopt(&mut self, change: Change) {
        let n = change.positions.len();
        let mut fixed = vec![false; n];
        for (old, &new) in change.old_to_new.iter().enumerate() {
            if self.fixed[old] {
                fixed[new] = true;
            }
        }
        let (columns, free) = free_columns(&fixed);
        self.reference = Reference::for_conditions(&change.mesh, &self.set);
        self.mesh = change.mesh;
        self.x = change.positions;
        self.fixed = fixed;
        self.columns = columns;
        self.free = free;
        self.linear = NormalSolver::default();
        self.factored.clear();
        self.factor_age = 0;
        self.forget_last_step();
    }

    /// Mesh modification (§4): collapses edges shorter than `threshold` × the mean edge
    /// length where the rules allow, flips flat creases next to them for better triangles,
    /// and keeps a change only if the conditions can be restored afterwards. Vertices in
    /// `protected` (being dragged) and fixed ones never disappear.
    pub fn remesh(&mut self, protected: &[usize], threshold: f64) -> RemeshOutcome {
        let mut outcome = RemeshOutcome::default();
        if self.mesh.lock_topology {
            return outcome;
        }
        let mut map: Vec<usize> = (0..self.x.len()).collect();
        let mut protect: Vec<usize> = protected.to_vec();
        for _ in 0..16 {
            protect.extend((0..self.x.len()).filter(|&v| self.fixed[v]));
            let mean = super::mean_edge(&self.mesh, &self.x);
            let mut short: Vec<(f64, usize)> = self
                .mesh
                .edges()
                .iter()
                .enumerate()
                .map(|(i, e)| ((self.x[e.vertices[1]] - self.x[e.vertices[0]]).norm(), i))
                .filter(|&(l, _)| l < threshold * mean)
                .collect();
            short.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut current = self.mesh.clone();
            current.set_positions(self.x.clone());
            let mut changed = false;
            for &(_, e) in &short {
                let planned = collapse_edge(&current, &self.x, e, &protect)
                    .map(|c| (c, true))
                    .or_else(|err| {
                        // A short flat crease may be flipped away instead.
                        flip_edge(&current, &self.x, e)
                            .map(|c| (c, false))
                            .map_err(|_| err)
                    });
                let Ok((change, is_collapse)) = planned else {
                    outcome.refused += 1;
                    continue;
                };
                let saved = (
                    self.mesh.clone(),
                    self.x.clone(),
                    self.reference.clone(),
                    self.fixed.clone(),
                );
                let step_map = change.old_to_new.clone();
                self.adopt(change);
                if self.correct().is_ok() {
                    map = map.iter().map(|&m| step_map[m]).collect();
                    protect = protect.iter().map(|&p| step_map[p]).collect();
                    if is_collapse {
                        outcome.collapses += 1;
                    } else {
                        outcome.flips += 1;
                    }
                    changed = true;
                    break;
                }
                // The conditions could not be restored: undo.
                let (mesh, x, reference, fixed) = saved;
                let old_n = x.len();
                self.fixed = fixed;
                self.adopt(Change {
                    mesh,
                    positions: x,
                    old_to_new: (0..old_n).collect(),
                });
                self.reference = reference;
                outcome.refused += 1;
            }
            if !changed {
                break;
            }
        }
        if outcome.collapses > 0 {
            outcome.renumbered = Some(map);
        }
        outcome
    }
}
