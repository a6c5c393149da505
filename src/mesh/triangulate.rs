//! Ear-clipping triangulation of simple polygons, used to turn the polygon faces of a crease
//! pattern into triangles joined by flat (target 0) creases, as the paper's model requires.

use super::{distance_to_segment, Vec2};
use crate::limits;

/// Ear clipping's work left for one file's faces ([`limits::TRIANGULATION_WORK`]): a
/// face is charged its corner count squared before it is clipped, so a file of one face
/// with a million corners is refused at once instead of clipping for hours.
#[derive(Debug)]
pub struct TriangulationBudget {
    left: u64,
}

impl Default for TriangulationBudget {
    fn default() -> Self {
        TriangulationBudget {
            left: limits::TRIANGULATION_WORK,
        }
    }
}

impl TriangulationBudget {
    /// Charges a face of `corners` corners, or says why it is past the budget.
    pub fn charge(&mut self, corners: usize) -> Result<(), String> {
        let cost = (corners as u64).saturating_mul(corners as u64);
        if cost > self.left {
            return Err(format!(
                "a face of {corners} corners is past what crease triangulates \
                 (faces of about {} corners in all): split it with creases, or draw fewer points on its outline",
                (limits::TRIANGULATION_WORK as f64).sqrt().round()
            ));
        }
        self.left -= cost;
        Ok(())
    }
}

/// Triangulates a simple polygon given by its corners in order (either orientation).
/// Returns triangles as indices into `corners`, counter-clockwise when the polygon is.
/// Among the available ears the fattest (largest smallest angle) is cut first, so the
/// added creases avoid slivers. Corners lying on a straight side are kept as vertices.
/// A new diagonal must pass no other corner closer than `clearance`, so that a drawing of
/// the result, read back with that merge tolerance, gives the same graph.
/// Returns `None` when the polygon is degenerate or self-intersecting.
pub fn triangulate_polygon(corners: &[Vec2], clearance: f64) -> Option<Vec<[usize; 3]>> {
    let n = corners.len();
    if n < 3 {
        return None;
    }
    let area2: f64 = (0..n).map(|i| corners[i].perp(&corners[(i + 1) % n])).sum();
    let scale = corners
        .iter()
        .map(|p| (p - corners[0]).norm_squared())
        .fold(0.0, f64::max);
    if area2.is_nan() || area2.abs() <= 1e-14 * scale {
        return None;
    }
    let mut ring: Vec<usize> = if area2 > 0.0 {
        (0..n).collect()
    } else {
        (0..n).rev().collect()
    };
    let eps = 1e-12 * scale;
    let mut triangles = Vec::with_capacity(n - 2);
    // Each corner's ear is cached, so a cut re-examines only what it changed: the two
    // corners beside the cut one (their triangles changed) and the ears that the cut corner
    // blocked (its witness is gone). A blocked ear keeps a witness corner; while that corner
    // is in the ring the ear stays blocked, since removing corners only removes blockers.
    // The result is the same as testing every ear every time, in O(n²) typical time
    // instead of O(n³) (a 2,000-corner face: 20 s before).
    let mut ears: Vec<Ear> = vec![Ear::Stale; n];
    let mut blocked_by: Vec<Vec<usize>> = vec![Vec::new(); n];
    while ring.len() > 3 {
        let m = ring.len();
        let mut best: Option<(usize, f64)> = None;
        for i in 0..m {
            let (a, b, c) = (ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]);
            if ears[b] == Ear::Stale {
                ears[b] = examine_ear(corners, &ring, a, b, c, eps, clearance);
                if let Ear::Blocked(w) = ears[b] {
                    blocked_by[w].push(b);
                }
            }
            if let Ear::Open(q) = ears[b] {
                if best.is_none_or(|(_, bq)| q > bq) {
                    best = Some((i, q));
                }
            }
        }
        let (i, _) = best?;
        let m = ring.len();
        let (prev, tip, next) = (ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]);
        triangles.push([prev, tip, next]);
        ring.remove(i);
        ears[prev] = Ear::Stale;
        ears[next] = Ear::Stale;
        for t in std::mem::take(&mut blocked_by[tip]) {
            if ears[t] == Ear::Blocked(tip) {
                ears[t] = Ear::Stale;
            }
        }
    }
    let (a, b, c) = (corners[ring[0]], corners[ring[1]], corners[ring[2]]);
    if (b - a).perp(&(c - a)) <= eps {
        return None;
    }
    triangles.push([ring[0], ring[1], ring[2]]);
    flip_caps(corners, &mut triangles, clearance);
    Some(triangles)
}

/// A corner this close to straight (radians) is nearly on the side opposite it.
const CAP_ANGLE: f64 = 0.02;

/// Flips the diagonal under every *cap*: a triangle with a corner within [`CAP_ANGLE`] of
/// straight, which ear clipping leaves when a polygon's corner lies nearly on a side
/// (a point drawn a little off a crease it should split). Such a triangle has almost no
/// area, and which way it faces is decided by the drawing's noise. Where the other
/// triangle on that diagonal makes a convex quadrilateral, the other diagonal gives two
/// proper triangles with a larger smallest angle; the flip is kept only then (and when
/// the new diagonal keeps `clearance` from every corner).
fn flip_caps(corners: &[Vec2], triangles: &mut [[usize; 3]], clearance: f64) {
    let signed = |t: [usize; 3]| {
        let [a, b, c] = t.map(|k| corners[k]);
        (b - a).perp(&(c - a))
    };
    let straight = |t: [usize; 3]| {
        (0..3).find(|&k| {
            let (a, b, c) = (
                corners[t[(k + 2) % 3]],
                corners[t[k]],
                corners[t[(k + 1) % 3]],
            );
            (a - b).angle(&(c - b)) > std::f64::consts::PI - CAP_ANGLE
        })
    };
    let mut side_of: std::collections::HashMap<(usize, usize), usize> = triangles
        .iter()
        .enumerate()
        .flat_map(|(i, t)| (0..3).map(move |k| ((t[k], t[(k + 1) % 3]), i)))
        .collect();
    // Each flip removes a cap and makes none (its two triangles are checked), so one
    // pass per triangle bounds the work even on a pathological polygon.
    for _ in 0..2 {
        let mut flipped = false;
        for i in 0..triangles.len() {
            let t = triangles[i];
            let Some(k) = straight(t) else { continue };
            let (a, b, c) = (t[(k + 2) % 3], t[k], t[(k + 1) % 3]);
            let Some(&j) = side_of.get(&(a, c)) else {
                continue;
            };
            let u = triangles[j];
            let d = u[(u.iter().position(|&x| x == a).expect("shares a") + 2) % 3];
            let (t1, t2) = ([a, b, d], [b, c, d]);
            let sign = signed(t).signum();
            let proper = |n: [usize; 3]| signed(n) * sign > 0.0 && straight(n).is_none();
            let clear = corners.iter().enumerate().all(|(m, &q)| {
                m == b || m == d || distance_to_segment(q, corners[b], corners[d]) >= clearance
            });
            let fatter = min_angle_of(corners, t1).min(min_angle_of(corners, t2))
                > min_angle_of(corners, t).min(min_angle_of(corners, u));
            if !(proper(t1) && proper(t2) && clear && fatter) {
                continue;
            }
            for old in [t, u] {
                for k in 0..3 {
                    side_of.remove(&(old[k], old[(k + 1) % 3]));
                }
            }
            (triangles[i], triangles[j]) = (t1, t2);
            for (n, new) in [(i, t1), (j, t2)] {
                for k in 0..3 {
                    side_of.insert((new[k], new[(k + 1) % 3]), n);
                }
            }
            flipped = true;
        }
        if !flipped {
            break;
        }
    }
}

fn min_angle_of(corners: &[Vec2], t: [usize; 3]) -> f64 {
    min_angle(corners[t[0]], corners[t[1]], corners[t[2]])
}

/// What is known of the ear at a corner.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Ear {
    /// Not examined since its neighbours or its witness changed.
    Stale,
    /// Reflex or flat: no ear.
    Reflex,
    /// Another corner lies in the ear or too close to its diagonal.
    Blocked(usize),
    /// A valid ear with this quality (its smallest angle).
    Open(f64),
}

/// The ear a → b → c: reflex, blocked (with the first corner that blocks it), or open.
fn examine_ear(
    corners: &[Vec2],
    ring: &[usize],
    a: usize,
    b: usize,
    c: usize,
    eps: f64,
    clearance: f64,
) -> Ear {
    let (pa, pb, pc) = (corners[a], corners[b], corners[c]);
    if (pb - pa).perp(&(pc - pa)) <= eps {
        return Ear::Reflex;
    }
    let witness = ring.iter().copied().find(|&k| {
        k != a
            && k != b
            && k != c
            && corners[k] != pa
            && corners[k] != pb
            && corners[k] != pc
            && (in_triangle(corners[k], pa, pb, pc, eps)
                || distance_to_segment(corners[k], pa, pc) < clearance)
    });
    match witness {
        Some(w) => Ear::Blocked(w),
        None => Ear::Open(min_angle(pa, pb, pc)),
    }
}

/// Inside or on the boundary of counter-clockwise triangle abc.
fn in_triangle(p: Vec2, a: Vec2, b: Vec2, c: Vec2, eps: f64) -> bool {
    (b - a).perp(&(p - a)) >= -eps
        && (c - b).perp(&(p - b)) >= -eps
        && (a - c).perp(&(p - c)) >= -eps
}

fn min_angle(a: Vec2, b: Vec2, c: Vec2) -> f64 {
    let ang = |p: Vec2, q: Vec2, r: Vec2| (q - p).angle(&(r - p));
    ang(a, b, c).min(ang(b, c, a)).min(ang(c, a, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(c: &[Vec2], t: [usize; 3]) -> f64 {
        0.5 * (c[t[1]] - c[t[0]]).perp(&(c[t[2]] - c[t[0]]))
    }

    #[test]
    fn l_shape_is_covered_exactly_by_positive_triangles() {
        let c: Vec<Vec2> = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .iter()
            .map(|&(x, y)| Vec2::new(x, y))
            .collect();
        let t = triangulate_polygon(&c, 0.0).unwrap();
        assert_eq!(t.len(), 4);
        assert!(t.iter().all(|&t| area(&c, t) > 0.0));
        let total: f64 = t.iter().map(|&t| area(&c, t)).sum();
        assert!((total - 3.0).abs() < 1e-12);
    }

    #[test]
    fn clockwise_input_gives_counter_clockwise_triangles_and_keeps_side_points() {
        // Triangle with its three side midpoints, listed clockwise.
        let c: Vec<Vec2> = [(0., 0.), (0.5, 1.), (1., 2.), (1.5, 1.), (2., 0.), (1., 0.)]
            .iter()
            .map(|&(x, y)| Vec2::new(x, y))
            .collect();
        let t = triangulate_polygon(&c, 0.0).unwrap();
        assert_eq!(t.len(), 4);
        assert!(t.iter().all(|&t| area(&c, t) > 1e-9));
    }

    /// Every ear tested at every cut: the O(n³) definition the cached version must match.
    fn reference(corners: &[Vec2], clearance: f64) -> Option<Vec<[usize; 3]>> {
        let n = corners.len();
        let area2: f64 = (0..n).map(|i| corners[i].perp(&corners[(i + 1) % n])).sum();
        let scale = corners
            .iter()
            .map(|p| (p - corners[0]).norm_squared())
            .fold(0.0, f64::max);
        let mut ring: Vec<usize> = if area2 > 0.0 {
            (0..n).collect()
        } else {
            (0..n).rev().collect()
        };
        let eps = 1e-12 * scale;
        let mut out = Vec::new();
        while ring.len() > 3 {
            let m = ring.len();
            let mut best: Option<(usize, f64)> = None;
            for i in 0..m {
                let (a, b, c) = (ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]);
                if let Ear::Open(q) = examine_ear(corners, &ring, a, b, c, eps, clearance) {
                    if best.is_none_or(|(_, bq)| q > bq) {
                        best = Some((i, q));
                    }
                }
            }
            let (i, _) = best?;
            out.push([ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]]);
            ring.remove(i);
        }
        out.push([ring[0], ring[1], ring[2]]);
        Some(out)
    }

    /// A star with `n` corners whose radii wobble (seeded), so many ears are blocked.
    fn star(n: usize, seed: u64) -> Vec<Vec2> {
        let mut rng = crate::random::Rng::new(seed);
        (0..n)
            .map(|k| {
                let wobble = rng.range(0.0, 50.0);
                let r = if k % 2 == 0 { 100.0 } else { 40.0 + wobble };
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                Vec2::new(r * t.cos(), r * t.sin())
            })
            .collect()
    }

    #[test]
    fn cached_ears_cut_exactly_what_testing_every_ear_cuts() {
        for (n, seed) in [(12, 1), (40, 2), (61, 3), (90, 4)] {
            let c = star(n, seed);
            assert_eq!(triangulate_polygon(&c, 0.5), reference(&c, 0.5), "n = {n}");
        }
    }

    #[test]
    fn a_two_thousand_corner_face_is_covered_exactly() {
        let c = star(2000, 7);
        let t = triangulate_polygon(&c, 0.0).unwrap();
        assert_eq!(t.len(), 1998);
        assert!(t.iter().all(|&t| area(&c, t) > 0.0));
        let total: f64 = t.iter().map(|&t| area(&c, t)).sum();
        let polygon: f64 = 0.5
            * (0..c.len())
                .map(|i| c[i].perp(&c[(i + 1) % c.len()]))
                .sum::<f64>();
        assert!(
            (total - polygon).abs() < 1e-9 * polygon,
            "{total} vs {polygon}"
        );
    }

    /// A corner drawn a hair off the straight side it splits is not left as the tip of
    /// a triangle of almost no area: its diagonal is flipped.
    #[test]
    fn a_corner_nearly_on_a_side_leaves_no_cap() {
        for offset in [1e-3, -1e-3, 1e-6] {
            // A pentagon whose corner 2 lies `offset` off the line from corner 1 to 3.
            let c = [
                Vec2::new(0.0, 0.0),
                Vec2::new(10.0, 0.0),
                Vec2::new(10.0 - offset, 5.0),
                Vec2::new(10.0, 10.0),
                Vec2::new(0.0, 10.0),
            ];
            let tris = triangulate_polygon(&c, 0.0).unwrap();
            let total: f64 = tris.iter().map(|&t| area(&c, t)).sum();
            assert!((total - (100.0 - 5.0 * offset)).abs() < 1e-9, "{total}");
            for &t in &tris {
                let angle = min_angle_of(&c, t);
                assert!(
                    angle > 0.1,
                    "offset {offset}: {t:?} has an angle of {angle}"
                );
                assert!(area(&c, t) > 0.0);
            }
        }
    }

    #[test]
    fn degenerate_polygon_is_refused() {
        let c = vec![Vec2::new(0., 0.), Vec2::new(1., 0.), Vec2::new(2., 0.)];
        assert!(triangulate_polygon(&c, 0.0).is_none());
    }
}
