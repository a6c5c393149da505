//! Tolerances that more than one module judges by, each named with its unit and kept with
//! the reason for its size: two modules asking the same question ("do the layers close?",
//! "do these images touch?") must get the same answer.

/// Of the design's diagonal, what double precision loses over a walk of reflections and
/// rotations round a vertex or across a pattern (relative, dimensionless).
pub const WALK_RELATIVE: f64 = 1e-6;

/// How many times a file's coordinate rounding a walk can compound: a point is reached
/// through up to eight rounded corners on the paper's typical crease counts.
pub const ROUNDING_COMPOUNDED: f64 = 8.0;

/// The gap (mm) within which flat-folded layers close up, images touch, or points lie in
/// one plane, for a design whose diagonal is `diagonal_mm` and whose file was rounded to
/// `rounding_mm`: [`WALK_RELATIVE`] of the diagonal plus [`ROUNDING_COMPOUNDED`] times the
/// rounding. Verification, the studio's x-ray, the layer solver and the layer-order rows'
/// contacts judge by this one figure, so their verdicts agree.
pub fn closure_mm(diagonal_mm: f64, rounding_mm: f64) -> f64 {
    WALK_RELATIVE * diagonal_mm + ROUNDING_COMPOUNDED * rounding_mm
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closure_grows_with_the_design_and_its_rounding() {
        // A 200 mm design in full precision: 0.2 µm; rounded to 0.001 mm: 8.2 µm.
        assert!((closure_mm(200.0, 0.0) - 2e-4).abs() < 1e-15);
        assert!((closure_mm(200.0, 1e-3) - 8.2e-3).abs() < 1e-15);
    }
}
