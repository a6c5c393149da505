//! Words printed on a template beside the edges they name (a tube's seam numbers), placed
//! where they collide with nothing: on a zig-zag seam the middles of two neighbouring
//! edges, each offset into the tab, meet in the notch between them (issue 47: 8 over 7,
//! 6 over 5 on `waterbomb-tube-bent`), and a number over a crease line is hard to read.

use super::{CreaseLine, SheetLabel};
use crate::geometry::clip_segment;
use crate::mesh::Vec2;

/// Size of the words printed on the sheet, points.
pub const LABEL_PT: f32 = 7.0;

/// Kept clear around a label's box, mm: ink beside a figure reads as part of it.
const LABEL_CLEARANCE_MM: f64 = 0.4;

/// The average advance of a character of the template's Helvetica at `pt` points, mm
/// (0.6 em: wide enough for any figure).
pub fn char_width_mm(pt: f32) -> f64 {
    f64::from(pt) * 0.6 * 25.4 / 72.0
}

/// Height of a figure at `pt` points, mm (Helvetica's cap height, 0.72 em).
fn figure_height_mm(pt: f32) -> f64 {
    f64::from(pt) * 0.72 * 25.4 / 72.0
}

/// The box a label's ink takes on the sheet, (lower left, upper right): centred on
/// `at` across, its baseline at `at.y`.
pub fn label_box(label: &SheetLabel) -> (Vec2, Vec2) {
    let half = char_width_mm(LABEL_PT) * label.text.chars().count() as f64 / 2.0;
    (
        Vec2::new(label.at.x - half, label.at.y),
        Vec2::new(label.at.x + half, label.at.y + figure_height_mm(LABEL_PT)),
    )
}

/// A label to place beside the edge `a`→`b`, on its right (the side its normal
/// (d.y, −d.x) points to), `depth` mm in.
#[derive(Clone, Debug)]
pub struct EdgeLabel {
    /// The edge's start on the sheet (mm).
    pub a: Vec2,
    /// Its end.
    pub b: Vec2,
    /// What is printed.
    pub text: String,
    /// How far in from the edge the label's middle goes, when nothing is in the way.
    pub depth: f64,
}

/// Where along its edge (fraction of its length) and how deep (times its depth) a label
/// may go, in order of preference: the edge's middle at its depth first.
const SITES: [(f64, f64); 15] = [
    (0.5, 1.0),
    (0.35, 1.0),
    (0.65, 1.0),
    (0.5, 0.7),
    (0.5, 1.3),
    (0.25, 1.0),
    (0.75, 1.0),
    (0.35, 0.7),
    (0.65, 0.7),
    (0.35, 1.3),
    (0.65, 1.3),
    (0.25, 0.7),
    (0.75, 0.7),
    (0.2, 1.0),
    (0.8, 1.0),
];

/// Places each label beside its edge where its box, with `LABEL_CLEARANCE_MM` around
/// it, meets no line of `lines` and no label placed before it; where every site is taken,
/// the one with the fewest collisions (labels counting before lines). Greedy, in order.
pub fn place_beside_edges(labels: &[EdgeLabel], lines: &[CreaseLine]) -> Vec<SheetLabel> {
    let segments: Vec<(Vec2, Vec2)> = lines
        .iter()
        .flat_map(|l| {
            let p = l.polyline();
            (1..p.len())
                .map(move |i| (p[i - 1], p[i]))
                .collect::<Vec<_>>()
        })
        .collect();
    let mut placed: Vec<SheetLabel> = Vec::with_capacity(labels.len());
    for l in labels {
        let d = l.b - l.a;
        let normal = Vec2::new(d.y, -d.x) / d.norm().max(f64::MIN_POSITIVE);
        let rise = figure_height_mm(LABEL_PT) / 2.0;
        let candidate = |&(t, k): &(f64, f64)| SheetLabel {
            at: l.a + d * t + normal * (l.depth * k) - Vec2::new(0.0, rise),
            text: l.text.clone(),
        };
        let collisions = |c: &SheetLabel| {
            let (lo, hi) = grown(label_box(c));
            let on_labels = placed
                .iter()
                .filter(|p| boxes_meet((lo, hi), label_box(p)))
                .count();
            let on_lines = segments
                .iter()
                .filter(|(p, q)| clip_segment(*p, *q, (lo, hi)).is_some())
                .count();
            (on_labels, on_lines)
        };
        let best = SITES
            .iter()
            .map(candidate)
            .map(|c| (collisions(&c), c))
            .enumerate()
            .min_by_key(|(i, ((labels, lines), _))| (*labels, *lines, *i))
            .map(|(_, (_, c))| c)
            .expect("there are sites");
        placed.push(best);
    }
    placed
}

/// A box grown by `LABEL_CLEARANCE_MM` on every side.
fn grown((lo, hi): (Vec2, Vec2)) -> (Vec2, Vec2) {
    let c = Vec2::new(LABEL_CLEARANCE_MM, LABEL_CLEARANCE_MM);
    (lo - c, hi + c)
}

/// Whether two boxes overlap.
fn boxes_meet((a0, a1): (Vec2, Vec2), (b0, b1): (Vec2, Vec2)) -> bool {
    a0.x < b1.x && b0.x < a1.x && a0.y < b1.y && b0.y < a1.y
}
