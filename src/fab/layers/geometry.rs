//! The plane geometry of the layer solver: which folded faces overlap, which hinge lines
//! pass through a face, which creases fold onto one line. Thin contacts (below `eps`)
//! are not overlaps.

use crate::mesh::{bounds, Vec2};

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

/// A folded face as [`PairOverlap::shares_with`] reads it: its corners, and what its
/// quick tests read (bounding box, incircle), computed once per face rather than once per
/// candidate triple.
pub(super) struct FoldedTriangle {
    corners: [Vec2; 3],
    lo: Vec2,
    hi: Vec2,
    incentre: Vec2,
    inradius: f64,
}

impl FoldedTriangle {
    pub(super) fn new(t: &[Vec2; 3]) -> FoldedTriangle {
        let (lo, hi) = bounds(t);
        // The incentre weighs each corner by the length of the side facing it.
        let facing = [0, 1, 2].map(|k| (t[(k + 2) % 3] - t[(k + 1) % 3]).norm());
        let perimeter: f64 = facing.iter().sum();
        let (incentre, inradius) = if perimeter > 0.0 {
            let centre = (t[0] * facing[0] + t[1] * facing[1] + t[2] * facing[2]) / perimeter;
            (centre, 2.0 * area(t) / perimeter)
        } else {
            (t[0], 0.0)
        };
        FoldedTriangle {
            corners: *t,
            lo,
            hi,
            incentre,
            inradius,
        }
    }
}

/// The region two triangles share (a convex polygon, possibly empty): computed once per
/// overlapping pair and then clipped by each candidate third face, the loop that finds the
/// transitivity triples.
pub(super) struct PairOverlap {
    corners: [Vec2; 6],
    len: usize,
    sides: Sides,
    lo: Vec2,
    hi: Vec2,
}

impl PairOverlap {
    /// The part of `a` inside `b` (two triangles share at most a hexagon).
    pub(super) fn new(a: &FoldedTriangle, b: &FoldedTriangle) -> PairOverlap {
        let mut buffers = [[Vec2::zeros(); MAX_CORNERS]; 2];
        let (k, len) = clip_by_triangle(&a.corners, &b.corners, &mut buffers);
        let mut corners = [Vec2::zeros(); 6];
        let len = len.min(6);
        corners[..len].copy_from_slice(&buffers[k][..len]);
        let shape = &corners[..len];
        let sides = Sides::new(shape);
        let (lo, hi) = bounds(shape);
        PairOverlap {
            corners,
            len,
            sides,
            lo,
            hi,
        }
    }

    /// The shared region's area (mm²).
    #[cfg(test)]
    fn area(&self) -> f64 {
        area(&self.corners[..self.len])
    }

    /// The shared region and triangle `c` have a common area above `eps`² (`scratch`
    /// is the clip's working space, kept by the caller: filling it afresh for every
    /// candidate cost more than the clip).
    ///
    /// Half the calls are answered without clipping (on Ryujin 2.1, 22 of 45 million, for
    /// 31.6 million candidate triples): when the two bounding boxes share less than `eps`²
    /// (8.5 million), or when a disc of radius 0.6 `eps` (area 1.13 `eps`²) about `c`'s
    /// incentre lies in the region (13.4 million). Each quick answer is the clip's own,
    /// with room to spare for rounding. (A disc about the region's centre, tried next,
    /// spared 3 million more clips but cost what it saved.)
    pub(super) fn shares_with(
        &self,
        c: &FoldedTriangle,
        eps: f64,
        scratch: &mut ClipScratch,
    ) -> bool {
        if self.len < 3 {
            return false;
        }
        let box_area = (self.hi.x.min(c.hi.x) - self.lo.x.max(c.lo.x)).max(0.0)
            * (self.hi.y.min(c.hi.y) - self.lo.y.max(c.lo.y)).max(0.0);
        if box_area < eps * eps * (1.0 - 1e-9) {
            return false;
        }
        let disc = 0.6 * eps;
        if c.inradius > disc && self.sides.hold(c.incentre, disc) {
            return true;
        }
        self.clipped_area(c, scratch) > eps * eps
    }

    /// The area the region shares with triangle `c`, clipped (mm²): what the quick
    /// answers of [`PairOverlap::shares_with`] stand in for.
    fn clipped_area(&self, c: &FoldedTriangle, scratch: &mut ClipScratch) -> f64 {
        let (k, len) = clip_by_triangle(&self.corners[..self.len], &c.corners, &mut scratch.0);
        area(&scratch.0[k][..len])
    }
}

/// The sides of a convex polygon of at most six corners, as inward unit normals `n` and
/// offsets `o`: a point x lies `n·x − o` inside a side.
struct Sides {
    normals: [Vec2; 6],
    offsets: [f64; 6],
    len: usize,
}

impl Sides {
    fn new(corners: &[Vec2]) -> Sides {
        let len = corners.len().min(6);
        let mut sides = Sides {
            normals: [Vec2::zeros(); 6],
            offsets: [0.0; 6],
            len,
        };
        // Inward is left of each side for a counter-clockwise polygon, right for a
        // clockwise one (the shoelace sum's sign tells which).
        let turn: f64 = (0..len)
            .map(|i| corners[i].perp(&corners[(i + 1) % len]))
            .sum();
        for i in 0..len {
            let (a, b) = (corners[i], corners[(i + 1) % len]);
            let d = (b - a) * turn.signum();
            let n = Vec2::new(-d.y, d.x) / d.norm().max(1e-300);
            sides.normals[i] = n;
            sides.offsets[i] = n.dot(&a);
        }
        sides
    }

    /// Whether a disc of radius `r` about `x` lies inside every side.
    fn hold(&self, x: Vec2, r: f64) -> bool {
        (0..self.len).all(|i| self.normals[i].dot(&x) - self.offsets[i] > r)
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

    fn face(p: [[f64; 2]; 3]) -> FoldedTriangle {
        FoldedTriangle::new(&tri(p))
    }

    /// The shared region of two triangles against its closed form, and the third-face
    /// test on each side of its threshold.
    #[test]
    fn pair_overlap_matches_closed_forms() {
        // a = (0,0),(2,0),(0,2) and b = (0,0),(2,0),(2,2) share (0,0),(2,0),(1,1):
        // area 1.
        let a = face([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]]);
        let b = face([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]]);
        let shared = PairOverlap::new(&a, &b);
        assert!((shared.area() - 1.0).abs() < 1e-12, "{}", shared.area());
        // Clockwise order changes nothing.
        let b_cw = face([[0.0, 0.0], [2.0, 2.0], [2.0, 0.0]]);
        assert!((PairOverlap::new(&a, &b_cw).area() - 1.0).abs() < 1e-12);
        // A third face over the apex (1,1): its sides y = 1 − h + 2|x − 1| meet the
        // apex's y = 1 − |x − 1| at |x − 1| = h/3, leaving a common area of h²/3. It
        // shares when eps² is below that, not when above.
        let h = 0.1;
        let c = face([[1.0 - h, 1.0 + h], [1.0 + h, 1.0 + h], [1.0, 1.0 - h]]);
        let mut scratch = ClipScratch::default();
        assert!(shared.shares_with(&c, 0.5 * h, &mut scratch));
        assert!(!shared.shares_with(&c, h, &mut scratch));
        // Disjoint triangles share nothing.
        let far = face([[5.0, 5.0], [6.0, 5.0], [5.0, 6.0]]);
        assert_eq!(PairOverlap::new(&a, &far).area(), 0.0);
        assert!(!shared.shares_with(&far, 1e-9, &mut scratch));
    }

    /// The quick answers of `shares_with` (bounding boxes, a disc about the third face's
    /// incentre) are the clip's own: brute force over random triangles of either
    /// orientation and all sizes, many of them near the `eps`² threshold.
    #[test]
    fn quick_answers_agree_with_the_clip() {
        let mut rng = crate::random::Rng::new(46);
        let corner = |rng: &mut crate::random::Rng, at: Vec2, size: f64| {
            at + Vec2::new(rng.range(-size, size), rng.range(-size, size))
        };
        let (mut shared, mut apart) = (0, 0);
        for _ in 0..40_000 {
            let eps = [1e-3, 1e-2, 5e-2][rng.below(3)];
            // The third face as large as the sheet, or a few eps across: its whole area
            // then lies near the threshold.
            let size = [0.2, 1.0, eps, 2.0 * eps][rng.below(4)];
            let at = Vec2::zeros();
            let face = |rng: &mut crate::random::Rng, at: Vec2, size: f64| {
                FoldedTriangle::new(&[0, 1, 2].map(|_| corner(rng, at, size)))
            };
            let (a, b) = (face(&mut rng, at, 1.0), face(&mut rng, at, 1.0));
            let region = PairOverlap::new(&a, &b);
            // The third face about a corner of the region, where the common area is
            // small, or about its centre, where all of a small face may lie inside.
            let corners = &region.corners[..region.len];
            let near = match rng.below(2) {
                _ if corners.is_empty() => at,
                0 => corners[rng.below(corners.len())],
                _ => corners.iter().sum::<Vec2>() / corners.len() as f64,
            };
            let c = face(&mut rng, near, size);
            let mut scratch = ClipScratch::default();
            let quick = region.shares_with(&c, eps, &mut scratch);
            let clip = region.len >= 3 && region.clipped_area(&c, &mut scratch) > eps * eps;
            assert_eq!(
                quick, clip,
                "eps {eps}: a {:?} b {:?} c {:?}",
                a.corners, b.corners, c.corners
            );
            if clip {
                shared += 1;
            } else {
                apart += 1;
            }
        }
        // Both answers are common, so each quick test was exercised.
        assert!(
            shared > 5_000 && apart > 5_000,
            "{shared} shared, {apart} apart"
        );
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
