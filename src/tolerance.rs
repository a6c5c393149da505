//! The named tolerances, each with its unit in its name (or "relative" to a stated size)
//! and the reason for its size, in one place: two modules asking the same question ("do
//! the layers close?", "do these images touch?") must get the same answer, and a reader
//! should find every such figure here rather than as a bare exponent in the code.

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

/// The residual verification accepts (radians for the angle conditions, relative to the
/// rest length for lengths): what paper, a blade and a scanner cannot tell apart, and
/// the figure a fold angle must come within of its target to count as drawn there.
pub const VERIFIED_RESIDUAL: f64 = 1e-6;

/// The residual the solver works to on every step (radians, or relative for lengths):
/// two orders below [`VERIFIED_RESIDUAL`], so a solved design always verifies, and no
/// tighter, since each order costs Newton iterations on every step of a drag.
pub const SOLVER_RESIDUAL: f64 = 1e-8;

/// The residual a pointer drag's steps on a large mesh are solved to while the pointer
/// moves (radians, or relative for lengths): what verification accepts, and on a 5 mm
/// edge 5 nm, far below what a screen shows. On the 10k-vertex Miura-ori the last two
/// orders down to [`SOLVER_RESIDUAL`] took half a live step's Newton iterations and
/// most of its refactorisations (the chord crawls there near the flat sheet); the
/// release brings the design back to [`SOLVER_RESIDUAL`].
pub const LIVE_RESIDUAL: f64 = VERIFIED_RESIDUAL;

/// Radians: two angles this close are the same angle but for the rounding of the
/// arithmetic that made them (a target read in degrees and turned to radians, a sum of
/// sector angles): a target is a multiple of π, a boundary angle sum is π, a crease is
/// not driven.
pub const SAME_ANGLE_RADIANS: f64 = 1e-9;

/// The residual a design is polished to before it is saved or handed on (radians, or
/// relative for lengths): four orders below [`SOLVER_RESIDUAL`], so the design's
/// unfolding is isometric to about 1e-12 and verification's 1e-6 is far away.
pub const SAVED_RESIDUAL: f64 = 1e-12;

/// Of the design's bounding-box diagonal (relative): faces closer than this touch rather
/// than cross, in the self-intersection check. Layers of a flat-folded state lie on each
/// other to rounding, about 1e-12 of the size; a real crossing is far deeper.
pub const SELF_CONTACT_RELATIVE: f64 = 1e-9;

/// Of the flat-folded pattern's size (relative): overlaps thinner than this are contact,
/// not overlap, in the layer solver (before the file's rounding is allowed for).
pub const LAYER_OVERLAP_RELATIVE: f64 = 1e-7;

/// The largest part of a drawing's shortest edge its inferred decimal rounding may be
/// (relative): a coarser "rounding" is a grid the values lie on exactly
/// (`io::rounding_of`).
pub const ROUNDING_OF_SHORTEST_EDGE: f64 = 0.01;

/// Of a drawing's diagonal (relative): points of a crease-pattern drawing (SVG, `.cp`)
/// closer than this are one vertex; drawings snap lines by eye, not to 1e-12.
pub const POINT_MERGE_RELATIVE: f64 = 1e-4;

/// Radians: a synthetic edge folded less than this, plus what the file's coordinate
/// rounding can turn its faces by, still joins one flat polygon when FOLD is written.
pub const FLAT_POLYGON_RADIANS: f64 = 1e-9;

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
