//! A tube's strip on the sheet (issue 31): the tube is cut open along its seam
//! ([`crate::mesh::Mesh::cut_open`]), and one side of the seam gets a glue tab: a strip of
//! paper beyond the seam, its hinge scored as a valley (it folds in under the other
//! side), its outline cut, its ends chamfered ([`END_LEAN`]) so the tabs of folds meeting
//! at the rims do not collide.

use super::advice::{Advice, FabOption};
use super::lines::{CreaseLine, LineKind};
use crate::mesh::{distance_to_segment, Vec2};

/// The glue tab of a strip, in the strip's flat coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct GlueTab {
    /// The seam side it hangs from, rim to rim (the hinge), paper on its left.
    pub hinge: Vec<Vec2>,
    /// Its cut outline from the hinge's first point round to its last: first point,
    /// chamfer, outer edge, chamfer, last point.
    pub outline: [Vec2; 4],
}

/// The tab of width `width` (mm) on the right of the polyline `hinge` (the strip lies on
/// its left). Its outer edge runs parallel to the seam's chord, `width` beyond the
/// farthest the seam reaches to the right, so a zigzag seam gets a straight tab at least
/// `width` wide everywhere. Each end leans in over the tab by up to [`END_LEAN`], less
/// where the hinge's end segment itself leans out: an end stays at least 45° off the
/// hinge, whose dashes would otherwise fall within the cut's clearance.
pub fn glue_tab(hinge: Vec<Vec2>, width: f64) -> Result<GlueTab, Advice> {
    let n = hinge.len();
    let (first, last) = (hinge[0], hinge[n - 1]);
    let chord = last - first;
    let length = chord.norm();
    let u = chord / length;
    let right = Vec2::new(u.y, -u.x);
    let reach = hinge
        .iter()
        .map(|p| (p - first).dot(&right))
        .fold(0.0, f64::max);
    let depth = reach + width;
    // The corner on the outer edge reached from hinge end `at`, whose end segment runs
    // along `segment`, leaning towards `inwards` (u at the first end, −u at the last).
    let corner = |at: Vec2, segment: Vec2, inwards: Vec2| -> Vec2 {
        let out_lean = segment.dot(&right).atan2(segment.dot(&inwards));
        let lean = (std::f64::consts::FRAC_PI_4 - out_lean).clamp(0.0, END_LEAN);
        let d = right * lean.cos() + inwards * lean.sin();
        at + d * ((depth - (at - first).dot(&right)) / lean.cos())
    };
    let q0 = corner(first, hinge[1] - first, u);
    let q1 = corner(last, hinge[n - 2] - last, -u);
    if (q1 - q0).dot(&u) <= 0.0 {
        return Err(Advice::text(format!(
            "a glue tab {width} mm wide does not fit along a seam {length:.1} mm long; give a narrower "
        ))
        .option(FabOption::Tab));
    }
    Ok(GlueTab {
        outline: [first, q0, q1, last],
        hinge,
    })
}

/// How far a tab's ends lean in from square to the seam (radians) at most: 30°, so tabs
/// of folds meeting at a rim do not collide.
pub const END_LEAN: f64 = std::f64::consts::PI / 6.0;

/// The strip's lines with the tab: cut lines along the hinge become valley scores, and
/// the tab's outline is cut.
pub fn with_tab(lines: Vec<CreaseLine>, tab: &GlueTab) -> Vec<CreaseLine> {
    let scale = tab
        .hinge
        .windows(2)
        .map(|w| (w[1] - w[0]).norm())
        .sum::<f64>();
    let on_hinge = |p: Vec2| {
        tab.hinge
            .windows(2)
            .any(|w| distance_to_segment(p, w[0], w[1]) <= 1e-9 * scale)
    };
    let mut out: Vec<CreaseLine> = lines
        .into_iter()
        .map(|mut l| {
            if l.kind == LineKind::Cut
                && l.curve.is_none()
                && on_hinge(l.a)
                && on_hinge(l.b)
                && on_hinge((l.a + l.b) / 2.0)
            {
                l.kind = LineKind::Valley;
            }
            l
        })
        .collect();
    for w in tab.outline.windows(2) {
        out.push(CreaseLine {
            a: w[0],
            b: w[1],
            kind: LineKind::Cut,
            junctions: Vec::new(),
            curve: None,
        });
    }
    out
}
