//! SVG's `transform` attribute and number lists, in full `f64` precision.

use crate::mesh::Vec2;

/// A 2D affine map `p ↦ (a·x + c·y + e, b·x + d·y + f)`, SVG's `matrix(a b c d e f)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine(pub [f64; 6]);

impl Affine {
    /// The identity.
    pub const IDENTITY: Affine = Affine([1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);

    /// Applies the map to a point.
    pub fn apply(&self, p: Vec2) -> Vec2 {
        let [a, b, c, d, e, f] = self.0;
        Vec2::new(a * p.x + c * p.y + e, b * p.x + d * p.y + f)
    }

    /// `self ∘ other`: apply `other` first.
    pub fn then_inner(&self, other: &Affine) -> Affine {
        let [a, b, c, d, e, f] = self.0;
        let [a2, b2, c2, d2, e2, f2] = other.0;
        Affine([
            a * a2 + c * b2,
            b * a2 + d * b2,
            a * c2 + c * d2,
            b * c2 + d * d2,
            a * e2 + c * f2 + e,
            b * e2 + d * f2 + f,
        ])
    }

    /// Scale factor of lengths (geometric mean of the axes).
    pub fn scale(&self) -> f64 {
        let [a, b, c, d, ..] = self.0;
        (a * d - b * c).abs().sqrt()
    }
}

/// Parses an SVG `transform` attribute (a list of matrix, translate, scale, rotate, skewX,
/// skewY), composed left to right as SVG does.
pub fn parse_transform(text: &str) -> Result<Affine, String> {
    let mut result = Affine::IDENTITY;
    let mut rest = text.trim();
    while !rest.is_empty() {
        let open = rest
            .find('(')
            .ok_or_else(|| format!("bad transform \"{}\"", crate::limits::short_text(text)))?;
        // The closing parenthesis is looked for after the opening one: ")(" is malformed.
        let close = rest[open..]
            .find(')')
            .map(|c| open + c)
            .ok_or_else(|| format!("bad transform \"{}\"", crate::limits::short_text(text)))?;
        let name = rest[..open].trim().trim_start_matches(',').trim();
        let args = number_list(&rest[open + 1..close], "transform")?;
        let arg = |i: usize, default: f64| args.get(i).copied().unwrap_or(default);
        let m = match (name, args.len()) {
            ("matrix", 6) => Affine([args[0], args[1], args[2], args[3], args[4], args[5]]),
            ("translate", 1 | 2) => Affine([1.0, 0.0, 0.0, 1.0, args[0], arg(1, 0.0)]),
            ("scale", 1 | 2) => Affine([args[0], 0.0, 0.0, arg(1, args[0]), 0.0, 0.0]),
            ("rotate", 1 | 3) => {
                let (s, c) = args[0].to_radians().sin_cos();
                let (cx, cy) = (arg(1, 0.0), arg(2, 0.0));
                let r = Affine([c, s, -s, c, 0.0, 0.0]);
                Affine([1.0, 0.0, 0.0, 1.0, cx, cy])
                    .then_inner(&r)
                    .then_inner(&Affine([1.0, 0.0, 0.0, 1.0, -cx, -cy]))
            }
            ("skewX", 1) => Affine([1.0, 0.0, args[0].to_radians().tan(), 1.0, 0.0, 0.0]),
            ("skewY", 1) => Affine([1.0, args[0].to_radians().tan(), 0.0, 1.0, 0.0, 0.0]),
            _ => {
                return Err(format!(
                    "unsupported transform \"{}\" with {} arguments",
                    crate::limits::short_text(name),
                    args.len()
                ))
            }
        };
        result = result.then_inner(&m);
        rest = rest[close + 1..].trim();
    }
    Ok(result)
}

/// Numbers separated by commas or white space (SVG's `points`, transform arguments);
/// a bad one is named with the `context` it was in.
pub fn number_list(text: &str, context: &str) -> Result<Vec<f64>, String> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<f64>().map_err(|_| {
                format!(
                    "bad number \"{}\" in {context}",
                    crate::limits::short_text(s)
                )
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn malformed_transforms_are_errors_not_panics() {
        for t in [
            ")(",
            "translate)(",
            "(",
            ")",
            "matrix(",
            "rotate(1,2",
            "scale)1(",
        ] {
            let e = parse_transform(t).expect_err(t);
            assert!(e.contains("transform"), "{t}: {e}");
        }
        let ok = parse_transform("translate(3) scale(2)").unwrap();
        assert_eq!(ok.0, [2.0, 0.0, 0.0, 2.0, 3.0, 0.0]);
    }

    #[test]
    fn transforms_compose_left_to_right() {
        let m = parse_transform("translate(10,0) scale(2)").unwrap();
        assert_eq!(m.apply(Vec2::new(1.0, 1.0)), Vec2::new(12.0, 2.0));
        let r = parse_transform("rotate(90)").unwrap();
        assert!((r.apply(Vec2::new(1.0, 0.0)) - Vec2::new(0.0, 1.0)).norm() < 1e-12);
        assert!(parse_transform("wobble(3)").is_err());
    }
}
