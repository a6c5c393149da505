//! The verification report that gates fabrication: every chosen condition family with its
//! largest and RMS residual, the worst element, the violation count and a verdict; plus
//! Maekawa's count |M − V| = 2, judged where every crease at a vertex folds flat.

use super::assign::{unassigned_interior, with_open_sides, SideSearch};
use super::budget::Budget;
use super::precision::{as_drawn, DrawnPrecision};
use super::rounding::RoundingBounds;
use crate::constraints::{ConstraintSet, Element, Family, Reference};
use crate::mesh::{Assignment, Mesh};
use crate::tolerance::VERIFIED_RESIDUAL;
use serde_json::{json, Value};
use std::f64::consts::PI;
use std::fmt;

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

/// One family's figures.
#[derive(Clone, Debug, PartialEq)]
pub struct FamilyReport {
    /// Family name (a [`Family`] name, or "maekawa").
    pub name: &'static str,
    /// Largest |residual|.
    pub max: f64,
    /// Root mean square residual.
    pub rms: f64,
    /// Where the largest residual is.
    pub worst: Option<String>,
    /// The same element, typed (for pictures that highlight it).
    pub worst_element: Option<Element>,
    /// Rows above tolerance.
    pub violations: usize,
    /// The tolerance applied to every row (radians, or relative for lengths).
    pub tolerance: f64,
    /// The largest allowance for the file's coordinate rounding added to one row's
    /// tolerance (zero for a full-precision file or a tolerance given by the user).
    pub allowance: f64,
    /// Why the tolerance is what it is, for the report.
    pub basis: String,
    /// The threshold at the worst element: the tolerance plus its allowance.
    pub worst_tolerance: f64,
    /// Rows evaluated.
    pub rows: usize,
    /// Whether the family decides the verdict (Maekawa's count is reported only).
    pub gating: bool,
    /// The elements above tolerance, largest first (at most [`LISTED_VIOLATIONS`]).
    pub violators: Vec<String>,
    /// Why a family that would decide the verdict was not judged (its analysis ran out
    /// of budget): the design is neither passed nor failed on it.
    pub undecided: Option<String>,
    /// Whether its residuals are quantities (radians, millimetres, a ratio) that reports
    /// may print; false when a row is a finding with no size, as faces that admit no
    /// layer order (the row's residual is then 1, a count).
    pub measured: bool,
}

/// How many violating elements a report lists per family.
pub const LISTED_VIOLATIONS: usize = 8;

impl FamilyReport {
    /// No row above tolerance.
    pub fn pass(&self) -> bool {
        self.violations == 0
    }
}

/// The result of verifying a design.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// One entry per family checked.
    pub families: Vec<FamilyReport>,
    /// Coordinate rounding of the source file (mm) that the per-element allowances come
    /// from, if any.
    pub precision: f64,
    /// How precisely a crease pattern was drawn, measured on its flat-folded state
    /// ([`super::precision::drawing_precision`]); `None` for a 3D design, a pattern that
    /// does not fold to a flat state, or a tolerance given by the user.
    pub drawn: Option<DrawnPrecision>,
    /// What was not checked, and why.
    pub notes: Vec<String>,
}

/// The one verdict on a design, shown alike by `verify` (text and `--json`), `fab`
/// (which refuses all but [`Verdict::Pass`] without `--force`), `report.json` and the
/// studio's badge.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// Every condition the design claims was judged and holds.
    Pass,
    /// A judged condition fails: which, where, and by how much against what.
    Fail {
        /// The condition (a family name).
        condition: &'static str,
        /// Where its largest residual is.
        at: String,
        /// By how much, when the condition is measured ([`FamilyReport::measured`]).
        excess: Option<Excess>,
    },
    /// Nothing judged fails, but something the design claims could not be judged: what,
    /// and why.
    Undecided {
        /// The condition.
        condition: &'static str,
        /// Why it was not judged.
        why: String,
    },
}

/// How far a failing condition's worst element is from holding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Excess {
    /// Its residual.
    pub value: f64,
    /// The threshold there.
    pub tolerance: f64,
}

impl Verdict {
    /// The process exit status that carries it: 0 pass, 1 fail, 3 undecided (2 is bad
    /// input, before any verdict).
    pub fn exit_code(&self) -> u8 {
        match self {
            Verdict::Pass => 0,
            Verdict::Fail { .. } => 1,
            Verdict::Undecided { .. } => 3,
        }
    }

    /// `PASS`, `FAIL` or `UNDECIDED`.
    pub fn word(&self) -> &'static str {
        match self {
            Verdict::Pass => "PASS",
            Verdict::Fail { .. } => "FAIL",
            Verdict::Undecided { .. } => "UNDECIDED",
        }
    }

    /// Whether the design passes.
    pub fn is_pass(&self) -> bool {
        *self == Verdict::Pass
    }
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Verdict::Pass => write!(f, "PASS"),
            Verdict::Fail {
                condition,
                at,
                excess: Some(Excess { value, tolerance }),
            } => write!(
                f,
                "FAIL — {condition} at {at} ({value:.3e} > {tolerance:.1e})"
            ),
            Verdict::Fail {
                condition,
                at,
                excess: None,
            } => write!(f, "FAIL — {condition} at {at}"),
            Verdict::Undecided { condition, why } => write!(f, "UNDECIDED — {condition}: {why}"),
        }
    }
}

impl Report {
    /// The verdict ([`Verdict`]): a judged condition that fails decides it; else one the
    /// design claims that could not be judged leaves it undecided; else it passes.
    pub fn verdict(&self) -> Verdict {
        if let Some(r) = self.first_failure() {
            return Verdict::Fail {
                condition: r.name,
                at: r.worst.clone().unwrap_or_else(|| "?".into()),
                excess: r.measured.then_some(Excess {
                    value: r.max,
                    tolerance: r.worst_tolerance,
                }),
            };
        }
        match self.undecided() {
            Some(r) => Verdict::Undecided {
                condition: r.name,
                why: r.undecided.clone().unwrap_or_default(),
            },
            None => Verdict::Pass,
        }
    }

    /// Whether the verdict is [`Verdict::Pass`]: every claimed condition judged, and
    /// every judged one holds.
    pub fn pass(&self) -> bool {
        self.verdict().is_pass()
    }

    /// The first family the design claims that was not judged (its analysis ran out of
    /// budget, or its creases do not say how they fold).
    pub fn undecided(&self) -> Option<&FamilyReport> {
        self.families.iter().find(|f| f.undecided.is_some())
    }

    /// The first failing family, for messages.
    pub fn first_failure(&self) -> Option<&FamilyReport> {
        self.families.iter().find(|f| f.gating && !f.pass())
    }

    /// The judged family furthest from holding, measured against its own tolerance, with
    /// the element where it is worst: what a picture of the design marks first.
    pub fn worst_family(&self) -> Option<(&FamilyReport, Element)> {
        self.families
            .iter()
            .filter(|f| f.gating && f.max > 0.0)
            .max_by(|a, b| (a.max / a.tolerance).total_cmp(&(b.max / b.tolerance)))
            .and_then(|f| f.worst_element.map(|e| (f, e)))
    }

    /// `{"pass": bool, "families": {NAME: {"max", "rms", "worst", "violations"}}}`.
    pub fn to_json(&self) -> Value {
        self.to_json_with(&self.verdict())
    }

    /// [`Report::to_json`] with `verdict` as its verdict (see [`Report::text_with`]).
    pub fn to_json_with(&self, verdict: &Verdict) -> Value {
        let families: serde_json::Map<String, Value> = self
            .families
            .iter()
            .map(|f| {
                (
                    f.name.to_string(),
                    json!({"max": f.max, "rms": f.rms, "worst": f.worst, "violations": f.violations,
                           "tolerance": f.tolerance, "rounding_allowance": f.allowance,
                           "tolerance_basis": f.basis, "rows": f.rows, "judged": f.gating,
                           "violators": f.violators, "not_judged_because": f.undecided,
                           "measured": f.measured}),
                )
            })
            .collect();
        let undecided: Vec<&str> = self
            .families
            .iter()
            .filter(|f| f.undecided.is_some())
            .map(|f| f.name)
            .collect();
        json!({"verdict": verdict.word(), "verdict_text": verdict.to_string(), "exit_code": verdict.exit_code(),
               "pass": verdict.is_pass(), "undecided": undecided, "families": families, "coordinate_precision_mm": self.precision,
               "drawn_precision_mm": self.drawn.map(|d| d.precision), "drawn_exactly": self.drawn.map(|d| d.exact),
               "notes": self.notes})
    }
}

impl Report {
    /// The report as text with `more` lines (a check judged beside it, as the path from
    /// flat) before its verdict line, and `verdict` there: the report's own, or one that
    /// also weighs what `more` found, so no failing line is ever shown beside a PASS.
    pub fn text_with(&self, more: &[String], verdict: &Verdict) -> String {
        let mut text = String::new();
        self.write_body(&mut text)
            .expect("writing to a String cannot fail");
        for line in more {
            text.push_str(line);
            text.push('\n');
        }
        text.push_str(&self.verdict_text(verdict));
        text
    }

    /// The verdict line, and for a failing condition of the report's own, where it fails.
    fn verdict_text(&self, verdict: &Verdict) -> String {
        match verdict {
            Verdict::Pass => "verdict: PASS\n".into(),
            undecided @ Verdict::Undecided { .. } => {
                format!("verdict: {undecided}; every condition judged passes\n")
            }
            fail @ Verdict::Fail { .. } => {
                let mut text = format!("verdict: {fail}\n");
                for failing in self.families.iter().filter(|r| r.gating && !r.pass()) {
                    let more = failing.violations.saturating_sub(failing.violators.len());
                    let tail = if more > 0 {
                        format!(" and {more} more")
                    } else {
                        String::new()
                    };
                    text.push_str(&format!(
                        "  {} fails at {}{tail}\n",
                        failing.name,
                        failing.violators.join(", ")
                    ));
                }
                text
            }
        }
    }

    /// Everything but the verdict: the table, notes, the drawing's precision, the
    /// tolerances.
    fn write_body(&self, f: &mut impl fmt::Write) -> fmt::Result {
        writeln!(
            f,
            "{:<20} {:>6} {:>10} {:>10} {:>6}  worst",
            "condition", "rows", "max", "rms", "fail"
        )?;
        for r in &self.families {
            // A family reported but not judged shows its count in brackets: it never
            // reads as a failure beside the verdict.
            let fail = if r.gating {
                r.violations.to_string()
            } else {
                format!("({})", r.violations)
            };
            // A finding without a size (faces that admit no order) has no figures.
            let (max, rms) = if r.measured {
                (format!("{:.3e}", r.max), format!("{:.3e}", r.rms))
            } else {
                ("-".into(), "-".into())
            };
            writeln!(
                f,
                "{:<20} {:>6} {max:>10} {rms:>10} {fail:>6}  {}",
                r.name,
                r.rows,
                r.worst.as_deref().unwrap_or("-")
            )?;
        }
        if self.families.iter().any(|r| !r.gating) {
            writeln!(
                f,
                "(n): reported, not judged: it does not decide the verdict"
            )?;
        }
        for note in &self.notes {
            writeln!(f, "note: {note}")?;
        }
        match self.drawn {
            Some(d) if d.exact => writeln!(
                f,
                "drawing: exact (folded, its corners meet to within {:.1e} mm)",
                d.precision
            )?,
            Some(d) => writeln!(
                f,
                "drawing: drawn to within {:.1e} mm (folded, corners meant to meet lie that near; \
                 the tolerances below allow for it)",
                d.precision
            )?,
            None => {}
        }
        // One line per distinct basis, naming the conditions it applies to.
        let mut bases: Vec<(&str, Vec<&str>)> = Vec::new();
        for r in self.families.iter().filter(|r| !r.basis.is_empty()) {
            match bases.iter_mut().find(|(b, _)| *b == r.basis) {
                Some((_, names)) => names.push(r.name),
                None => bases.push((&r.basis, vec![r.name])),
            }
        }
        for (basis, names) in bases {
            writeln!(f, "tolerance ({}): {basis}", names.join(", "))?;
        }
        Ok(())
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text_with(&[], &self.verdict()))
    }
}

fn summarise(name: &'static str, values: &[(f64, Element)], tolerance: f64) -> FamilyReport {
    summarise_with(name, values, tolerance, |_| 0.0)
}

/// [`summarise`] with an extra allowance per element.
fn summarise_with(
    name: &'static str,
    values: &[(f64, Element)],
    tolerance: f64,
    allowance: impl Fn(Element) -> f64,
) -> FamilyReport {
    let mut widest: f64 = 0.0;
    let mut worst_tolerance = tolerance;
    let mut max = 0.0;
    let mut worst = None;
    let mut sum2 = 0.0;
    let mut violations = 0;
    let mut over: Vec<(f64, &Element)> = Vec::new();
    for (v, label) in values {
        let a = v.abs();
        sum2 += a * a;
        let extra = allowance(*label);
        widest = widest.max(extra);
        if a > tolerance + extra || a.is_nan() {
            violations += 1;
            over.push((if a.is_nan() { f64::INFINITY } else { a }, label));
        }
        if a > max || a.is_nan() {
            max = a;
            worst = Some(*label);
            worst_tolerance = tolerance + extra;
        }
    }
    over.sort_by(|x, y| y.0.total_cmp(&x.0));
    FamilyReport {
        violators: over
            .iter()
            .take(LISTED_VIOLATIONS)
            .map(|(a, l)| format!("{l} ({a:.1e})"))
            .collect(),
        name,
        max,
        worst: worst.map(|w| w.to_string()),
        worst_element: worst,
        rms: if values.is_empty() {
            0.0
        } else {
            (sum2 / values.len() as f64).sqrt()
        },
        violations,
        tolerance,
        allowance: widest,
        basis: String::new(),
        worst_tolerance,
        rows: values.len(),
        gating: true,
        undecided: None,
        measured: true,
    }
}

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

/// A crease pattern whose creases are all unassigned (`U`, Flat-Folder's "unassigned"
/// patterns) says only where the paper folds: its claim is that some mountain/valley
/// folds it flat. The layer search is run with those creases' sides free
/// ([`super::layers::assign_unassigned`]); the pattern is verified with the sides found
/// (a note says so), fails naming the faces no assignment orders, or is undecided when the
/// search could not finish. `None` for any other design.
fn verify_assigning(
    mesh: &Mesh,
    conditions: Option<&ConstraintSet>,
    tol: Tolerances,
    budget: &Budget,
) -> Option<Report> {
    let (assigned, mountains, valleys) = match super::assign::assign_sides(mesh, budget)? {
        SideSearch::Found {
            mesh,
            mountains,
            valleys,
        } => (*mesh, mountains, valleys),
        SideSearch::NoOrder { conflict, open } => {
            let mut report = verify_as_drawn(mesh, conditions, tol, budget);
            report.families.retain(|f| f.name != "assignment");
            let mut row = conflict_report(&conflict);
            row.basis =
                format!("no mountain/valley for the {open} unassigned creases gives a layer order");
            report.families.push(row);
            return Some(report);
        }
        SideSearch::Stopped(e) => {
            let mut report = verify_as_drawn(mesh, conditions, tol, budget);
            if let Some(row) = report.families.iter_mut().find(|f| f.name == "assignment") {
                let why = format!("the search for their sides stopped: {e}");
                row.basis = format!("not judged: {why}");
                row.undecided = Some(why);
            }
            return Some(report);
        }
    };
    let mut report = verify_as_drawn(&assigned, conditions, tol, budget);
    report.notes.push(format!(
        "the {} unassigned creases were given the sides of a layer order found with them free: \
         {mountains} mountain(s), {valleys} valley(s); the verdict is the assigned pattern's",
        mountains + valleys
    ));
    Some(report)
}

/// The flat-folded states of a crease pattern ([`super::layers::count_states`]): each
/// independent group's count, up to `cap` a group, or `None` when it has none. A pattern
/// of only unassigned creases counts the states of every side they may take (as
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
    let mut notes = Vec::new();
    if let Some(r) = families
        .iter()
        .find(|r| r.name == EMPIRICAL && r.violations > 0)
    {
        notes.push(format!(
            "eq. (7, 8), the paper's empirical condition for a locally closed vertex, does not hold at \
             {} sector(s) (largest at {}): designs keep it while they are varied, but a flat fold \
             does not need it, and it does not decide the verdict (eq. 6 and the layer order do)",
            r.violations,
            r.worst.as_deref().unwrap_or("?")
        ));
    }
    if set.families.contains(&Family::FlatFoldability) {
        families.extend(maekawa(mesh));
    }
    if mesh.has_3d() {
        families.push(self_intersection(mesh));
    }
    // The layer order is the crease pattern's: whether it folds flat. A design whose 3D
    // form lies in a plane (a flat-folded frame, or the unfolded sheet) is judged so and
    // fails without one. A freeform 3D design is judged on its crease pattern folded flat
    // too, but reported, not gating: it folds to its own form (the self-intersection row
    // judges that), and its flat state is a property the maker should know of, not a bar
    // to cutting it.
    let asked = set.families.contains(&Family::LayerOrder);
    let wants_flat =
        conditions.is_none() || asked || set.families.contains(&Family::FlatFoldability);
    if wants_flat {
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
        families.extend(report);
    }
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

/// The row of a crease pattern whose creases are all unassigned, as drawn: undecided
/// ([`verify_assigning`] replaces it with the verdict of the sides it finds). `None` for
/// a pattern with mountains or valleys (its `U` lines are free, as Resch's tucks), or a
/// 3D design (its creases fold to the form it has).
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

/// The layer-order problem's cap (pairs and constraints) when only reported, for a
/// freeform 3D design.
const FREEFORM_LAYER_CAP: usize = 2_000_000;

/// The time the freeform report may take within a deadline (the studio's live analysis).
const FREEFORM_LIVE: std::time::Duration = std::time::Duration::from_millis(150);

/// Layer order of the flat-folded state ([`super::layers`]), judged when every crease
/// folds to ±π and the faces close up around every vertex (else the local conditions
/// already say why it cannot fold flat): one row, failing with the faces in conflict.
fn layer_order_report(
    mesh: &Mesh,
    budget: &Budget,
    freeform: bool,
    only_reported: bool,
    claimed: bool,
) -> Option<FamilyReport> {
    use super::layers::{
        layer_order_naming_within, LayerError, LayerOrder, ADVISORY_SHRINK_WORK, SHRINK_WORK,
    };
    let folded = super::flat_folded(mesh, None).ok()?;
    let closes = folded.layers_close();
    let creases = mesh.edges().iter().any(|e| e.assignment.is_folded());
    if !creases {
        return None;
    }
    // Faces that do not close up leave no flat-folded state to order. The local
    // conditions usually fail there and say why; where they hold within the drawing's
    // allowances, nothing about the layers was shown, and a claim to fold flat is
    // undecided, not passed.
    if !closes && folded.open_seam {
        return Some(open_tube_report(&folded, only_reported));
    }
    if !closes {
        let why = format!(
            "folded flat, the faces around vertex {} leave a gap of {:.1e} mm, past the {:.1e} mm \
             the drawing explains: there is no flat-folded state to order",
            folded.worst_vertex.unwrap_or(0),
            folded.mismatch,
            folded.tolerance
        );
        return Some(FamilyReport {
            gating: false,
            basis: format!("not judged: {why}"),
            undecided: (!only_reported && !freeform).then_some(why),
            ..summarise("layer-order", &[], 0.0)
        });
    }
    // A pattern drawn at partial folds (Origami Simulator's 90°) does not claim to fold
    // flat: reported, not judged, as Maekawa there. A freeform design's creases stand
    // at partial folds by design; its targets (all ±π, or there is no flat state) are
    // its claim.
    if let Some(e) = super::layers::partial_crease(mesh).filter(|_| !freeform) {
        let edge = &mesh.edges()[e];
        let why = format!(
            "crease {e} is drawn at {:.0}°, a partial fold: the pattern does not say it folds flat",
            crate::io::fold::angle_to_fold(edge.fold_angle)
        );
        return Some(FamilyReport {
            gating: false,
            basis: format!("not judged: {why}"),
            undecided: claimed.then_some(why),
            ..summarise("layer-order", &[], 0.0)
        });
    }
    // Reported, not gating, for a freeform design: a third of the cap, and under a
    // deadline (the studio's) at most FREEFORM_LIVE of it, so verifying a large 3D design
    // costs little more than it did before its flat state was judged and the studio's
    // verdict is not held up by it.
    let now = std::time::Instant::now();
    let reported = Budget {
        max_constraints: budget.max_constraints.min(FREEFORM_LAYER_CAP),
        // Only a live analysis (one that can be cancelled: the studio's) holds the
        // report to FREEFORM_LIVE; the command line's deadline stands as given.
        deadline: budget.deadline.map(|(at, given)| match budget.cancel {
            Some(_) => (at.min(now + FREEFORM_LIVE), given.min(FREEFORM_LIVE)),
            None => (at, given),
        }),
        ..budget.clone()
    };
    let (budget, naming) = if only_reported {
        (&reported, ADVISORY_SHRINK_WORK)
    } else {
        (budget, SHRINK_WORK)
    };
    let mut report = match layer_order_naming_within(mesh, budget, naming) {
        Ok(LayerOrder::Found(orders)) => FamilyReport {
            rows: orders.len(),
            ..summarise("layer-order", &[], 0.0)
        },
        Ok(LayerOrder::Conflict(c)) => conflict_report(&c),
        Err(LayerError::OverBudget(e)) => FamilyReport {
            gating: false,
            basis: format!("not judged: {e}"),
            undecided: (!only_reported).then(|| e.to_string()),
            ..summarise("layer-order", &[], 0.0)
        },
        // The search stopped, or the folded state could not be set up: nothing was
        // shown either way, so a claim of folding flat is left undecided.
        Err(e) => FamilyReport {
            gating: false,
            basis: format!("not decided: {e}"),
            undecided: (!only_reported).then(|| format!("not decided: {e}")),
            ..summarise("layer-order", &[], 0.0)
        },
    };
    if report.basis.is_empty() {
        report.basis = "one order of every overlapping pair of faces once folded flat, or the faces that admit none".into();
    }
    if only_reported {
        report.gating = false;
        report.basis = format!(
            "{}; the crease pattern folded flat, reported: a freeform design folds to its own form",
            report.basis
        );
    }
    Some(report)
}

/// The failing layer-order row of a tube whose seam does not close once folded flat: the
/// reflections of the creases round the tube do not compose to the identity, so no flat
/// state exists (a proof, not a search), though every vertex may fold flat on its own.
fn open_tube_report(folded: &super::FlatFolded, only_reported: bool) -> FamilyReport {
    let vertex = folded.worst_vertex.unwrap_or(0);
    let mut r = summarise(
        "layer-order",
        &[(folded.mismatch, Element::Vertex(vertex))],
        folded.tolerance,
    );
    r.violators = vec![format!(
        "folded flat, the tube does not close: its seam's two sides land {:.3} mm apart at vertex \
         {vertex}, though every vertex folds flat on its own",
        folded.mismatch
    )];
    r.basis = format!(
        "the tube's strip folded flat closes round the tube within {:.1e} mm",
        folded.tolerance
    );
    r.gating = !only_reported;
    r
}

/// The failing layer-order row of faces that admit no order.
fn conflict_report(c: &super::layers::LayerConflict) -> FamilyReport {
    let faces = &c.faces;
    let element = Element::Faces(faces[0], *faces.get(1).unwrap_or(&faces[0]));
    let mut r = summarise("layer-order", &[(1.0, element)], 0.0);
    r.measured = false;
    let names: Vec<String> = faces.iter().map(|f| f.to_string()).collect();
    // A vertex of 2,000 creases names 2,000 faces: the table shows the first few.
    r.worst = Some(if names.len() > 12 {
        format!(
            "faces {}, … ({} in all)",
            names[..12].join(", "),
            names.len()
        )
    } else {
        format!("faces {}", names.join(", "))
    });
    r.violators = vec![c.to_string()];
    r.basis =
        "one order of every overlapping pair of faces once folded flat, or the faces that admit none"
            .into();
    r
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
