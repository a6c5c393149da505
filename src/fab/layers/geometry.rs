//! The plane geometry of the layer solver: which folded faces overlap, which hinge lines
//! pass through a face, which creases fold onto one line. Thin contacts (below `eps`)
//! are not overlaps.

use crate::mesh::Vec2;

/// How deeply two triangles overlap: the least distance, over the axes normal to their
/// sides, their shadows share (how far one would have to move to clear the other), or
/// `None` when some axis separates them to within `eps` (contact, not overlap).
pub(super) fn overlap_depth(s: &[Vec2; 3], t: &[Vec2; 3], eps: f64) -> Option<f64> {
    let mut depth = f64::INFINITY;
    for poly in [s, t] {
        for k in 0..3 {
            let d = poly[(k + 1) % 3] - poly[k];
            let n = Vec2::new(-d.y, d.x) / d.norm().max(1e-300);
            let span = |p: &[Vec2; 3]| {
                p.iter()
                    .map(|q| n.dot(q))
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                        (lo.min(x), hi.max(x))
                    })
            };
            let (a, b) = (span(s), span(t));
            if a.1 <= b.0 + eps || b.1 <= a.0 + eps {
                return None;
            }
            depth = depth.min((a.1 - b.0).min(b.1 - a.0));
        }
    }
    Some(depth)
}

/// Segment p–q (longer than `eps`) passes through triangle t deeper than `eps`: some
/// point of it lies farther than `eps` inside every side of t. That is the depth
/// [`overlap_depth`] asks of two faces, so where a face's corner pokes into another face
/// deeper than the contact allowance, the creases that meet at that corner cross that
/// face too, however short the stretch past the allowance (a design drawn a little
/// inexactly folds a corner 0.08 % of its size past a crease line; asking that stretch to
/// be longer than `eps` as well left the overlap in and its constraints out, and counted
/// each such corner as a free choice: Lang's Hyperbolic Limit, 2⁴² states where
/// Flat-Folder finds its one).
pub(super) fn crosses(p: Vec2, q: Vec2, t: &[Vec2; 3], eps: f64) -> bool {
    let d = q - p;
    let len = d.norm();
    if len <= eps {
        return false;
    }
    let area = (t[1] - t[0]).perp(&(t[2] - t[0]));
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for k in 0..3 {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let e = b - a;
        // Inward distance of x from side a→b, for a counter-clockwise or clockwise t.
        let inward = |x: Vec2| e.perp(&(x - a)) * area.signum() / e.norm();
        let (fp, fd) = (inward(p) - eps, inward(q) - inward(p));
        // Need fp + fd·s > 0.
        if fd.abs() < 1e-300 {
            if fp <= 0.0 {
                return false;
            }
        } else if fd > 0.0 {
            lo = lo.max(-fp / fd);
        } else {
            hi = hi.min(-fp / fd);
        }
    }
    hi > lo
}

/// Segments p–q and r–s lie on one line and share a stretch longer than `eps`.
pub(super) fn collinear_overlap(p: Vec2, q: Vec2, r: Vec2, s: Vec2, eps: f64) -> bool {
    let d = q - p;
    let len = d.norm();
    let u = d / len;
    let off = |x: Vec2| u.perp(&(x - p)).abs();
    if off(r) > eps || off(s) > eps {
        return false;
    }
    let (a, b) = ((r - p).dot(&u), (s - p).dot(&u));
    let (a, b) = (a.min(b), a.max(b));
    b.min(len) - a.max(0.0) > eps
}

/// The region two triangles share (a convex polygon, possibly empty): computed once per
/// overlapping pair and then clipped by each candidate third face, the loop that finds the
/// transitivity triples.
pub(super) struct PairOverlap {
    corners: [Vec2; 6],
    len: usize,
}

impl PairOverlap {
    /// The part of `a` inside `b` (two triangles share at most a hexagon).
    pub(super) fn new(a: &[Vec2; 3], b: &[Vec2; 3]) -> PairOverlap {
        let mut buffers = [[Vec2::zeros(); MAX_CORNERS]; 2];
        let (k, len) = clip_by_triangle(a, b, &mut buffers);
        let mut corners = [Vec2::zeros(); 6];
        let len = len.min(6);
        corners[..len].copy_from_slice(&buffers[k][..len]);
        PairOverlap { corners, len }
    }

    /// The shared region's area (mm²).
    #[cfg(test)]
    fn area(&self) -> f64 {
        area(&self.corners[..self.len])
    }

    /// The shared region and triangle `c` have a common area above `eps`² (`scratch`
    /// is the clip's working space, kept by the caller: filling it afresh for every
    /// candidate cost more than the clip).
    pub(super) fn shares_with(&self, c: &[Vec2; 3], eps: f64, scratch: &mut ClipScratch) -> bool {
        if self.len < 3 {
            return false;
        }
        let (k, len) = clip_by_triangle(&self.corners[..self.len], c, &mut scratch.0);
        area(&scratch.0[k][..len]) > eps * eps
    }
}

/// Working space for clipping: two polygons of up to [`MAX_CORNERS`] corners.
pub(super) struct ClipScratch([[Vec2; MAX_CORNERS]; 2]);

impl Default for ClipScratch {
    fn default() -> Self {
        ClipScratch([[Vec2::zeros(); MAX_CORNERS]; 2])
    }
}

/// Corners a clip may hold: a hexagon clipped by a triangle has at most nine.
const MAX_CORNERS: usize = 12;

/// Sutherland–Hodgman: the part of convex polygon `input` inside triangle `t`, left in
/// one of two stack buffers (returned: which, and its corner count). The first cut reads
/// `input`, then each reads one buffer and writes the other, so nothing is copied per
/// clip (this runs once per candidate triple).
fn clip_by_triangle(
    input: &[Vec2],
    t: &[Vec2; 3],
    buffers: &mut [[Vec2; MAX_CORNERS]; 2],
) -> (usize, usize) {
    let orient = (t[1] - t[0]).perp(&(t[2] - t[0])).signum();
    let [first, second] = buffers;
    let mut n = cut(input, t[0], t[1], orient, first);
    n = cut(&first[..n], t[1], t[2], orient, second);
    n = cut(&second[..n], t[2], t[0], orient, first);
    (0, n)
}

/// The part of convex polygon `from` on the inner side of line a→b (`orient` = the
/// triangle's orientation), written to `to`; returns its corner count.
fn cut(from: &[Vec2], a: Vec2, b: Vec2, orient: f64, to: &mut [Vec2; MAX_CORNERS]) -> usize {
    let side = |x: Vec2| (b - a).perp(&(x - a)) * orient;
    let n = from.len();
    let mut len = 0;
    for i in 0..n {
        let (p, q) = (from[i], from[(i + 1) % n]);
        let (sp, sq) = (side(p), side(q));
        // Convex clipping adds at most one corner per cut; a degenerate input must
        // still not write past the end.
        if sp >= 0.0 && len < MAX_CORNERS {
            to[len] = p;
            len += 1;
        }
        if (sp >= 0.0) != (sq >= 0.0) && len < MAX_CORNERS {
            to[len] = p + (q - p) * (sp / (sp - sq));
            len += 1;
        }
    }
    len
}

/// The area of a simple polygon.
fn area(c: &[Vec2]) -> f64 {
    (0..c.len())
        .map(|i| c[i].perp(&c[(i + 1) % c.len()]))
        .sum::<f64>()
        .abs()
        / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(p: [[f64; 2]; 3]) -> [Vec2; 3] {
        p.map(|[x, y]| Vec2::new(x, y))
    }

    /// The shared region of two triangles against its closed form, and the third-face
    /// test on each side of its threshold.
    #[test]
    fn pair_overlap_matches_closed_forms() {
        // a = (0,0),(2,0),(0,2) and b = (0,0),(2,0),(2,2) share (0,0),(2,0),(1,1):
        // area 1.
        let a = tri([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]]);
        let b = tri([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]]);
        let shared = PairOverlap::new(&a, &b);
        assert!((shared.area() - 1.0).abs() < 1e-12, "{}", shared.area());
        // Clockwise order changes nothing.
        let b_cw = tri([[0.0, 0.0], [2.0, 2.0], [2.0, 0.0]]);
        assert!((PairOverlap::new(&a, &b_cw).area() - 1.0).abs() < 1e-12);
        // A third face over the apex (1,1): its sides y = 1 − h + 2|x − 1| meet the
        // apex's y = 1 − |x − 1| at |x − 1| = h/3, leaving a common area of h²/3. It
        // shares when eps² is below that, not when above.
        let h = 0.1;
        let c = tri([[1.0 - h, 1.0 + h], [1.0 + h, 1.0 + h], [1.0, 1.0 - h]]);
        let mut scratch = ClipScratch::default();
        assert!(shared.shares_with(&c, 0.5 * h, &mut scratch));
        assert!(!shared.shares_with(&c, h, &mut scratch));
        // Disjoint triangles share nothing.
        let far = tri([[5.0, 5.0], [6.0, 5.0], [5.0, 6.0]]);
        assert_eq!(PairOverlap::new(&a, &far).area(), 0.0);
        assert!(!shared.shares_with(&far, 1e-9, &mut scratch));
    }

    /// A face whose corner pokes into another deeper than `eps` overlaps it, and the
    /// sides that meet at that corner cross it, however short their stretch deeper
    /// than `eps`; a corner within `eps` of the side does neither.
    #[test]
    fn the_sides_at_a_corner_that_overlaps_a_face_cross_it() {
        let t = tri([[0.0, 0.0], [10.0, 0.0], [5.0, 10.0]]);
        let eps = 0.1;
        for (poke, inside) in [(0.15, true), (0.08, false)] {
            let s = tri([[4.0, -5.0], [6.0, -5.0], [5.0, poke]]);
            let depth = overlap_depth(&s, &t, eps);
            assert_eq!(depth.is_some(), inside, "poke {poke}: {depth:?}");
            if let Some(d) = depth {
                assert!((d - poke).abs() < 1e-12, "poke {poke}: depth {d}");
            }
            // The sides from the corner: deeper than eps for only 0.05 of their length.
            for base in [s[0], s[1]] {
                assert_eq!(crosses(s[2], base, &t, eps), inside, "poke {poke}");
                assert_eq!(crosses(base, s[2], &t, eps), inside, "poke {poke}");
            }
        }
        // A crease through the middle crosses; one along a side, within eps, does not.
        let through = crosses(Vec2::new(-1.0, 3.0), Vec2::new(11.0, 3.0), &t, eps);
        assert!(through);
        let along = crosses(Vec2::new(-1.0, 0.05), Vec2::new(11.0, 0.05), &t, eps);
        assert!(!along);
    }
}
