//! SVG path data in full `f64` precision, with Bézier curves and elliptical
//! arcs flattened to polylines within [`CURVE_TOLERANCE_MM`].

use super::svg_transform::Affine;
use crate::mesh::Vec2;
use std::f64::consts::PI;

/// Largest distance between a flattened curve and the true one, in millimetres.
pub const CURVE_TOLERANCE_MM: f64 = 0.02;

struct Tokens<'a> {
    s: &'a [u8],
    i: usize,
}

impl Tokens<'_> {
    fn skip_separators(&mut self) {
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_whitespace() || self.s[self.i] == b',')
        {
            self.i += 1;
        }
    }

    fn command(&mut self) -> Option<u8> {
        self.skip_separators();
        let c = *self.s.get(self.i)?;
        if c.is_ascii_alphabetic() && c != b'e' && c != b'E' {
            self.i += 1;
            Some(c)
        } else {
            None
        }
    }

    fn at_number(&mut self) -> bool {
        self.skip_separators();
        matches!(self.s.get(self.i), Some(c) if c.is_ascii_digit() || *c == b'-' || *c == b'+' || *c == b'.')
    }

    fn number(&mut self) -> Result<f64, String> {
        self.skip_separators();
        let start = self.i;
        let s = self.s;
        let mut i = self.i;
        if i < s.len() && (s[i] == b'-' || s[i] == b'+') {
            i += 1;
        }
        let mut seen_dot = false;
        while i < s.len() && (s[i].is_ascii_digit() || (s[i] == b'.' && !seen_dot)) {
            seen_dot |= s[i] == b'.';
            i += 1;
        }
        if i < s.len() && (s[i] == b'e' || s[i] == b'E') {
            let mut j = i + 1;
            if j < s.len() && (s[j] == b'-' || s[j] == b'+') {
                j += 1;
            }
            if j < s.len() && s[j].is_ascii_digit() {
                i = j;
                while i < s.len() && s[i].is_ascii_digit() {
                    i += 1;
                }
            }
        }
        self.i = i;
        std::str::from_utf8(&s[start..i])
            .ok()
            .and_then(|t| t.parse().ok())
            .ok_or_else(|| format!("bad number in path data at character {start}"))
    }

    fn flag(&mut self) -> Result<bool, String> {
        self.skip_separators();
        match self.s.get(self.i) {
            Some(b'0') => {
                self.i += 1;
                Ok(false)
            }
            Some(b'1') => {
                self.i += 1;
                Ok(true)
            }
            _ => Err(format!("bad arc flag in path data at character {}", self.i)),
        }
    }
}

/// Flattens path data into polylines (one per subpath) in the coordinates `to_mm` maps to.
/// Curves are subdivided there, so the tolerance holds in millimetres.
pub fn flatten_path(d: &str, to_mm: &Affine) -> Result<Vec<Vec<Vec2>>, String> {
    let mut t = Tokens {
        s: d.as_bytes(),
        i: 0,
    };
    let mut pen = Pen {
        to_mm,
        paths: Vec::new(),
        current: Vec::new(),
        pos: Vec2::zeros(),
        start: Vec2::zeros(),
        last_control: None,
    };
    let mut cmd = t
        .command()
        .ok_or("path data does not start with a command")?;
    if cmd != b'M' && cmd != b'm' {
        return Err("path data does not start with a move".into());
    }
    loop {
        let rel = cmd.is_ascii_lowercase();
        let base = if rel { pen.pos } else { Vec2::zeros() };
        let upper = cmd.to_ascii_uppercase();
        if upper == b'M' {
            pen.move_to(Vec2::new(t.number()?, t.number()?) + base);
            // Further pairs after a move are line-tos.
            cmd = if rel { b'l' } else { b'L' };
            if !t.at_number() {
                match t.command() {
                    Some(c) => cmd = c,
                    None => break,
                }
            }
            continue;
        }
        pen.draw(upper, rel, base, &mut t)?;
        // Repeated parameters continue the same command; Z takes none.
        if upper == b'Z' || !t.at_number() {
            match t.command() {
                Some(c) => cmd = c,
                None => break,
            }
        }
    }
    if t.i < t.s.len() {
        t.skip_separators();
        if t.i < t.s.len() {
            return Err(format!("unexpected character in path data at {}", t.i));
        }
    }
    if pen.current.len() > 1 {
        pen.paths.push(pen.current);
    }
    Ok(pen.paths)
}

/// Where a path's drawing stands: the subpaths done, the one being drawn (in mm), the
/// current point and the subpath's start (in path units), and the last curve's second
/// control point, which a smooth curve (`S`, `T`) reflects.
struct Pen<'a> {
    to_mm: &'a Affine,
    paths: Vec<Vec<Vec2>>,
    current: Vec<Vec2>,
    pos: Vec2,
    start: Vec2,
    last_control: Option<(u8, Vec2)>,
}

impl Pen<'_> {
    /// `M`: ends the subpath being drawn and starts one at `p`.
    fn move_to(&mut self, p: Vec2) {
        if self.current.len() > 1 {
            self.paths.push(std::mem::take(&mut self.current));
        }
        self.pos = p;
        self.start = p;
        self.current = vec![self.to_mm.apply(p)];
        self.last_control = None;
    }

    /// One drawing command (`upper`: L, H, V, C, S, Q, T, A or Z), its parameters read
    /// from `t`, relative to `base` when `rel`.
    fn draw(&mut self, upper: u8, rel: bool, base: Vec2, t: &mut Tokens) -> Result<(), String> {
        let point = |t: &mut Tokens| -> Result<Vec2, String> {
            Ok(base + Vec2::new(t.number()?, t.number()?))
        };
        let pos = self.pos;
        // The reflected control point of a smooth curve following a curve of `kind`.
        let smooth = |kind: u8, last: Option<(u8, Vec2)>| match last {
            Some((k, c)) if k == kind => pos * 2.0 - c,
            _ => pos,
        };
        match upper {
            b'L' => self.pos = point(t)?,
            b'H' => self.pos = Vec2::new(t.number()? + if rel { pos.x } else { 0.0 }, pos.y),
            b'V' => self.pos = Vec2::new(pos.x, t.number()? + if rel { pos.y } else { 0.0 }),
            b'C' | b'S' => {
                let c1 = if upper == b'C' {
                    point(t)?
                } else {
                    smooth(b'C', self.last_control)
                };
                let c2 = point(t)?;
                let end = point(t)?;
                self.cubic_to(c1, c2, end);
                self.last_control = Some((b'C', c2));
            }
            b'Q' | b'T' => {
                let c = if upper == b'Q' {
                    point(t)?
                } else {
                    smooth(b'Q', self.last_control)
                };
                let end = point(t)?;
                // Degree elevation: a quadratic is a cubic with these controls.
                let c1 = pos + (c - pos) * (2.0 / 3.0);
                let c2 = end + (c - end) * (2.0 / 3.0);
                self.cubic_to(c1, c2, end);
                self.last_control = Some((b'Q', c));
            }
            b'A' => {
                let (rx, ry, phi) = (t.number()?, t.number()?, t.number()?);
                let (large, sweep) = (t.flag()?, t.flag()?);
                let end = point(t)?;
                let tol = CURVE_TOLERANCE_MM / self.to_mm.scale().max(1e-300);
                for p in arc(pos, end, rx, ry, phi, large, sweep, tol) {
                    self.current.push(self.to_mm.apply(p));
                }
                self.pos = end;
            }
            b'Z' => {
                self.pos = self.start;
                let start = self.to_mm.apply(self.start);
                self.current.push(start);
                self.paths.push(std::mem::take(&mut self.current));
                self.current = vec![start];
            }
            other => return Err(format!("unknown path command '{}'", other as char)),
        }
        if !matches!(upper, b'C' | b'S' | b'Q' | b'T' | b'Z') {
            self.last_control = None;
        }
        if !matches!(upper, b'C' | b'S' | b'Q' | b'T' | b'A' | b'Z') {
            self.current.push(self.to_mm.apply(self.pos));
        }
        Ok(())
    }

    /// A cubic Bézier from the current point, subdivided in millimetres.
    fn cubic_to(&mut self, c1: Vec2, c2: Vec2, end: Vec2) {
        let ctrl = [self.pos, c1, c2, end].map(|p| self.to_mm.apply(p));
        cubic(ctrl, CURVE_TOLERANCE_MM, 0, &mut self.current);
        self.pos = end;
    }
}

/// Adaptive subdivision until the control polygon is within `tol` of the chord; appends
/// every point but the first.
fn cubic(p: [Vec2; 4], tol: f64, depth: u32, out: &mut Vec<Vec2>) {
    let chord = p[3] - p[0];
    let len = chord.norm();
    let dist = |q: Vec2| {
        if len > 0.0 {
            chord.perp(&(q - p[0])).abs() / len
        } else {
            (q - p[0]).norm()
        }
    };
    if depth >= 16 || dist(p[1]).max(dist(p[2])) <= tol {
        out.push(p[3]);
        return;
    }
    let mid = |a: Vec2, b: Vec2| (a + b) * 0.5;
    let (p01, p12, p23) = (mid(p[0], p[1]), mid(p[1], p[2]), mid(p[2], p[3]));
    let (p012, p123) = (mid(p01, p12), mid(p12, p23));
    let m = mid(p012, p123);
    cubic([p[0], p01, p012, m], tol, depth + 1, out);
    cubic([m, p123, p23, p[3]], tol, depth + 1, out);
}

/// Points along an elliptical arc (SVG implementation notes F.6.5), excluding the start,
/// with chord deviation at most `tol` in the arc's own units.
#[allow(clippy::too_many_arguments)]
fn arc(
    p0: Vec2,
    p1: Vec2,
    rx: f64,
    ry: f64,
    phi_deg: f64,
    large: bool,
    sweep: bool,
    tol: f64,
) -> Vec<Vec2> {
    let (mut rx, mut ry) = (rx.abs(), ry.abs());
    if rx == 0.0 || ry == 0.0 || p0 == p1 {
        return vec![p1];
    }
    let (s, c) = phi_deg.to_radians().sin_cos();
    let d = (p0 - p1) * 0.5;
    let x1 = c * d.x + s * d.y;
    let y1 = -s * d.x + c * d.y;
    let lambda = (x1 * x1) / (rx * rx) + (y1 * y1) / (ry * ry);
    if lambda > 1.0 {
        rx *= lambda.sqrt();
        ry *= lambda.sqrt();
    }
    let num = (rx * rx * ry * ry - rx * rx * y1 * y1 - ry * ry * x1 * x1).max(0.0);
    let den = rx * rx * y1 * y1 + ry * ry * x1 * x1;
    let mut k = (num / den).sqrt();
    if large == sweep {
        k = -k;
    }
    let (cx1, cy1) = (k * rx * y1 / ry, -k * ry * x1 / rx);
    let mid = (p0 + p1) * 0.5;
    let center = Vec2::new(c * cx1 - s * cy1 + mid.x, s * cx1 + c * cy1 + mid.y);
    let angle = |u: Vec2| u.y.atan2(u.x);
    let t0 = angle(Vec2::new((x1 - cx1) / rx, (y1 - cy1) / ry));
    let t1 = angle(Vec2::new((-x1 - cx1) / rx, (-y1 - cy1) / ry));
    let mut dt = t1 - t0;
    if sweep && dt < 0.0 {
        dt += 2.0 * PI;
    } else if !sweep && dt > 0.0 {
        dt -= 2.0 * PI;
    }
    let r = rx.max(ry);
    let step = 2.0 * (1.0 - (tol / r).min(1.0)).acos();
    let n = ((dt.abs() / step.max(1e-6)).ceil() as usize).clamp(1, 10_000);
    (1..=n)
        .map(|i| {
            if i == n {
                return p1;
            }
            let t = t0 + dt * i as f64 / n as f64;
            let (st, ct) = t.sin_cos();
            Vec2::new(
                center.x + c * rx * ct - s * ry * st,
                center.y + s * rx * ct + c * ry * st,
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compact_numbers_and_implicit_line_tos_parse() {
        let p = flatten_path("M10.5.5l1-1 2,0H20V5z", &Affine::IDENTITY).unwrap();
        let pts = &p[0];
        let expect = [
            (10.5, 0.5),
            (11.5, -0.5),
            (13.5, -0.5),
            (20.0, -0.5),
            (20.0, 5.0),
            (10.5, 0.5),
        ];
        assert_eq!(pts.len(), expect.len());
        for (q, e) in pts.iter().zip(expect) {
            assert!((q - Vec2::new(e.0, e.1)).norm() < 1e-12, "{q:?} vs {e:?}");
        }
    }

    #[test]
    fn flattened_semicircle_stays_within_tolerance_of_the_circle() {
        let p = flatten_path("M0,0 A50,50 0 0 1 100,0", &Affine::IDENTITY).unwrap();
        let c = Vec2::new(50.0, 0.0);
        for w in p[0].windows(2) {
            // Vertices on the circle, chord midpoints within tolerance of it.
            assert!(((w[0] - c).norm() - 50.0).abs() < 1e-9);
            let mid = (w[0] + w[1]) * 0.5;
            assert!(50.0 - (mid - c).norm() <= CURVE_TOLERANCE_MM + 1e-12);
        }
        assert!((p[0].last().unwrap() - Vec2::new(100.0, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn flattened_cubic_stays_within_tolerance_of_the_curve() {
        let ctrl = [
            Vec2::new(0., 0.),
            Vec2::new(0., 80.),
            Vec2::new(100., 80.),
            Vec2::new(100., 0.),
        ];
        let p = flatten_path("M0,0 C0,80 100,80 100,0", &Affine::IDENTITY).unwrap();
        let bez = |t: f64| {
            let u = 1.0 - t;
            ctrl[0] * u * u * u
                + ctrl[1] * 3.0 * u * u * t
                + ctrl[2] * 3.0 * u * t * t
                + ctrl[3] * t * t * t
        };
        let poly = &p[0];
        for k in 0..=1000 {
            let q = bez(k as f64 / 1000.0);
            let d = poly
                .windows(2)
                .map(|w| {
                    let (a, b) = (w[0], w[1]);
                    let t = ((q - a).dot(&(b - a)) / (b - a).norm_squared()).clamp(0.0, 1.0);
                    (a + (b - a) * t - q).norm()
                })
                .fold(f64::INFINITY, f64::min);
            assert!(
                d <= CURVE_TOLERANCE_MM,
                "curve point {k} is {d} mm from the polyline"
            );
        }
    }
}
