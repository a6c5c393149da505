//! Smooth curves on the sheet. A curved crease is a chain of chords in the mesh (paper
//! §6.6: planar strips between rulings); the paper it is cut into should be scored along
//! the smooth curve the chords stand for, not along the chords. The curve is the G1 spline
//! of cubic Béziers through the chain's vertices whose tangent at each vertex is the
//! tangent of the circle through it and its two neighbours, and whose handles are those of
//! the circular arc between two such tangents: vertices that lie on a circle give that
//! circle (to the Bézier's own 10⁻⁶ of the radius), so an arc or a concentric ring leaves
//! as itself.

use crate::mesh::Vec2;

/// Largest distance between a curve and the chords it is flattened into (mm): what the
/// cutter's job (HP-GL, GP-GL, DXF) and the clearance check use in its place, far below
/// any cutter's step (0.025 mm at the finest).
pub const FLATTEN_MM: f64 = 0.005;

/// Samples per cubic in its arc-length table: a 3 mm dash on a 5 mm radius is measured to
/// better than 10⁻⁶ mm.
const TABLE: usize = 64;

/// A cubic Bézier curve B(t) = (1−t)³p0 + 3(1−t)²t c1 + 3(1−t)t² c2 + t³p3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cubic {
    /// Start.
    pub p0: Vec2,
    /// First control point.
    pub c1: Vec2,
    /// Second control point.
    pub c2: Vec2,
    /// End.
    pub p3: Vec2,
}

impl Cubic {
    /// The point at parameter `t` in [0, 1].
    pub fn point(&self, t: f64) -> Vec2 {
        let s = 1.0 - t;
        self.p0 * (s * s * s)
            + self.c1 * (3.0 * s * s * t)
            + self.c2 * (3.0 * s * t * t)
            + self.p3 * (t * t * t)
    }

    /// B′(t).
    pub fn derivative(&self, t: f64) -> Vec2 {
        let s = 1.0 - t;
        (self.c1 - self.p0) * (3.0 * s * s)
            + (self.c2 - self.c1) * (6.0 * s * t)
            + (self.p3 - self.c2) * (3.0 * t * t)
    }

    /// The cubic from `p0` to `p3` leaving along the unit tangent `t0` and arriving along
    /// `t3`, with the handles of a circular arc: for tangents θ apart, each handle is
    /// (2/3)·tan(θ/4)/sin(θ/2) of the chord, which is (4/3)·tan(θ/4)·R on a circle of
    /// radius R (the standard arc approximation) and a third of the chord as θ → 0.
    pub fn hermite(p0: Vec2, t0: Vec2, p3: Vec2, t3: Vec2) -> Cubic {
        let chord = (p3 - p0).norm();
        let theta = t0.dot(&t3).clamp(-1.0, 1.0).acos();
        let handle = if theta < 1e-6 {
            chord / 3.0
        } else {
            chord * (2.0 / 3.0) * (theta / 4.0).tan() / (theta / 2.0).sin()
        };
        Cubic {
            p0,
            c1: p0 + t0 * handle,
            c2: p3 - t3 * handle,
            p3,
        }
    }

    /// The same curve run backwards.
    pub fn reversed(&self) -> Cubic {
        Cubic {
            p0: self.p3,
            c1: self.c2,
            c2: self.c1,
            p3: self.p0,
        }
    }

    /// The part between parameters `t0` and `t1` (de Casteljau, exact).
    pub fn split(&self, t0: f64, t1: f64) -> Cubic {
        if t1 < t0 {
            return self.split(t1, t0).reversed();
        }
        // The tail from t0, then its head up to where t1 falls in it.
        let tail = self.tail(t0);
        if t0 >= 1.0 {
            return tail;
        }
        tail.head((t1 - t0) / (1.0 - t0))
    }

    fn head(&self, t: f64) -> Cubic {
        let lerp = |a: Vec2, b: Vec2| a + (b - a) * t;
        let (a, b, c) = (
            lerp(self.p0, self.c1),
            lerp(self.c1, self.c2),
            lerp(self.c2, self.p3),
        );
        let (d, e) = (lerp(a, b), lerp(b, c));
        Cubic {
            p0: self.p0,
            c1: a,
            c2: d,
            p3: lerp(d, e),
        }
    }

    fn tail(&self, t: f64) -> Cubic {
        self.reversed().head(1.0 - t).reversed()
    }

    /// The cubic with `f` applied to its four points (exact for an affine `f`: the sheet's
    /// placement, mirroring, moving onto a page).
    pub fn mapped(&self, f: impl Fn(Vec2) -> Vec2) -> Cubic {
        Cubic {
            p0: f(self.p0),
            c1: f(self.c1),
            c2: f(self.c2),
            p3: f(self.p3),
        }
    }

    /// Parameters of a uniform subdivision whose chords stay within `tolerance` of the
    /// curve: a chord over a parameter step h strays at most h²/8 · max|B″|, and
    /// |B″| ≤ 6·max(|p0 − 2c1 + c2|, |c1 − 2c2 + p3|).
    pub fn flatten_params(&self, tolerance: f64) -> Vec<f64> {
        let m = (self.p0 - self.c1 * 2.0 + self.c2)
            .norm()
            .max((self.c1 - self.c2 * 2.0 + self.p3).norm());
        let n = ((0.75 * m / tolerance).sqrt().ceil() as usize).clamp(1, 4096);
        (0..=n).map(|i| i as f64 / n as f64).collect()
    }

    /// The chords' ends, from `p0` to `p3`, within `tolerance` of the curve.
    pub fn flatten(&self, tolerance: f64) -> Vec<Vec2> {
        let mut points: Vec<Vec2> = self
            .flatten_params(tolerance)
            .into_iter()
            .map(|t| self.point(t))
            .collect();
        // The ends exactly, so joined strokes stay joined.
        points[0] = self.p0;
        *points.last_mut().expect("two points") = self.p3;
        points
    }

    /// Cumulative arc length at `TABLE + 1` evenly spaced parameters.
    fn length_table(&self) -> [f64; TABLE + 1] {
        // Each step's length by three-point Gauss–Legendre on |B′|.
        let h = 1.0 / TABLE as f64;
        let mut table = [0.0; TABLE + 1];
        for i in 1..=TABLE {
            table[i] = table[i - 1] + self.length_between((i - 1) as f64 * h, i as f64 * h);
        }
        table
    }

    /// Arc length (mm).
    pub fn length(&self) -> f64 {
        self.length_table()[TABLE]
    }

    /// The parameter at arc length `s` from `p0` (clamped to the curve).
    pub fn param_at_length(&self, s: f64) -> f64 {
        let table = self.length_table();
        self.param_in(&table, s)
    }

    /// The part between arc lengths `a` and `b` from `p0`.
    pub fn between_lengths(&self, a: f64, b: f64) -> Cubic {
        let table = self.length_table();
        self.split(self.param_in(&table, a), self.param_in(&table, b))
    }

    /// Arc length from `t0` to `t1`, both in one step of the table (Gauss–Legendre).
    fn length_between(&self, t0: f64, t1: f64) -> f64 {
        let (mid, half) = ((t0 + t1) / 2.0, (t1 - t0) / 2.0);
        GAUSS_3
            .iter()
            .map(|(x, w)| w * self.derivative(mid + x * half).norm())
            .sum::<f64>()
            * half
    }

    /// The parameter at length `s` given this cubic's [`Cubic::length_table`]: found in
    /// the table, then made exact by Newton steps on the length within the step.
    fn param_in(&self, table: &[f64; TABLE + 1], s: f64) -> f64 {
        if s <= 0.0 {
            return 0.0;
        }
        if s >= table[TABLE] {
            return 1.0;
        }
        let i = table.partition_point(|&l| l <= s).clamp(1, TABLE);
        let (l0, l1) = (table[i - 1], table[i]);
        let t0 = (i - 1) as f64 / TABLE as f64;
        let f = if l1 > l0 { (s - l0) / (l1 - l0) } else { 0.0 };
        let mut t = t0 + f / TABLE as f64;
        for _ in 0..3 {
            let speed = self.derivative(t).norm();
            if speed <= 0.0 {
                break;
            }
            let error = l0 + self.length_between(t0, t) - s;
            t = (t - error / speed).clamp(t0, i as f64 / TABLE as f64);
        }
        t
    }
}

/// Three-point Gauss–Legendre nodes and weights on [−1, 1].
const GAUSS_3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// The unit tangent at `p` of the circle through `a`, `p`, `b` (the chord direction when
/// they are in line): exact for points on a circle, however unevenly spaced.
fn circle_tangent(a: Vec2, p: Vec2, b: Vec2) -> Vec2 {
    let (u, w) = (p - a, b - p);
    let cross = u.x * w.y - u.y * w.x;
    let (lu, lw, lc) = (u.norm(), w.norm(), (b - a).norm());
    if cross.abs() < 1e-12 * lu * lw {
        return (b - a).normalize();
    }
    // R = |u||w||u + w| / (2|u × w|); the chord u subtends 2·asin(|u|/2R), and the tangent
    // at p is u turned by half that, towards the turn.
    let radius = lu * lw * lc / (2.0 * cross.abs());
    let half = (lu / (2.0 * radius)).clamp(-1.0, 1.0).asin() * cross.signum();
    let d = u / lu;
    Vec2::new(
        d.x * half.cos() - d.y * half.sin(),
        d.x * half.sin() + d.y * half.cos(),
    )
}

/// The tangent at the end `p` of an open chain, the next two points being `q`, `r`: that
/// of the circle through all three.
fn end_tangent(p: Vec2, q: Vec2, r: Vec2) -> Vec2 {
    // On a circle the tangents at the two ends of a chord make equal angles with it, on
    // either side: the tangent at p is the one at q reflected in the chord.
    let tq = circle_tangent(p, q, r);
    let d = (q - p).normalize();
    d * (2.0 * d.dot(&tq)) - tq
}

/// A smooth curve through a crease chain's vertices (see the module's note), with arc
/// length along it.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothCurve {
    points: Vec<Vec2>,
    closed: bool,
    pieces: Vec<Cubic>,
    /// Arc length at each point (a closed curve's last entry is its whole length).
    knots: Vec<f64>,
}

impl SmoothCurve {
    /// The curve through `points` (at least two, consecutive ones distinct), back to the
    /// first if `closed`.
    pub fn through(points: Vec<Vec2>, closed: bool) -> SmoothCurve {
        let n = points.len();
        let tangents: Vec<Vec2> = (0..n)
            .map(|i| {
                let at = |k: isize| points[(k.rem_euclid(n as isize)) as usize];
                let i = i as isize;
                if closed && n >= 3 {
                    circle_tangent(at(i - 1), at(i), at(i + 1))
                } else if n == 2 {
                    (points[1] - points[0]).normalize()
                } else if i == 0 {
                    end_tangent(points[0], points[1], points[2])
                } else if i as usize == n - 1 {
                    -end_tangent(points[n - 1], points[n - 2], points[n - 3])
                } else {
                    circle_tangent(at(i - 1), at(i), at(i + 1))
                }
            })
            .collect();
        let count = if closed { n } else { n - 1 };
        let pieces: Vec<Cubic> = (0..count)
            .map(|i| {
                let j = (i + 1) % n;
                Cubic::hermite(points[i], tangents[i], points[j], tangents[j])
            })
            .collect();
        let mut knots = vec![0.0];
        for p in &pieces {
            knots.push(knots[knots.len() - 1] + p.length());
        }
        SmoothCurve {
            points,
            closed,
            pieces,
            knots,
        }
    }

    /// The points it passes through.
    pub fn points(&self) -> &[Vec2] {
        &self.points
    }

    /// Whether it closes on itself.
    pub fn closed(&self) -> bool {
        self.closed
    }

    /// Its cubics, one per chord.
    pub fn pieces(&self) -> &[Cubic] {
        &self.pieces
    }

    /// Arc length at each of its points, from the first; a closed curve ends with its
    /// whole length, back at the first point.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// Whole arc length (mm).
    pub fn length(&self) -> f64 {
        self.knots[self.knots.len() - 1]
    }

    /// The curve with `f` applied to its points, built again (the construction commutes
    /// with similarities, so for the sheet's placement this is the placed curve).
    pub fn mapped(&self, f: impl Fn(Vec2) -> Vec2) -> SmoothCurve {
        SmoothCurve::through(self.points.iter().map(|&p| f(p)).collect(), self.closed)
    }

    /// The piece holding arc length `s` and the length along that piece.
    fn locate(&self, s: f64) -> (usize, f64) {
        let s = s.clamp(0.0, self.length());
        let i = (self.knots.partition_point(|&k| k <= s).max(1) - 1).min(self.pieces.len() - 1);
        (i, s - self.knots[i])
    }

    /// The point at arc length `s`.
    pub fn point_at(&self, s: f64) -> Vec2 {
        let (i, along) = self.locate(s);
        let piece = &self.pieces[i];
        piece.point(piece.param_at_length(along))
    }

    /// The unit tangent at arc length `s`.
    pub fn tangent_at(&self, s: f64) -> Vec2 {
        let (i, along) = self.locate(s);
        let piece = &self.pieces[i];
        piece.derivative(piece.param_at_length(along)).normalize()
    }

    /// One cubic for the stretch between arc lengths `a` < `b`: exact when it lies in one
    /// piece, else the arc-handled cubic between its end points and tangents (exact on a
    /// circle, and within [`FLATTEN_MM`] of the curve for a dash on any curve this tool
    /// makes — the tests measure it).
    pub fn cubic_between(&self, a: f64, b: f64) -> Cubic {
        let (i, from) = self.locate(a);
        let (j, to) = self.locate(b);
        if i == j {
            return self.pieces[i].between_lengths(from, to);
        }
        // At a knot, the piece ending there.
        if j == i + 1 && to <= 1e-12 {
            return self.pieces[i].between_lengths(from, self.knots[j] - self.knots[i]);
        }
        Cubic::hermite(
            self.point_at(a),
            self.tangent_at(a),
            self.point_at(b),
            self.tangent_at(b),
        )
    }

    /// The exact cubics of the stretch between arc lengths `a` < `b`, one per piece it
    /// crosses.
    pub fn span(&self, a: f64, b: f64) -> Vec<Cubic> {
        let (i, from) = self.locate(a);
        let (j, to) = self.locate(b);
        (i..=j)
            .filter_map(|k| {
                let piece = &self.pieces[k];
                let lo = if k == i { from } else { 0.0 };
                let hi = if k == j {
                    to
                } else {
                    self.knots[k + 1] - self.knots[k]
                };
                (hi - lo > 1e-9).then(|| piece.between_lengths(lo, hi))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::distance_to_segment;
    use std::f64::consts::PI;

    /// How far `cubic`, standing for the stretch of `curve` between arc lengths `a` < `b`,
    /// strays from it: the largest distance from 33 points along it to the stretch,
    /// flattened to within 10⁻⁶ mm.
    fn stray(curve: &SmoothCurve, cubic: &Cubic, a: f64, b: f64) -> f64 {
        let mut stretch = vec![curve.point_at(a)];
        for piece in curve.span(a, b) {
            stretch.extend(piece.flatten(1e-6).into_iter().skip(1));
        }
        (0..=32)
            .map(|k| {
                let p = cubic.point(k as f64 / 32.0);
                stretch
                    .windows(2)
                    .map(|w| distance_to_segment(p, w[0], w[1]))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    }

    fn on_circle(r: f64, angles: &[f64]) -> Vec<Vec2> {
        angles
            .iter()
            .map(|a| Vec2::new(3.0 + r * a.cos(), -2.0 + r * a.sin()))
            .collect()
    }

    fn off_circle(p: Vec2, r: f64) -> f64 {
        ((p - Vec2::new(3.0, -2.0)).norm() - r).abs()
    }

    #[test]
    fn points_on_a_circle_give_the_circle_even_unevenly_spaced() {
        // Against the closed form: every sample of every piece on the circle, to the
        // arc Bézier's own error (about 10⁻⁶ R for a 30° piece).
        let r = 40.0;
        let angles = [0.1, 0.35, 0.5, 0.9, 1.2, 1.25, 1.6];
        for closed in [false, true] {
            let angles: Vec<f64> = if closed {
                (0..24)
                    .map(|i| i as f64 * 2.0 * PI / 24.0 + 0.01 * (i % 3) as f64)
                    .collect()
            } else {
                angles.to_vec()
            };
            let curve = SmoothCurve::through(on_circle(r, &angles), closed);
            for piece in curve.pieces() {
                for k in 0..=50 {
                    let p = piece.point(k as f64 / 50.0);
                    assert!(off_circle(p, r) < 1e-5 * r, "{} off", off_circle(p, r));
                }
            }
            // Its length is the arc's.
            let arc = if closed {
                2.0 * PI * r
            } else {
                (angles[angles.len() - 1] - angles[0]) * r
            };
            assert!(
                (curve.length() - arc).abs() < 1e-5 * arc,
                "{} vs {arc}",
                curve.length()
            );
        }
    }

    #[test]
    fn the_curve_is_smooth_at_its_points_and_passes_through_them() {
        // G1: the tangents of the pieces on either side of a point agree; and the curve
        // holds each point exactly.
        let points: Vec<Vec2> = (0..12)
            .map(|i| {
                let x = i as f64 * 4.0;
                Vec2::new(x, 6.0 * (x / 9.0).sin())
            })
            .collect();
        let curve = SmoothCurve::through(points.clone(), false);
        for (i, w) in curve.pieces().windows(2).enumerate() {
            let (out, into) = (
                w[0].derivative(1.0).normalize(),
                w[1].derivative(0.0).normalize(),
            );
            assert!((out - into).norm() < 1e-12);
            assert_eq!(w[0].p3, points[i + 1]);
        }
        // Its point at each knot is the point.
        for (k, p) in curve.knots().iter().zip(&points) {
            assert!((curve.point_at(*k) - p).norm() < 1e-6);
        }
    }

    #[test]
    fn flattening_keeps_within_its_tolerance_and_splitting_is_exact() {
        let c = Cubic {
            p0: Vec2::new(0.0, 0.0),
            c1: Vec2::new(10.0, 20.0),
            c2: Vec2::new(30.0, -15.0),
            p3: Vec2::new(40.0, 5.0),
        };
        for tol in [0.05, 0.005] {
            let ts = c.flatten_params(tol);
            for w in ts.windows(2) {
                let (a, b) = (c.point(w[0]), c.point(w[1]));
                // Brute force: the curve between them against the chord.
                for k in 0..=20 {
                    let t = w[0] + (w[1] - w[0]) * k as f64 / 20.0;
                    let p = c.point(t);
                    let d = b - a;
                    let along = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
                    assert!((a + d * along - p).norm() <= tol);
                }
            }
        }
        // A split part traces the same points as the whole.
        let part = c.split(0.3, 0.8);
        for k in 0..=10 {
            let u = k as f64 / 10.0;
            assert!((part.point(u) - c.point(0.3 + 0.5 * u)).norm() < 1e-12);
        }
        let back = c.split(0.8, 0.3);
        assert!((back.point(0.0) - c.point(0.8)).norm() < 1e-12);
        // Lengths: the parts of a cut add up to the whole.
        let (l, a, b) = (
            c.length(),
            c.split(0.0, 0.4).length(),
            c.split(0.4, 1.0).length(),
        );
        assert!((a + b - l).abs() < 1e-6 * l);
        let t = c.param_at_length(a);
        assert!((t - 0.4).abs() < 1e-9, "{t}");
        // A part cut at given lengths is that long.
        let part = c.between_lengths(3.0, 4.5);
        assert!((part.length() - 1.5).abs() < 1e-9, "{}", part.length());
    }

    #[test]
    fn a_dash_across_a_knot_stays_on_the_curve() {
        // A sine through coarse samples (5 mm apart, radius of curvature down to 18 mm):
        // the one-cubic dash across a knot strays from the curve by under 0.002 mm, well
        // inside the flattening tolerance (a wrong tangent or handle strays by tenths).
        let points: Vec<Vec2> = (0..10)
            .map(|i| {
                let x = i as f64 * 5.0;
                Vec2::new(x, 8.0 * (x / 12.0).sin())
            })
            .collect();
        let curve = SmoothCurve::through(points, false);
        for k in 1..curve.knots().len() - 1 {
            let (a, b) = (curve.knots()[k] - 1.5, curve.knots()[k] + 1.5);
            let dash = curve.cubic_between(a, b);
            let stray = stray(&curve, &dash, a, b);
            assert!(stray < 0.002, "{stray} mm at knot {k}");
        }
        // On a circle, exact.
        let curve = SmoothCurve::through(on_circle(10.0, &[0.0, 0.4, 0.8, 1.2]), false);
        let dash = curve.cubic_between(2.0, 6.0);
        for k in 0..=20 {
            assert!(off_circle(dash.point(k as f64 / 20.0), 10.0) < 1e-5);
        }
    }
}
