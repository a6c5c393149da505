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

/// Segment p–q passes through the interior of triangle t for a length above `eps`.
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
    (hi - lo) * len > eps
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

/// Three triangles share a region of positive area.
pub(super) fn common_overlap(a: &[Vec2; 3], b: &[Vec2; 3], c: &[Vec2; 3], eps: f64) -> bool {
    let mut poly = Polygon::from(a);
    poly.clip(b);
    poly.clip(c);
    poly.area() > eps * eps
}

/// A convex polygon of at most twelve corners, on the stack: a triangle clipped by two
/// triangles has at most nine, and this runs once per candidate triple. Two buffers, read
/// from one and written to the other, so a clip copies nothing.
struct Polygon {
    buffers: [[Vec2; 12]; 2],
    current: usize,
    len: usize,
}

impl Polygon {
    fn from(t: &[Vec2; 3]) -> Polygon {
        let mut buffers = [[Vec2::zeros(); 12]; 2];
        buffers[0][..3].copy_from_slice(t);
        Polygon {
            buffers,
            current: 0,
            len: 3,
        }
    }

    /// Sutherland–Hodgman: keeps the part inside triangle `t`.
    fn clip(&mut self, t: &[Vec2; 3]) {
        let orient = (t[1] - t[0]).perp(&(t[2] - t[0])).signum();
        for k in 0..3 {
            if self.len == 0 {
                return;
            }
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let side = |x: Vec2| (b - a).perp(&(x - a)) * orient;
            let (n, from) = (self.len, self.current);
            let [first, second] = &mut self.buffers;
            let (input, output) = if from == 0 {
                (&*first, second)
            } else {
                (&*second, first)
            };
            let mut len = 0;
            let mut push = |p: Vec2| {
                // Convex clipping adds at most one corner per cut; a degenerate input must
                // still not write past the end.
                if len < output.len() {
                    output[len] = p;
                    len += 1;
                }
            };
            for i in 0..n {
                let (p, q) = (input[i], input[(i + 1) % n]);
                let (sp, sq) = (side(p), side(q));
                if sp >= 0.0 {
                    push(p);
                }
                if (sp >= 0.0) != (sq >= 0.0) {
                    push(p + (q - p) * (sp / (sp - sq)));
                }
            }
            self.len = len;
            self.current = 1 - from;
        }
    }

    fn area(&self) -> f64 {
        let c = &self.buffers[self.current][..self.len];
        (0..c.len())
            .map(|i| c[i].perp(&c[(i + 1) % c.len()]))
            .sum::<f64>()
            .abs()
            / 2.0
    }
}
