//! What scoring produces and is set by: the dash code of each fold type, the scoring
//! settings, strokes and the toolpath they make, and the dash patterns along one span
//! (a full code, or the marks of a stretch too short for one). Shared by `score` (which
//! lays the dashes out) and `clearance` (which trims them), so neither imports the other.

use super::curve::{Cubic, FLATTEN_MM};
use super::layout::Media;
use super::lines::LineKind;
use crate::mesh::Vec2;
use std::collections::BTreeMap;

/// Perforation of a fold line: cut `cut` mm, leave `gap` mm, repeat.
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct DashCode {
    /// Length of each cut dash (mm).
    pub cut: f64,
    /// Length of paper left between dashes (mm).
    pub gap: f64,
}

/// What a fold too short for any dash gets (a machine profile's `short_folds`: nothing,
/// dash or solid).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShortFolds {
    /// No cut: it is named in the report, to be creased by hand.
    #[default]
    Nothing,
    /// One dash of its kind's length (at most the fold's), centred on it.
    Dash,
    /// Cut along its whole length.
    Solid,
}

impl ShortFolds {
    /// How the report says it.
    pub fn name(self) -> &'static str {
        match self {
            ShortFolds::Nothing => "nothing",
            ShortFolds::Dash => "a centred dash",
            ShortFolds::Solid => "a solid cut",
        }
    }
}

/// How each kind of line is cut.
#[derive(Clone, Debug, PartialEq)]
pub struct ScoreSettings {
    /// Per kind: `Some(None)` cuts a solid line, `Some(Some(code))` perforates, a missing
    /// kind is not cut at all.
    pub codes: BTreeMap<LineKind, Option<DashCode>>,
    /// Distance kept from points where three or more creases meet (mm).
    pub clearance: f64,
    /// Shortest dash worth cutting (mm).
    pub min_dash: f64,
    /// What folds too short for any dash get.
    pub short_folds: ShortFolds,
    /// The grid the cutter's job rounds every point to (mm; 0 for a drawing kept exact).
    /// Clearances are kept with [`ScoreSettings::rounding_slack`] to spare, so they still
    /// hold in the job the machine receives.
    pub step_mm: f64,
}

impl Default for ScoreSettings {
    fn default() -> Self {
        ScoreSettings {
            codes: BTreeMap::from([
                (LineKind::Cut, None),
                (LineKind::Mountain, Some(DashCode { cut: 3.0, gap: 1.5 })),
                (LineKind::Valley, Some(DashCode { cut: 1.5, gap: 1.5 })),
            ]),
            clearance: 1.0,
            min_dash: 0.3,
            short_folds: ShortFolds::Nothing,
            step_mm: 0.0,
        }
    }
}

/// How one kind of line is cut: the tool that cuts it and its speed and force. Routing
/// groups strokes by it (one tour per physical tool); the writers send it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolSetting {
    /// Pen or tool number (`SP n`).
    pub pen: u32,
    /// Speed in mm/s (`VS`, sent in cm/s), if the machine takes one.
    pub speed: Option<f64>,
    /// Force (`FS`), in the machine's units, if it takes one.
    pub force: Option<f64>,
}

/// One pen-down segment, straight or bent along a cubic (a dash of a curved crease).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stroke {
    /// What the stroke is for (selects the tool).
    pub kind: LineKind,
    /// Start (mm on the media).
    pub from: Vec2,
    /// End.
    pub to: Vec2,
    /// The sheet line ([`crate::fab::Sheet`]'s `lines`) it cuts or scores: a crease's dashes share it.
    pub line: usize,
    /// The two inner control points of the cubic it follows from `from` to `to`, if it is
    /// not straight.
    pub bend: Option<[Vec2; 2]>,
}

impl Stroke {
    /// A straight stroke.
    pub fn straight(kind: LineKind, from: Vec2, to: Vec2, line: usize) -> Stroke {
        Stroke {
            kind,
            from,
            to,
            line,
            bend: None,
        }
    }

    /// A stroke along `cubic`.
    pub fn along(kind: LineKind, cubic: &Cubic, line: usize) -> Stroke {
        Stroke {
            kind,
            from: cubic.p0,
            to: cubic.p3,
            line,
            bend: Some([cubic.c1, cubic.c2]),
        }
    }

    /// The cubic it follows, if it bends.
    pub fn cubic(&self) -> Option<Cubic> {
        self.bend.map(|[c1, c2]| Cubic {
            p0: self.from,
            c1,
            c2,
            p3: self.to,
        })
    }

    /// Length in mm (along the curve for a bent stroke).
    pub fn length(&self) -> f64 {
        match self.cubic() {
            Some(c) => c.length(),
            None => (self.to - self.from).norm(),
        }
    }

    /// The same stroke drawn the other way.
    pub fn reversed(self) -> Stroke {
        Stroke {
            from: self.to,
            to: self.from,
            bend: self.bend.map(|[c1, c2]| [c2, c1]),
            ..self
        }
    }

    /// The points the pen passes through: its ends if straight, else chords within
    /// [`FLATTEN_MM`] of its curve. What line-only formats (HP-GL, GP-GL, DXF) send and
    /// what the clearance check measures.
    pub fn polyline(&self) -> Vec<Vec2> {
        match self.cubic() {
            Some(c) => c.flatten(FLATTEN_MM),
            None => vec![self.from, self.to],
        }
    }

    /// The part of it between lengths `a` and `b` from its start.
    pub fn piece(&self, a: f64, b: f64) -> Stroke {
        match self.cubic() {
            Some(c) => Stroke::along(self.kind, &c.between_lengths(a, b), self.line),
            None => {
                let len = self.length();
                let u = (self.to - self.from) / len;
                Stroke {
                    from: self.from + u * a,
                    to: self.from + u * b,
                    ..*self
                }
            }
        }
    }

    /// The stroke with `f` applied to its points (exact for an affine `f`).
    pub fn mapped(&self, f: impl Fn(Vec2) -> Vec2) -> Stroke {
        Stroke {
            from: f(self.from),
            to: f(self.to),
            bend: self.bend.map(|[c1, c2]| [f(c1), f(c2)]),
            ..*self
        }
    }
}

/// Ordered strokes for one sheet.
#[derive(Clone, Debug)]
pub struct Toolpath {
    /// The media.
    pub media: Media,
    /// Strokes in cutting order.
    pub strokes: Vec<Stroke>,
}

impl Toolpath {
    /// Pen-up distance from the origin through every stroke and back to the origin (mm).
    pub fn travel(&self) -> f64 {
        let mut at = Vec2::zeros();
        let mut total = 0.0;
        for s in &self.strokes {
            total += (s.from - at).norm();
            at = s.to;
        }
        total + at.norm()
    }

    /// Pen-down length per kind (mm).
    pub fn cut_length(&self) -> BTreeMap<LineKind, f64> {
        let mut out = BTreeMap::new();
        for s in &self.strokes {
            *out.entry(s.kind).or_insert(0.0) += s.length();
        }
        out
    }
}

/// How much longer than every other kind's dash a lone dash of the longer-dashed kind
/// must be for a folder to tell them apart (mm).
pub const DISTINCT_MM: f64 = 0.5;

impl ScoreSettings {
    /// How much closer two strokes can come once every end is rounded to its nearest grid
    /// step: each end moves at most √2/2 step, so every point of a segment does too (a
    /// segment's points are convex combinations of its ends), and the gap between two
    /// segments shrinks by at most twice that.
    pub fn rounding_slack(&self) -> f64 {
        std::f64::consts::SQRT_2 * self.step_mm
    }

    /// For the kind whose dashes are longest (mountains, by default): the shortest lone
    /// dash that still reads as that kind, the other kinds' longest dash plus
    /// [`DISTINCT_MM`]. `None` for other kinds, whose short dashes read as their own.
    pub fn lone_dash_floor(&self, kind: LineKind) -> Option<f64> {
        let own = self.codes.get(&kind).copied().flatten()?;
        let others = self
            .codes
            .iter()
            .filter(|(k, _)| **k != kind)
            .filter_map(|(_, c)| c.map(|c| c.cut))
            .fold(f64::NEG_INFINITY, f64::max);
        (others.is_finite() && own.cut > others).then_some(others + DISTINCT_MM)
    }
}

/// Marks on a stretch of `len` mm too short for a full dash of a kind whose lone dashes
/// must be at least `floor` long: one dash over the stretch if it is that long, else a
/// pair of thirds (a pattern no other kind makes), else nothing (the crease is named).
pub(super) fn short_marks(len: f64, floor: f64, min_dash: f64) -> Vec<(f64, f64)> {
    if len >= floor {
        vec![(0.0, len)]
    } else if len / 3.0 >= min_dash {
        vec![(0.0, len / 3.0), (2.0 * len / 3.0, len)]
    } else {
        Vec::new()
    }
}

/// Dashes `(start, end)` along a span of length `len`, symmetric about its middle.
pub fn dashes(len: f64, code: DashCode, min_dash: f64) -> Vec<(f64, f64)> {
    if len < min_dash {
        return Vec::new();
    }
    let period = code.cut + code.gap;
    let n = (((len + code.gap) / period).floor() as usize).max(1);
    let dash = code.cut.min(len);
    let used = n as f64 * dash + (n - 1) as f64 * code.gap;
    let start = (len - used) / 2.0;
    (0..n)
        .map(|i| {
            let s = start + i as f64 * period;
            (s, s + dash)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dashes_are_symmetric_and_keep_the_code() {
        let code = DashCode { cut: 3.0, gap: 1.5 };
        let d = dashes(20.0, code, 0.3);
        // floor((20 + 1.5) / 4.5) = 4 dashes: 4·3 + 3·1.5 = 16.5, margins 1.75 each side.
        assert_eq!(d.len(), 4);
        assert!((d[0].0 - 1.75).abs() < 1e-12 && (20.0 - d[3].1 - 1.75).abs() < 1e-12);
        for w in d.windows(2) {
            assert!((w[1].0 - w[0].1 - 1.5).abs() < 1e-12);
        }
        assert!(d.iter().all(|(s, e)| (e - s - 3.0).abs() < 1e-12));
    }

    #[test]
    fn short_spans_get_one_short_dash_or_none() {
        let code = DashCode { cut: 3.0, gap: 1.5 };
        assert_eq!(dashes(2.0, code, 0.3), vec![(0.0, 2.0)]);
        assert!(dashes(0.2, code, 0.3).is_empty());
    }
}
