//! What verification says: each condition family's figures ([`FamilyReport`]), the
//! report that gathers them ([`Report`]) and the one verdict drawn from it ([`Verdict`]),
//! as text and as JSON.

use crate::constraints::Element;
use crate::fab::precision::DrawnPrecision;
use serde_json::{json, Value};
use std::fmt;

/// One family's figures.
#[derive(Clone, Debug, PartialEq)]
pub struct FamilyReport {
    /// Family name (a [`Family`](crate::constraints::Family) name, or "maekawa").
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

    /// The largest residual as a figure reports may print: `None` for a finding without a
    /// size (faces that admit no order, see [`FamilyReport::measured`]).
    pub fn figure(&self) -> Option<f64> {
        self.measured.then_some(self.max)
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
    /// ([`crate::fab::precision::drawing_precision`]); `None` for a 3D design, a pattern that
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
                excess: r.figure().map(|value| Excess {
                    value,
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

pub(super) fn summarise(
    name: &'static str,
    values: &[(f64, Element)],
    tolerance: f64,
) -> FamilyReport {
    summarise_with(name, values, tolerance, |_| 0.0)
}

/// [`summarise`] with an extra allowance per element.
pub(super) fn summarise_with(
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
