//! Foldable from the plane (the paper's §7 lists it among the properties a variation
//! should keep): the design's crease pattern folded in simulation mode from flat to the
//! design's own fold angles, rigid panels where α = 0, in even steps; after each step the
//! 3D form is checked for faces passing through each other.
//!
//! A clear path is one path that works, found by the simulation's own motion (every crease
//! driven in proportion); it does not prove that no other motion collides, and a
//! collision on this path does not prove that every path collides (a maker may fold the
//! flaps one at a time). Contact is not a collision: layers that only touch pass.

use super::{record_fold_angles, PipelineError, Progress};
use crate::fab::self_intersections;
use crate::mesh::{Mesh, Vec3};
use crate::solver::{fold_toward, Mode, Options, Solver};

/// Steps of the path: each a twentieth of the way, so a collision is placed to within 5%
/// of the fold.
pub const PATH_STEPS: usize = 20;

/// The first collision on the path from flat.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PathCollision {
    /// The step (1 ..= steps) after which faces first cross.
    pub step: usize,
    /// How far along the path that is: the creases' mean fraction of the design's angles.
    pub fraction: f64,
    /// The deepest crossing pair there.
    pub faces: (usize, usize),
    /// How far the pierced edge reaches through (mm).
    pub depth: f64,
}

/// What folding the design from flat found.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PathReport {
    /// Steps taken (all of them on a clear path).
    pub steps: usize,
    /// The first collision, or none: the path is clear.
    pub collision: Option<PathCollision>,
}

impl std::fmt::Display for PathReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.collision {
            None => write!(
                f,
                "path from flat: clear (folded to the design's angles in {} steps, no faces passing through each other)",
                self.steps
            ),
            Some(c) => write!(
                f,
                "path from flat: faces {} and {} pass through each other ({:.2} mm deep) at step {} of {} ({:.0}% of the way)",
                c.faces.0,
                c.faces.1,
                c.depth,
                c.step,
                PATH_STEPS,
                100.0 * c.fraction
            ),
        }
    }
}

/// Folds `design`'s crease pattern from flat toward the design's own fold angles (the
/// angles its 3D form has, or, for a crease pattern alone, the angles it is drawn at)
/// and reports the first step where faces cross.
pub fn folding_path(design: &Mesh, progress: Progress) -> Result<PathReport, PipelineError> {
    let Some(flat) = design.flat().map(<[_]>::to_vec) else {
        return Err(PipelineError::Input(
            "the design has no crease pattern to fold from (a 3D-only file: convert it first)"
                .into(),
        ));
    };
    let mut angles = design.clone();
    if angles.has_3d() {
        record_fold_angles(&mut angles);
    }
    let mut start = design.clone();
    start.set_positions(flat.iter().map(|p| Vec3::new(p.x, p.y, 0.0)).collect());
    let mut driven = 0;
    for (edge, shaped) in start.edges_mut().iter_mut().zip(angles.edges()) {
        edge.fold_angle = 0.0;
        edge.target = if shaped.fold_angle.abs() > crate::tolerance::SAME_ANGLE_RADIANS {
            driven += 1;
            shaped.fold_angle
        } else {
            0.0
        };
    }
    if driven == 0 {
        return Ok(PathReport {
            steps: 0,
            collision: None,
        });
    }
    let anchor = Solver::default_fixed(&start, &[]);
    let mut solver = Solver::new(start, Mode::folding_set(), &anchor, Options::default())?;
    for step in 1..=PATH_STEPS {
        let fraction = step as f64 / PATH_STEPS as f64;
        fold_toward(&mut solver, fraction, 4000, &mut |_| {})?;
        progress("path", step, PATH_STEPS);
        let mut now = solver.mesh().clone();
        now.set_positions(solver.positions().to_vec());
        let crossings = self_intersections(&now);
        if let Some(worst) = crossings.iter().max_by(|a, b| a.depth.total_cmp(&b.depth)) {
            return Ok(PathReport {
                steps: step,
                collision: Some(PathCollision {
                    step,
                    fraction,
                    faces: worst.faces,
                    depth: worst.depth,
                }),
            });
        }
    }
    Ok(PathReport {
        steps: PATH_STEPS,
        collision: None,
    })
}
