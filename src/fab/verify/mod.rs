//! The verification report that gates fabrication: every chosen condition family with its
//! largest and RMS residual, the worst element, the violation count and a verdict; plus
//! Maekawa's count |M − V| = 2, judged where every crease at a vertex folds flat.

use super::assign::{unassigned_interior, with_open_sides, SideSearch};
use super::budget::Budget;
use super::precision::as_drawn;
use super::rounding::RoundingBounds;
use crate::constraints::{ConstraintSet, Element, Family, Reference};
use crate::mesh::{Assignment, Mesh};
use crate::tolerance::VERIFIED_RESIDUAL;
use std::f64::consts::PI;

/// Pass thresholds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// Angle conditions, radians.
    pub angle: f64,
    /// Length conditions, relative.
    pub length: f64,
    /// Add to each element's threshold what the file's coordinate rounding can explain
    /// there ([`RoundingBounds`]); off when the user gave a tolerance.
    pub rounding: bool,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            angle: VERIFIED_RESIDUAL,
            length: VERIFIED_RESIDUAL,
            rounding: true,
        }
    }
}

impl Tolerances {
    /// One tolerance for every condition, used exactly as given (`verify --tol`).
    pub fn exactly(t: f64) -> Tolerances {
        Tolerances {
            angle: t,
            length: t,
            rounding: false,
        }
    }
}

mod layer_order;
mod report;

use layer_order::{conflict_report, layer_order_report};
use report::{summarise, summarise_with};

pub use report::{Excess, FamilyReport, Report, Verdict, LISTED_VIOLATIONS};

/// Verifies a design against a set of conditions (its own default set when `None`).
pub fn verify(mesh: &Mesh, conditions: Option<&ConstraintSet>, tol: Tolerances) -> Report {
    verify_within(mesh, conditions, tol, &Budget::default())
}

/// [`verify`] with the layer order judged within `budget`: past it, the layer order is
/// reported as not judged (with the budget's advice) and does not decide the verdict.
pub fn verify_within(
    mesh: &Mesh,
    conditions: Option<&ConstraintSet>,
    tol: Tolerances,
    budget: &Budget,
) -> Report {
    verify_assigning(mesh, conditions, tol, budget)
        .unwrap_or_else(|| verify_as_drawn(mesh, conditions, tol, budget))
}

/// A crease pattern with unassigned creases (`U`, Flat-Folder's "unassigned" patterns,
/// all or some of its creases: [`super::assign::unassigned_interior`]) says only where
/// the paper folds there: its claim is that some mountain/valley folds it flat. The
/// layer search is run with those creases' sides free
/// ([`super::layers::assign_unassigned`]); the pattern is verified with the sides found
/// (a note says so), fails naming the faces no assignment orders, or is undecided when
/// the search could not finish. `None` for any other design.
fn verify_assigning(
    mesh: &Mesh,
    conditions: Option<&ConstraintSet>,
    tol: Tolerances,
    budget: &Budget,
) -> Option<Report> {
    let search = super::assign::assign_sides(mesh, budget)?;
    Some(verify_searched(mesh, &search, conditions, tol, budget))
}

/// [`verify_within`] of a crease pattern whose unassigned creases' sides were already
/// searched for (`search`, [`super::assign_sides`]'s answer), so that a caller that
/// needs the search itself (`fab`, which makes the assigned pattern) does not run it
/// twice, and reports what `verify` reports.
pub fn verify_searched(
    mesh: &Mesh,
    search: &SideSearch,
    conditions: Option<&ConstraintSet>,
    tol: Tolerances,
    budget: &Budget,
) -> Report {
    let (assigned, mountains, valleys) = match search {
        SideSearch::Found {
            mesh,
            mountains,
            valleys,
        } => (mesh.as_ref(), *mountains, *valleys),
        // Judged with its unassigned creases folded, their side open (Kawasaki's sums
        // and the rest hold or fail as for any side); the layer order is the search's.
        SideSearch::NoOrder { conflict, open } => {
            let mut row = conflict_report(conflict);
            row.basis =
                format!("no mountain/valley for the {open} unassigned creases gives a layer order");
            let mut report = verify_with_sides_open(mesh, conditions, tol, Some(row));
            report.families.retain(|f| f.name != "assignment");
            return report;
        }
        SideSearch::Stopped(e) => {
            let mut report = verify_with_sides_open(mesh, conditions, tol, None);
            if let Some(row) = report.families.iter_mut().find(|f| f.name == "assignment") {
                let why = format!("the search for their sides stopped: {e}");
                row.basis = format!("not judged: {why}");
                row.undecided = Some(why);
            }
            return report;
        }
    };
    let mut report = verify_as_drawn(assigned, conditions, tol, budget);
    report.notes.push(format!(
        "the {} unassigned creases were given the sides of a layer order found with them free: \
         {mountains} mountain(s), {valleys} valley(s); the verdict is the assigned pattern's",
        mountains + valleys
    ));
    report
}

/// The report of a pattern whose unassigned creases found no sides, judged with them
/// folded, their side open, and `layer_order` as its layer-order row: the search for
/// the sides has already judged it (or stopped), and is not run again.
fn verify_with_sides_open(
    mesh: &Mesh,
    conditions: Option<&ConstraintSet>,
    tol: Tolerances,
    layer_order: Option<FamilyReport>,
) -> Report {
    let open = unassigned_interior(mesh).unwrap_or_default();
    let free = with_open_sides(mesh, &open);
    verify_drawn_with(&free, conditions, tol, |_, _| (layer_order, Vec::new()))
}

/// The flat-folded states of a crease pattern ([`super::layers::count_states`]): each
/// independent group's count, up to `cap` a group, or `None` when it has none. A pattern
/// with unassigned creases counts the states of every side they may take (as
/// Flat-Folder does).
pub fn count_flat_states(
    mesh: &Mesh,
    budget: &Budget,
    cap: u64,
) -> Result<Option<Vec<super::GroupCount>>, super::LayerError> {
    let (_, measured) = as_drawn(mesh);
    let mesh = measured.as_ref();
    match unassigned_interior(mesh) {
        Some(open) => super::count_states(&with_open_sides(mesh, &open), budget, cap),
        None => super::count_states(mesh, budget, cap),
    }
}

/// [`verify_within`] of the design as its file draws it.
fn verify_as_drawn(
    mesh: &Mesh,
    conditions: Option<&ConstraintSet>,
    tol: Tolerances,
    budget: &Budget,
) -> Report {
    verify_drawn_with(mesh, conditions, tol, |mesh, set| {
        flat_state(mesh, conditions, set, budget)
    })
}

/// [`verify_as_drawn`] with the layer-order row and its notes from `flat`, given the
/// design as measured and its set of conditions.
fn verify_drawn_with(
    mesh: &Mesh,
    conditions: Option<&ConstraintSet>,
    tol: Tolerances,
    flat: impl FnOnce(&Mesh, &ConstraintSet) -> (Option<FamilyReport>, Vec<String>),
) -> Report {
    let (drawn, measured) = if tol.rounding {
        as_drawn(mesh)
    } else {
        (None, std::borrow::Cow::Borrowed(mesh))
    };
    let mesh = measured.as_ref();
    let reference = Reference::new(mesh);
    let default;
    let set = match conditions {
        Some(s) => s,
        None => {
            default = ConstraintSet::default_for(&reference);
            &default
        }
    };
    let rows = set.evaluate_values(mesh, &reference, mesh.positions());
    let bounds = tol.rounding.then(|| RoundingBounds::new(mesh)).flatten();
    let precision = bounds.as_ref().map_or(0.0, |b| b.precision);
    let mut families: Vec<FamilyReport> = set
        .families
        .iter()
        .filter(|&&f| f != Family::LayerOrder)
        .flat_map(|&family| family_reports(mesh, family, &rows, tol, bounds.as_ref()))
        .collect();
    let mut notes: Vec<String> = empirical_note(&families).into_iter().collect();
    if set.families.contains(&Family::FlatFoldability) {
        families.extend(maekawa(mesh));
    }
    if mesh.has_3d() {
        families.push(self_intersection(mesh));
    }
    let (layer_order, flat_notes) = flat(mesh, set);
    families.extend(layer_order);
    notes.extend(flat_notes);
    families.extend(unassigned_creases(mesh));
    if conditions.is_none() && !set.families.contains(&Family::FlatFoldability) {
        notes.push(match reference.odd_vertex {
            Some(v) => format!(
                "flat-foldability not checked: vertex {v} has an odd number of folded creases, so this \
                 assignment cannot fold flat (check it anyway with --conditions)"
            ),
            None => "flat-foldability not checked: no vertex has folded creases".to_string(),
        });
    }
    Report {
        families,
        precision,
        drawn,
        notes,
    }
}

/// The layer-order row of the design's flat-folded state, when flat folding is wanted,
/// and the notes it calls for (no flat state to judge, a freeform design whose crease
/// pattern cannot fold flat).
fn flat_state(
    mesh: &Mesh,
    conditions: Option<&ConstraintSet>,
    set: &ConstraintSet,
    budget: &Budget,
) -> (Option<FamilyReport>, Vec<String>) {
    // The layer order is the crease pattern's: whether it folds flat. A design whose 3D
    // form lies in a plane (a flat-folded frame, or the unfolded sheet) is judged so and
    // fails without one. A freeform 3D design is judged on its crease pattern folded flat
    // too, but reported, not gating: it folds to its own form (the self-intersection row
    // judges that), and its flat state is a property the maker should know of, not a bar
    // to cutting it.
    let asked = set.families.contains(&Family::LayerOrder);
    let wants_flat =
        conditions.is_none() || asked || set.families.contains(&Family::FlatFoldability);
    let mut notes = Vec::new();
    if !wants_flat {
        return (None, notes);
    }
    // Named among the conditions, the order gates a freeform design too.
    let freeform = mesh.has_3d() && !lies_in_a_plane(mesh);
    let only_reported = freeform && !asked;
    // Flat folding named among the conditions is a claim: what cannot be judged of it
    // leaves the verdict undecided.
    let claimed = conditions.is_some();
    let report = layer_order_report(mesh, budget, freeform, only_reported, claimed);
    if report.is_none() {
        notes.extend(flat_state_unjudged(mesh));
    }
    if let Some(r) = report
        .as_ref()
        .filter(|r| only_reported && r.violations > 0)
    {
        notes.push(format!(
            "this design folds to its 3D form but its crease pattern cannot fold flat: {}",
            r.violators.join("; ")
        ));
    }
    (report, notes)
}

/// The note on the paper's empirical condition (eq. 7, 8) where it does not hold: it is
/// reported, never judged.
fn empirical_note(families: &[FamilyReport]) -> Option<String> {
    let r = families
        .iter()
        .find(|r| r.name == EMPIRICAL && r.violations > 0)?;
    Some(format!(
        "eq. (7, 8), the paper's empirical condition for a locally closed vertex, does not hold at \
         {} sector(s) (largest at {}): designs keep it while they are varied, but a flat fold \
         does not need it, and it does not decide the verdict (eq. 6 and the layer order do)",
        r.violations,
        r.worst.as_deref().unwrap_or("?")
    ))
}

/// A design whose creases all fold to ±180° claims a flat-folded state; where none could
/// be built to judge (a tube that cannot be unrolled into its strip), the report says so
/// rather than nothing.
fn flat_state_unjudged(mesh: &Mesh) -> Option<String> {
    let mut folded = mesh.edges().iter().filter(|e| e.assignment.is_folded());
    let first = folded.next()?;
    let all_flat = std::iter::once(first)
        .chain(folded)
        .all(|e| crate::constraints::folds_flat(e.target) == Some(true));
    if !all_flat {
        return None;
    }
    let why = match super::flat_folded(mesh, None) {
        Err(e) => e.to_string(),
        Ok(_) => "its crease pattern could not be folded flat to order".to_string(),
    };
    Some(format!(
        "every crease of this design folds to ±180°, but whether it folds flat was not judged: {why}"
    ))
}

/// The row of a crease pattern with unassigned creases, as drawn: undecided
/// ([`verify_assigning`] replaces it with the verdict of the sides it finds). `None` for
/// a pattern with a partial fold (its `U` lines are free, as Resch's tucks), or a 3D
/// design (its creases fold to the form it has).
fn unassigned_creases(mesh: &Mesh) -> Option<FamilyReport> {
    let unassigned = unassigned_interior(mesh)?;
    let first = unassigned[0];
    let why = format!(
        "{} crease(s) are unassigned (U, the first edge {first}): whether the pattern folds flat \
         depends on the mountain or valley they are given",
        unassigned.len()
    );
    Some(FamilyReport {
        rows: unassigned.len(),
        gating: false,
        basis: format!("not judged: {why}"),
        undecided: Some(why),
        ..summarise("assignment", &[], 0.0)
    })
}

/// Faces of the 3D form that pass through each other ([`super::intersect`]): one row per
/// crossing pair, its residual how deep the piercing edge reaches through (mm). Any
/// crossing fails; contact does not count.
fn self_intersection(mesh: &Mesh) -> FamilyReport {
    let values: Vec<(f64, Element)> = super::self_intersections(mesh)
        .into_iter()
        .map(|c| (c.depth, Element::Faces(c.faces.0, c.faces.1)))
        .collect();
    let mut report = summarise("self-intersection", &values, 0.0);
    // Rows are the crossings found, not the pairs examined.
    report.rows = mesh.faces().len();
    report.basis = format!(
        "any crossing deeper than {:.0e} of the design's size (contact is not a crossing)",
        crate::tolerance::SELF_CONTACT_RELATIVE
    );
    report
}

/// Whether the 3D form lies in one plane, to a millionth of its diagonal plus what the
/// file's rounding explains: then it is a flat state of the crease pattern (folded flat,
/// or not folded), and the pattern's layer order is the design's.
fn lies_in_a_plane(mesh: &Mesh) -> bool {
    let (lo, hi) = mesh.bounding_box();
    let tolerance = crate::tolerance::closure_mm((hi - lo).norm(), mesh.coordinate_precision);
    crate::geometry::out_of_plane(mesh.positions().iter().copied()) <= tolerance
}

/// The name under which the paper's empirical inequalities (7, 8) are reported.
const EMPIRICAL: &str = "empirical-inequality";

/// One family's report ([`family_report`]); the angular inequalities give two: eq. (6),
/// Kawasaki's necessary condition, judged as `angular-inequality`, and eq. (7, 8), the
/// paper's empirical condition, reported but not judged as `empirical-inequality`.
fn family_reports(
    mesh: &Mesh,
    family: Family,
    rows: &crate::constraints::Rows,
    tol: Tolerances,
    bounds: Option<&RoundingBounds>,
) -> Vec<FamilyReport> {
    let values = rows
        .residuals
        .iter()
        .zip(&rows.labels)
        .filter(|(_, (f, _))| *f == family)
        .map(|(r, (_, el))| (*r, *el));
    if family != Family::AngularInequality {
        return vec![family_report(
            mesh,
            family,
            family.name(),
            values.collect(),
            tol,
            bounds,
        )];
    }
    let (empirical, necessary): (Vec<_>, Vec<_>) = values.partition(|(_, el)| el.is_empirical());
    let mut advice = family_report(mesh, family, EMPIRICAL, empirical, tol, bounds);
    advice.gating = false;
    advice.basis = format!(
        "reported, not judged: the paper's empirical condition (eq. 7, 8); {}",
        advice.basis
    );
    vec![
        family_report(mesh, family, family.name(), necessary, tol, bounds),
        advice,
    ]
}

/// One family's rows summarised against its tolerance (radians, or relative or mm for
/// lengths), each element's allowance for the file's rounding added when `bounds` has
/// one, with the basis of the tolerance stated for the report.
fn family_report(
    mesh: &Mesh,
    family: Family,
    name: &'static str,
    values: Vec<(f64, Element)>,
    tol: Tolerances,
    bounds: Option<&RoundingBounds>,
) -> FamilyReport {
    let (t, unit) = match family {
        Family::Coincidence => (tol.length, "mm"),
        f if f.is_length() => (tol.length, "relative"),
        _ => (tol.angle, "rad"),
    };
    let mut report = summarise_with(name, &values, t, |el| {
        bounds.map_or(0.0, |b| b.allowance(mesh, family, el))
    });
    report.basis = if !tol.rounding {
        format!("{t:.0e} {unit}, as given")
    } else if let Some(b) = bounds {
        let widest = if report.rows > 0 {
            format!(", up to {:.1e}", report.allowance)
        } else {
            String::new()
        };
        format!(
            "{t:.0e} {unit} plus each element's bound from the file's precision (±{:.1e} mm){widest}",
            b.precision
        )
    } else {
        format!("{t:.0e} {unit} (full-precision coordinates)")
    };
    report
}
/// Maekawa's theorem at every interior vertex that folds flat as drawn: the fold
/// angles of a flat-folded vertex sum to ±2π, |M − V| = 2 for simple creases (merged
/// creases of §4 count by their multiple of π). Residual |Σ target| / π − 2, in creases.
/// A vertex is judged when every crease at it targets an odd multiple of π (facet lines,
/// target 0, do not count) and, in a file with only a crease pattern, is also drawn at that
/// angle: a pattern that states partial folds (Origami Simulator's 90°) does not claim to
/// fold flat, so its vertices are reported under `maekawa-partial`, not judged.
fn maekawa(mesh: &Mesh) -> Vec<FamilyReport> {
    let topo = mesh.topology();
    let (mut judged, mut partial) = (Vec::new(), Vec::new());
    for (v, fan) in topo.fans.iter().enumerate() {
        if fan.boundary || fan.spokes.is_empty() {
            continue;
        }
        let (mut sum, mut creases, mut is_partial) = (0.0, 0, false);
        for &e in &fan.spokes {
            let edge = &mesh.edges()[e];
            match edge.assignment {
                Assignment::Mountain | Assignment::Valley => {
                    let odd = crate::constraints::folds_flat(edge.target) == Some(true);
                    let drawn =
                        mesh.has_3d() || (edge.fold_angle - edge.target).abs() < VERIFIED_RESIDUAL;
                    is_partial |= !(odd && drawn);
                    sum += edge.target;
                    creases += 1;
                }
                Assignment::Flat | Assignment::Join if edge.target == 0.0 => {}
                _ => is_partial = true,
            }
        }
        if creases == 0 {
            continue;
        }
        let value = ((sum.abs() / PI) - 2.0, Element::Vertex(v));
        if is_partial {
            partial.push(value);
        } else {
            judged.push(value);
        }
    }
    let mut out = vec![summarise("maekawa", &judged, 0.5)];
    if !partial.is_empty() {
        out.push(FamilyReport {
            gating: false,
            ..summarise("maekawa-partial", &partial, 0.5)
        });
    }
    out
}
