//! How precisely a crease pattern was drawn: the scale below which its flat-folded state
//! stops having one structure. Patterns drawn in ORIPA-like tools carry noise (vertices a
//! few thousandths of a millimetre off), so corners that fold onto one point land a little
//! apart, and Kawasaki's sums miss π by as much. Measured, that noise founds the allowances
//! verification gives the pattern ([`super::rounding::RoundingBounds`], the layers'
//! closure and contact), as a file's decimal rounding already does.
//!
//! The idea is Flat-Folder's (`L_2_V_EV_EL`): halve a length scale from an eighth of the
//! shortest crease and count the features at each scale, until the counts repeat.
//! Flat-Folder then works at the coarsest scale of the repeating run; this takes the
//! finest scale at which the count still holds, the level the noise starts below, so
//! an allowance is never wider than the drawing needs, and holds it to a few times the gaps
//! the folded corners really leave. A pattern with exact coordinates
//! keeps one count down to the last halving and is drawn to within a few billionths of
//! its shortest crease.

use super::flat_fold::{cluster_labels, flat_folded};
use crate::mesh::{Mesh, Vec2};

/// The finest scale tried is the shortest crease over 2 to this power (Flat-Folder
/// tries 25 halvings from an eighth).
const FINEST: i32 = 28;

/// The drawing precision is at most this many times the largest gap the folded corners
/// leave around a vertex ([`super::FlatFolded::mismatch`]).
const GAPS_EXPLAINED: f64 = 4.0;

/// The largest gap, as a fraction of the shortest crease, taken as a drawing's noise
/// where its folded corners settle at no scale ([`unsettled`]): 1/256, noise that turns
/// a crease by at most about 0.2°.
const UNSETTLED_RELATIVE: f64 = 1.0 / 256.0;

/// A precision below this fraction of the pattern's diagonal is what double precision
/// leaves along the folding (about 1e-16 a reflection, compounded): the drawing is exact.
const EXACT_RELATIVE: f64 = 1e-12;

/// How a pattern's drawing was measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawnPrecision {
    /// The scale (mm) down to which the folded state keeps one structure: corners meant
    /// to meet lie within it.
    pub precision: f64,
    /// Whether the structure held down to the finest scale tried (exact coordinates).
    pub exact: bool,
}

/// The drawing precision of a crease pattern, from its flat-folded state: `None` when
/// it has no crease pattern or does not fold to a flat state to measure.
pub fn drawing_precision(mesh: &Mesh) -> Option<DrawnPrecision> {
    let cp = mesh.crease_pattern()?;
    let shortest = shortest_line(mesh, cp, true);
    if !shortest.is_finite() {
        return None;
    }
    let folded = flat_folded(mesh, None).ok()?;
    let corners: Vec<Vec2> = folded.triangles.iter().flatten().copied().collect();
    // The count at each scale, coarse to fine. Below the gaps the folded corners leave,
    // the noise itself is resolved (every noisy image its own point) and counts repeat
    // again, so a run there would say "exact" of a drawing whose vertices miss Kawasaki's
    // sums: only scales above the gap are tried.
    // The search starts at an eighth of the shortest crease, as Flat-Folder's; where the
    // folded corners' gaps bound the noise (interior vertices, below), it may start at a
    // half, so that a run of three fits above a drawing's compounded noise.
    let bounded = folded.worst_vertex.is_some();
    let first = if bounded { 1 } else { 3 };
    let scales: Vec<f64> = (first..FINEST)
        .map(|i| shortest / 2f64.powi(i))
        .filter(|&s| s >= folded.mismatch)
        .collect();
    let counts: Vec<usize> = scales.iter().map(|&s| clusters(&corners, s)).collect();
    // The first run of three equal counts, as Flat-Folder's, followed to its end.
    let Some(start) = (0..counts.len().saturating_sub(2))
        .find(|&i| counts[i] == counts[i + 1] && counts[i] == counts[i + 2])
    else {
        return unsettled(&folded, shortest_line(mesh, cp, false));
    };
    let end = (start..counts.len())
        .take_while(|&i| counts[i] == counts[start])
        .last()
        .unwrap_or(start);
    // A scale coarser than the gaps the folded corners actually leave would merge real
    // features, not noise: the precision is held to a few times the largest gap.
    let (lo, hi) = crate::mesh::bounds(cp);
    // (A pattern without interior vertices, parallel pleats, leaves no gap to go by.)
    let explained = if bounded {
        GAPS_EXPLAINED * folded.mismatch
    } else {
        f64::INFINITY
    };
    let precision = scales[end].min(explained);
    let last = end + 1 == counts.len() && scales.len() == (FINEST - first) as usize;
    Some(DrawnPrecision {
        precision,
        exact: last || precision <= EXACT_RELATIVE * (hi - lo).norm(),
    })
}

/// The precision of a drawing whose folded corners settle at no scale above the gaps
/// they leave: Lang's computed tessellations (Rings8) miss Kawasaki's sums by about the
/// same small amount at every vertex, and their folded corners lie apart at every scale
/// from the gaps up to the creases. The gaps are then the one measure of the drawing's
/// noise, taken as its precision while they are small against its features (at most
/// [`UNSETTLED_RELATIVE`] of `shortest_crease`, [`shortest_line`] without the paper's
/// edges); a larger gap is no noise to allow for.
fn unsettled(folded: &super::FlatFolded, shortest_crease: f64) -> Option<DrawnPrecision> {
    (folded.worst_vertex.is_some()
        && folded.mismatch > 0.0
        && folded.mismatch <= UNSETTLED_RELATIVE * shortest_crease)
        .then_some(DrawnPrecision {
            precision: folded.mismatch,
            exact: false,
        })
}

/// The shortest line of `cp` of positive length (infinite when there is none), the
/// paper's edges among them or not: the scales start from every line, but noise is
/// judged against the creases it turns, not against a sliver of boundary where a
/// crease ends a hair from a corner.
fn shortest_line(mesh: &Mesh, cp: &[Vec2], with_boundary: bool) -> f64 {
    mesh.edges()
        .iter()
        .filter(|e| with_boundary || !e.assignment.is_boundary())
        .map(|e| (cp[e.vertices[1]] - cp[e.vertices[0]]).norm())
        .filter(|&l| l > 0.0)
        .fold(f64::INFINITY, f64::min)
}

/// How many groups `points` fall into when points within `scale` of each other (in x and
/// y) are one ([`cluster_labels`]).
fn clusters(points: &[Vec2], scale: f64) -> usize {
    let labels = cluster_labels(points, scale);
    let mut seen = vec![false; points.len()];
    labels
        .iter()
        .filter(|&&l| !std::mem::replace(&mut seen[l], true))
        .count()
}

/// A crease pattern's drawing noise, measured ([`drawing_precision`]),
/// founds its allowances as a file's rounding does: the mesh with that precision, and the
/// measurement. A pattern drawn exactly, or a 3D design, keeps the tolerances it had.
pub fn as_drawn(mesh: &Mesh) -> (Option<DrawnPrecision>, std::borrow::Cow<'_, Mesh>) {
    let drawn = (!mesh.has_3d()).then(|| drawing_precision(mesh)).flatten();
    match drawn {
        Some(d) if !d.exact && d.precision > mesh.coordinate_precision => {
            let mut noisy = mesh.clone();
            noisy.coordinate_precision = d.precision;
            (drawn, std::borrow::Cow::Owned(noisy))
        }
        _ => (drawn, std::borrow::Cow::Borrowed(mesh)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clusters_join_points_within_the_scale_and_keep_apart_those_beyond() {
        let points = [
            Vec2::new(0.0, 0.0),
            Vec2::new(0.0, 0.0),
            Vec2::new(0.004, 0.003),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
        ];
        assert_eq!(clusters(&points, 0.01), 3);
        assert_eq!(clusters(&points, 0.001), 4);
        assert_eq!(clusters(&points, 2.0), 1);
    }
}
