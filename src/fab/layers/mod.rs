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
//! The solver propagates forced values and searches the rest with conflict-driven clause
//! learning (module `search`), one independent group of variables at a time. An
//! unsatisfiable group is shrunk towards a smallest set of faces that still has no
//! order, which the report names.

mod balance;
mod count;
mod crimp;
mod geometry;
mod pair_index;
mod problem;
mod search;
mod thirds;

pub use count::{GroupCount, StateTotal};

use super::budget::{Budget, OverBudget};
use super::flat_fold::FlatFolded;
use crate::constraints::folds_flat;
use crate::mesh::bounds;
use crate::mesh::{Assignment, Mesh};
use geometry::overlap_depth;
use pair_index::SpreadRow;
use problem::{Constraint, Lit, Problem};

/// The most the contact allowance may be (mm): a sheet of 80 g/m² paper is about 0.1 mm
/// thick, so an overlap deeper than that is a collision however coarse the file's
/// rounding, never a sliver.
pub const MAX_CONTACT: f64 = 0.1;

/// The answer: an order, or the faces that admit none.
#[derive(Clone, Debug, PartialEq)]
pub enum LayerOrder {
    /// One valid order: FOLD `faceOrders` triples `[f, g, s]`, s = +1 when f lies above g
    /// (on the side g's normal points to), −1 below; one per overlapping pair.
    Found(Vec<[i64; 3]>),
    /// No order exists; these faces alone already have none.
    Conflict(LayerConflict),
}

/// Faces that admit no layer order, and how much they overlap: a designer tells a real
/// collision (millimetres) from a sliver (a few microns, what rounding leaves) by it.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerConflict {
    /// The faces (triangles of the mesh), a smallest set found with no order.
    pub faces: Vec<usize>,
    /// Of the overlaps among them, the thinnest: how far (mm) its two faces would have
    /// to move apart, in the folded plane, to stop overlapping.
    pub thinnest: f64,
    /// The thickest such overlap (mm).
    pub thickest: f64,
    /// Overlaps thinner than this (mm) were taken as contact.
    pub contact: f64,
    /// The vertex whose creases alone cannot be stacked flat, when the conflict was found
    /// there (by crimps, before any pair search).
    pub vertex: Option<usize>,
}

impl std::fmt::Display for LayerConflict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<String> = self.faces.iter().map(|f| f.to_string()).collect();
        if let Some(v) = self.vertex {
            write!(f, "the creases at vertex {v} cannot be stacked flat (no sequence of crimps folds them); its {} faces overlap by ", self.faces.len())?;
        } else {
            write!(
                f,
                "no order among faces {}; they overlap by ",
                names.join(", ")
            )?;
        }
        write!(
            f,
            "{:.3}-{:.3} mm (thinner than {:.1e} mm counts as contact)",
            self.thinnest, self.thickest, self.contact
        )
    }
}

/// Why no layer order was computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LayerError {
    /// The flat-folded state itself is unavailable (partial targets, no crease pattern).
    #[error("{0}")]
    NotFlat(#[from] super::NotFlatFoldable),
    /// The faces do not close up around a vertex once folded flat (Kawasaki's condition
    /// fails there): there is no flat-folded state to order.
    #[error("the faces around vertex {vertex} leave a gap of {gap:.2e} mm once folded flat (more than {tolerance:.1e} mm): it does not fold flat")]
    Open {
        /// The vertex with the widest gap.
        vertex: usize,
        /// The gap, mm.
        gap: f64,
        /// The closure tolerance it exceeds, mm.
        tolerance: f64,
    },
    /// A folded crease has the same piece of paper on both sides: the lines around its
    /// ends stay flat, so it cannot fold.
    #[error("crease {0} cannot fold: the paper on its two sides is joined round its end by lines that stay flat")]
    SelfHinged(usize),
    /// Too many overlaps to solve within the given budget.
    #[error("the search gave up after {0} decisions")]
    GaveUp(usize),
    /// The analysis ran out of its [`Budget`] (time, size, or cancelled).
    #[error("{0}")]
    OverBudget(#[from] OverBudget),
}

impl LayerError {
    /// The command line's exit code for a search that ended so: 1 when it answers the
    /// question (the faces do not close up, a crease cannot fold), 3 when it stopped
    /// undecided (a budget ran out, the search gave up, no flat state to order).
    pub fn exit_code(&self) -> u8 {
        match self {
            LayerError::Open { .. } | LayerError::SelfHinged(_) => 1,
            LayerError::NotFlat(_) | LayerError::GaveUp(_) | LayerError::OverBudget(_) => 3,
        }
    }
}

/// The most search work ([`Budget::work`]) a verdict spends naming fewer faces of a
/// conflict already proved: about 4 s on the machine the benchmarks run on (80 million
/// units a second). Work, not time, so the faces named are the same on any machine and
/// under any load.
pub const SHRINK_WORK: u64 = 320_000_000;

/// The most search work a row that only advises (a 3D design's flat state) spends on
/// naming its conflict: about half a second.
pub const ADVISORY_SHRINK_WORK: u64 = 40_000_000;

/// Decisions the search may take before giving up (a bound on time, not a verdict).
pub const SEARCH_BUDGET: usize = 2_000_000;

/// The first mountain or valley crease drawn at a fold other than its target: a pattern
/// drawn at partial folds (Origami Simulator's 90°) does not claim to fold flat.
pub fn partial_crease(mesh: &Mesh) -> Option<usize> {
    mesh.edges().iter().position(|e| {
        e.assignment.is_folded()
            && (e.fold_angle - e.target).abs() > crate::tolerance::VERIFIED_RESIDUAL
    })
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
    decide(mesh, budget, Some(SHRINK_WORK))
}

/// [`layer_order_within`] with at most `naming` units of search work spent shrinking a
/// conflict to fewer faces (for a row that only advises, where seconds spent naming are
/// not worth it).
pub fn layer_order_naming_within(
    mesh: &Mesh,
    budget: &Budget,
    naming: u64,
) -> Result<LayerOrder, LayerError> {
    decide(mesh, budget, Some(naming))
}

/// Whether `mesh`'s flat-folded state has a layer order, within `budget`: `None` when it
/// has, else the faces of a group of overlapping pairs that has none (not shrunk to a
/// smallest set, which costs a solve per face: this is the check a drag step is held to).
pub fn layer_conflict(mesh: &Mesh, budget: &Budget) -> Result<Option<LayerConflict>, LayerError> {
    Ok(match decide(mesh, budget, None)? {
        LayerOrder::Found(_) => None,
        LayerOrder::Conflict(c) => Some(c),
    })
}

/// The order, or a conflict (shrunk towards a smallest set of faces with at most `shrink`
/// units of search work).
fn decide(mesh: &Mesh, budget: &Budget, shrink: Option<u64>) -> Result<LayerOrder, LayerError> {
    Ok(match solved(mesh, budget, shrink)? {
        Solved::Order(problem, values) => LayerOrder::Found(problem.face_orders(&values)),
        Solved::Conflict(c) => LayerOrder::Conflict(c),
    })
}

/// For a crease pattern whose unassigned creases aim at ±π (their side left open): a
/// mountain or valley for each, read back from a layer order the search found with
/// their hinges free, or the faces of a conflict no assignment escapes. What Flat-Folder
/// does for an "unassigned" pattern.
pub fn assign_unassigned(
    mesh: &Mesh,
    budget: &Budget,
) -> Result<Result<Vec<(usize, Assignment)>, LayerConflict>, LayerError> {
    Ok(match solved(mesh, budget, Some(SHRINK_WORK))? {
        Solved::Order(problem, values) => Ok(problem.hinge_assignments(mesh, &values)),
        Solved::Conflict(c) => Err(c),
    })
}

/// A solved layer problem: its values, or the conflict.
enum Solved {
    Order(Box<Problem>, Vec<bool>),
    Conflict(LayerConflict),
}

/// The flat-folded states of `mesh`: the count of each independent group of open pair
/// variables (each up to `cap`), whose product is the number of layer orders; `None` when
/// there is none.
pub fn count_states(
    mesh: &Mesh,
    budget: &Budget,
    cap: u64,
) -> Result<Option<Vec<GroupCount>>, LayerError> {
    match prepared(mesh, budget)? {
        Prepared::Problem(problem) => problem.count_states(budget, cap),
        Prepared::Conflict(_) => Ok(None),
    }
}

/// A layer problem set up, or a vertex already known to stack no way.
enum Prepared {
    Problem(Box<Problem>),
    Conflict(LayerConflict),
}

/// The flat-folded state of `mesh` and its layer problem, checked to close up.
fn prepared(mesh: &Mesh, budget: &Budget) -> Result<Prepared, LayerError> {
    let folded = super::flat_folded(mesh, None)?;
    if !folded.layers_close() {
        return Err(LayerError::Open {
            vertex: folded.worst_vertex.unwrap_or(0),
            gap: folded.mismatch,
            tolerance: folded.tolerance,
        });
    }
    // Judged at the drawing's precision: the noise spread over the pattern rather than
    // compounded along the walk, then corners meant to meet, met.
    let folded = balance::balanced(mesh, folded).snapped(mesh.coordinate_precision);
    let crease_at = |e: usize| folds_completely(&mesh.edges()[e]);
    if let Some((vertex, faces)) = crimp::first_unstackable_vertex(mesh, crease_at) {
        return Ok(Prepared::Conflict(vertex_conflict(
            mesh, &folded, vertex, faces, budget,
        )?));
    }
    let problem = Problem::build(mesh, &folded, budget)?;
    if let Some(crease) = problem.self_hinged {
        return Err(LayerError::SelfHinged(crease));
    }
    Ok(Prepared::Problem(Box::new(problem)))
}

/// [`decide`]'s work, keeping the problem and its values.
fn solved(mesh: &Mesh, budget: &Budget, shrink: Option<u64>) -> Result<Solved, LayerError> {
    let problem = match prepared(mesh, budget)? {
        Prepared::Problem(problem) => problem,
        Prepared::Conflict(c) => return Ok(Solved::Conflict(c)),
    };
    match problem.solve(None, budget)? {
        Ok(values) => Ok(Solved::Order(problem, values)),
        Err(group) => {
            let pieces = match shrink {
                Some(work) => problem.smallest_conflict(group, budget, work),
                None => group,
            };
            Ok(Solved::Conflict(problem.conflict(&pieces)))
        }
    }
}

/// A vertex whose creases cannot be stacked, with the overlaps among its faces.
fn vertex_conflict(
    mesh: &Mesh,
    folded: &FlatFolded,
    vertex: usize,
    faces: Vec<usize>,
    budget: &Budget,
) -> Result<LayerConflict, OverBudget> {
    let tri = &folded.triangles;
    let contact = contact_allowance(mesh, folded);
    let (mut thinnest, mut thickest) = (f64::INFINITY, 0.0f64);
    for (i, &a) in faces.iter().enumerate() {
        budget.check()?;
        for &b in &faces[i + 1..] {
            if let Some(d) = overlap_depth(&tri[a], &tri[b], contact) {
                thinnest = thinnest.min(d);
                thickest = thickest.max(d);
            }
        }
    }
    let mut faces = faces;
    faces.sort_unstable();
    Ok(LayerConflict {
        faces,
        thinnest: thinnest.min(thickest),
        thickest,
        contact,
        vertex: Some(vertex),
    })
}

/// Overlaps thinner than this (mm) are contact: rounded coordinates fold to images that
/// miss each other by about the file's rounding, compounded along the reflections (the
/// closure gap measures it), and a millionth-tenth of the size is what double precision
/// loses; never more than [`MAX_CONTACT`], a paper's thickness, unless the file itself
/// is no more precise than that (its measured drawing precision, which the report
/// states: an overlap deeper than it still fails).
fn contact_allowance(mesh: &Mesh, folded: &FlatFolded) -> f64 {
    let (lo, hi) = bounds(folded.triangles.as_flattened());
    (crate::tolerance::LAYER_OVERLAP_RELATIVE * (hi - lo).norm())
        .max(
            2.0 * folded.mismatch
                + crate::tolerance::ROUNDING_COMPOUNDED * mesh.coordinate_precision,
        )
        .clamp(1e-300, MAX_CONTACT.max(mesh.coordinate_precision))
}

/// A crease that folds to ±π once folded flat: a hinge between two pieces. An unassigned
/// crease aimed at ±π is one whose side the search finds ([`assign_unassigned`]); an
/// unassigned crease keeps its default target 0 and is no hinge.
pub fn folds_completely(edge: &crate::mesh::Edge) -> bool {
    matches!(
        edge.assignment,
        Assignment::Mountain | Assignment::Valley | Assignment::Unassigned
    ) && folds_flat(edge.target) == Some(true)
}
