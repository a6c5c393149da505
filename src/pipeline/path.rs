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
use crate::fab::{self_intersections, Report, Verdict};
use crate::io::fold::angle_to_fold;
use crate::mesh::{Assignment, Mesh, Vec3};
use crate::solver::{fold_toward, mean_fraction, Mode, Options, Solver};

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

/// A path that ended short of the design's fold angles: the solver's conditions held at
/// every step, but the creases could not follow their drive.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PathShort {
    /// The crease furthest from its angle at the end.
    pub edge: usize,
    /// Its fold angle there (degrees, FOLD's sign: valley positive).
    pub reached_degrees: f64,
    /// The design's angle for it (degrees, FOLD's sign).
    pub design_degrees: f64,
}

/// What folding the design from flat found.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PathReport {
    /// Steps taken (all of them on a clear path).
    pub steps: usize,
    /// Steps the path was divided into.
    pub of: usize,
    /// Whether the panels (faces joined by flat lines) had to bend: folded with rigid
    /// panels the creases stopped short of the design's angles, so the path was folded
    /// again with the flat lines free to fold.
    pub panels_bend: bool,
    /// The most a crease turned against its mountain or valley sign near the flat state
    /// (degrees; 0 on most paths, see [`crate::solver::WRONG_WAY_NEAR_FLAT_RADIANS`]).
    pub wrong_way_degrees: f64,
    /// The first collision, or none.
    pub collision: Option<PathCollision>,
    /// Where the path ended short of the design's angles even with bending panels, or
    /// none. A path with neither a collision nor this is clear.
    pub short: Option<PathShort>,
}

impl PathReport {
    /// No faces pass through each other and the design's angles are reached.
    pub fn is_clear(&self) -> bool {
        self.collision.is_none() && self.short.is_none()
    }
}

impl std::fmt::Display for PathReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let bending = if self.panels_bend {
            " with the panels bending (rigid panels cannot fold it)"
        } else {
            ""
        };
        if let Some(c) = &self.collision {
            return write!(
                f,
                "path from flat: faces {} and {} pass through each other ({:.2} mm deep) at step {} of {} ({:.0}% of the way){bending}",
                c.faces.0,
                c.faces.1,
                c.depth,
                c.step,
                self.of,
                100.0 * c.fraction
            );
        }
        if let Some(s) = &self.short {
            return write!(
                f,
                "path from flat: stops short of the design even with the panels bending: crease {} reaches {:.1}° of its {:.1}°",
                s.edge, s.reached_degrees, s.design_degrees
            );
        }
        write!(
            f,
            "path from flat: clear (folded to the design's angles in {} steps{bending}, no faces passing through each other",
            self.steps
        )?;
        // Below the two decimals shown it would read "0.00°".
        if self.wrong_way_degrees >= 0.005 {
            write!(
                f,
                "; near flat a crease turns up to {:.2}° against its sign",
                self.wrong_way_degrees
            )?;
        }
        write!(f, ")")
    }
}

/// The verdict of a design judged with its path from flat (`verify --path`), decided here
/// for every face: the report's, except that a design that otherwise holds fails when
/// faces pass through each other on the way, and is undecided when the path stops short
/// of its angles or the solver cannot follow it (`path` is then `Err`, saying why).
pub fn verdict_with_path(report: &Report, path: &Result<PathReport, String>) -> Verdict {
    let verdict = report.verdict();
    if !verdict.is_pass() {
        return verdict;
    }
    const CONDITION: &str = "path-from-flat";
    match path {
        Ok(PathReport {
            collision: Some(c),
            of,
            ..
        }) => Verdict::Fail {
            condition: CONDITION,
            at: format!(
                "faces {} and {}, step {} of {of}",
                c.faces.0, c.faces.1, c.step
            ),
            excess: Some(crate::fab::verify::Excess {
                value: c.depth,
                tolerance: 0.0,
            }),
        },
        Ok(p) if p.short.is_some() => Verdict::Undecided {
            condition: CONDITION,
            why: p.to_string(),
        },
        Ok(_) => Verdict::Pass,
        Err(why) => Verdict::Undecided {
            condition: CONDITION,
            why: why.clone(),
        },
    }
}

/// How near the design's angles a path's last step must bring every crease (radians,
/// 0.6°): a design read from a file rounded to six digits lands within 1e-3 of them, one
/// crease saved them itself within 1e-12.
pub const REACHED_RADIANS: f64 = 0.01;

/// Folds `design`'s crease pattern from flat toward the design's own fold angles (the
/// angles its 3D form has, or, for a crease pattern alone, the angles it is drawn at)
/// and reports the first step where faces cross.
pub fn folding_path(design: &Mesh, progress: Progress) -> Result<PathReport, PipelineError> {
    let sheet = foldable_sheet(design)?;
    walk(&sheet, PATH_STEPS, progress, &mut |_, _| {})
}

/// The sheet a design is folded from, in the design's 3D form: the design itself when it
/// has its crease pattern, a 3D-only form with its unfolding, a tube cut open along its
/// seam into its strip (the seam closes as the strip folds; face numbers are the tube's).
pub fn foldable_sheet(design: &Mesh) -> Result<std::borrow::Cow<'_, Mesh>, PipelineError> {
    use crate::geometry::unfold::{sheet_of, PatternFrom};
    sheet_of(design, PatternFrom::Stored).map_err(|e| {
        PipelineError::Input(if design.is_tube() {
            format!("the tube cannot be cut open into its strip: {e}")
        } else {
            format!("the design has only a 3D form and it cannot be unfolded into a crease pattern: {e}")
        })
    })
}

/// The path from flat of a design with its crease pattern ([`foldable_sheet`]) in `steps` even steps, calling `frame` with each state the path
/// reaches (step 0 the flat sheet) and its fraction of the way; the report as
/// [`folding_path`]'s.
///
/// Panels are rigid first; when the creases stop short of the design's angles (a square
/// twist) or the solver cannot follow, the path is folded again from flat with the flat
/// lines free to fold, and `frame` sees the sheet flat again (fraction 0).
pub(super) fn walk(
    design: &Mesh,
    steps: usize,
    progress: Progress,
    frame: &mut dyn FnMut(f64, &[Vec3]),
) -> Result<PathReport, PipelineError> {
    match walk_with(design, steps, false, progress, frame) {
        Ok(report) if report.short.is_none() => Ok(report),
        rigid => match walk_with(design, steps, true, progress, frame) {
            Ok(bending) => Ok(bending),
            // The rigid path's own finding (or failure) says more than the bent one's.
            Err(_) => rigid,
        },
    }
}

fn walk_with(
    design: &Mesh,
    steps: usize,
    bend: bool,
    progress: Progress,
    frame: &mut dyn FnMut(f64, &[Vec3]),
) -> Result<PathReport, PipelineError> {
    let flat = design
        .crease_pattern()
        .map(<[_]>::to_vec)
        .expect("walk is given a design with its crease pattern (foldable_sheet)");
    let mut angles = design.clone();
    if angles.has_3d() {
        record_fold_angles(&mut angles);
    }
    let mut start = design.clone();
    start.set_positions(flat.iter().map(|p| Vec3::new(p.x, p.y, 0.0)).collect());
    let mut driven = 0;
    // An edge with paper on one side only (a tube's seam on its strip) has no fold angle
    // to drive, whatever the file recorded for it.
    let hinges: Vec<bool> = design
        .topology()
        .edge_faces
        .iter()
        .map(|sides| sides.iter().all(Option::is_some))
        .collect();
    for ((edge, shaped), hinge) in start.edges_mut().iter_mut().zip(angles.edges()).zip(hinges) {
        edge.fold_angle = 0.0;
        if bend && edge.assignment == Assignment::Flat {
            edge.alpha = crate::limits::ALPHA.max;
        }
        edge.target = if hinge && shaped.fold_angle.abs() > crate::tolerance::SAME_ANGLE_RADIANS {
            driven += 1;
            shaped.fold_angle
        } else {
            0.0
        };
    }
    frame(0.0, start.positions());
    let mut report = PathReport {
        steps: 0,
        of: steps,
        panels_bend: bend,
        wrong_way_degrees: 0.0,
        collision: None,
        short: None,
    };
    if driven == 0 {
        return Ok(report);
    }
    let anchor = Solver::default_fixed(&start, &[]);
    let mut solver = Solver::new(start, Mode::folding_set(), &anchor, Options::default())?;
    for step in 1..=steps {
        let fraction = step as f64 / steps as f64;
        let folded = fold_toward(
            &mut solver,
            fraction,
            continuation_steps(steps),
            &mut |_| {},
        )?;
        report.steps = step;
        report.wrong_way_degrees = report.wrong_way_degrees.max(folded.wrong_way.to_degrees());
        progress("path", step, steps);
        frame(fraction, solver.positions());
        report.collision = first_crossing(&solver, step, fraction);
        if report.collision.is_some() {
            return Ok(report);
        }
    }
    report.short = furthest_from_target(&solver)
        .filter(|s| (s.reached_degrees - s.design_degrees).abs().to_radians() > REACHED_RADIANS);
    Ok(report)
}

/// Folds `state` (the crease pattern at the design, its creases' targets the design's
/// angles) on from the design until every mountain and valley crease is folded flat
/// (±180°), in `steps` even steps, calling `frame` with each state; checks each for faces
/// passing through each other as the path from flat does. The first collision, if any.
/// Flat is the limit where layers touch: the last step's contact is not a crossing, so
/// a wrong stacking shows on the steps before it, where the layers are still apart.
pub(super) fn on_to_flat(
    sheet: &Mesh,
    state: &[Vec3],
    steps: usize,
    progress: Progress,
    frame: &mut dyn FnMut(&[Vec3]),
) -> Result<Option<PathCollision>, PipelineError> {
    let mut start = sheet.clone();
    start.set_positions(state.to_vec());
    record_fold_angles(&mut start);
    for edge in start.edges_mut() {
        let folded = edge.fold_angle.abs() > crate::tolerance::SAME_ANGLE_RADIANS;
        if folded && matches!(edge.assignment, Assignment::Mountain | Assignment::Valley) {
            edge.target = edge.fold_angle.signum() * std::f64::consts::PI;
        } else {
            edge.target = 0.0;
        }
    }
    let anchor = Solver::default_fixed(&start, &[]);
    let mut solver = Solver::new(start, Mode::folding_set(), &anchor, Options::default())?;
    if solver.mesh().edges().iter().all(|e| e.target == 0.0) {
        return Ok(None);
    }
    let from = mean_fraction(&solver);
    for step in 1..=steps {
        let amount = from + (1.0 - from) * step as f64 / steps as f64;
        fold_toward(&mut solver, amount, continuation_steps(steps), &mut |_| {})?;
        progress("on to flat", step, steps);
        frame(solver.positions());
        if let Some(hit) = first_crossing(&solver, step, amount) {
            return Ok(Some(hit));
        }
    }
    Ok(None)
}

/// The deepest pair of faces passing through each other at the solver's state, as the
/// collision at `step` (`fraction` of the way), or none.
fn first_crossing(solver: &Solver, step: usize, fraction: f64) -> Option<PathCollision> {
    let mut now = solver.mesh().clone();
    now.set_positions(solver.positions().to_vec());
    self_intersections(&now)
        .iter()
        .max_by(|a, b| a.depth.total_cmp(&b.depth))
        .map(|worst| PathCollision {
            step,
            fraction,
            faces: worst.faces,
            depth: worst.depth,
        })
}

/// The driven crease furthest from its target at the solver's state.
fn furthest_from_target(solver: &Solver) -> Option<PathShort> {
    let folds = &solver.reference().previous_fold;
    solver
        .mesh()
        .edges()
        .iter()
        .enumerate()
        .filter(|(_, e)| e.target != 0.0)
        .max_by(|(a, ea), (b, eb)| {
            (folds[*a] - ea.target)
                .abs()
                .total_cmp(&(folds[*b] - eb.target).abs())
        })
        .map(|(edge, e)| PathShort {
            edge,
            reached_degrees: angle_to_fold(folds[edge]),
            design_degrees: angle_to_fold(e.target),
        })
}

/// Continuation steps of the solver's folding within one step of a path of `steps`: the
/// whole path then takes as many as one fold from flat does (`fold_toward`'s 60), at
/// least two a step (a 961-vertex Miura-ori's ten frames took 40 s at 60 each).
fn continuation_steps(steps: usize) -> usize {
    (60 / steps.max(1)).max(2)
}
