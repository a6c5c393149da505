//! The freeform solver: null-space steps keep the conditions to first order, Newton
//! removes the drift, long drags keep every condition, a drag that cannot converge says
//! so. Design scripts and the `deform`, `fold` and `info` commands are `design_scripts.rs`.

use crease::constraints::{ConstraintSet, Reference};
use crease::fab::{verify, Tolerances};
use crease::generate::{generate, Params, PatternKind};
use crease::mesh::{Mesh, Vec3};
use crease::pipeline::{run_design, DesignJob, PipelineError};
use crease::solver::{Move, Options, Solver, SolverError, Stage};

fn miura() -> Mesh {
    generate(&Params::defaults(PatternKind::Miura)).unwrap()
}

#[test]
fn a_null_space_step_keeps_the_conditions_to_first_order() {
    let m = miura();
    let set = ConstraintSet::default_for(&Reference::new(&m));
    let fixed = Solver::default_fixed(&m, &[0]);
    let mut s = Solver::new(m.clone(), set.clone(), &fixed, Options::default()).unwrap();
    let mut dx0 = vec![Vec3::zeros(); m.vertex_count()];
    dx0[0] = Vec3::new(0.0, 0.0, 1.0);
    dx0[10] = Vec3::new(0.5, -0.3, 0.2);
    let dx = s.null_space_step(&dx0).unwrap();
    assert!(
        dx.iter().map(|d| d.norm()).sum::<f64>() > 1e-3,
        "the step moves something"
    );
    let reference = Reference::new(&m);
    let r0 = set.evaluate(&m, &reference, m.positions()).residuals;
    // Equality residuals change at second order along dx: halving ε quarters the change.
    let change = |eps: f64| {
        let x: Vec<Vec3> = m
            .positions()
            .iter()
            .zip(&dx)
            .map(|(p, d)| p + d * eps)
            .collect();
        let r = set.evaluate(&m, &reference, &x).residuals;
        r.iter()
            .zip(&r0)
            .fold(0.0f64, |a, (p, q)| a.max((p - q).abs()))
    };
    let (c1, c2) = (change(1e-2), change(5e-3));
    assert!(c1 < 1e-4, "first-order change {c1}");
    assert!(c2 < 0.3 * c1, "second order: {c1:e} then {c2:e}");
    for &v in &fixed {
        assert_eq!(dx[v], Vec3::zeros());
    }
}

#[test]
fn newton_converges_quadratically_from_a_perturbed_state() {
    let mut m = miura();
    let x: Vec<Vec3> = m
        .positions()
        .iter()
        .enumerate()
        .map(|(i, p)| {
            p + Vec3::new(
                ((i * 7) % 5) as f64,
                ((i * 3) % 4) as f64,
                ((i * 11) % 3) as f64,
            ) * 0.02
        })
        .collect();
    m.set_positions(x);
    let set = ConstraintSet::parse("developability,flat-foldability").unwrap();
    let fixed = Solver::default_fixed(&m, &[]);
    let mut s = Solver::new(m, set, &fixed, Options::default()).unwrap();
    assert!(s.residual() > 1e-4);
    let iterations = s.correct().unwrap();
    assert!(s.residual() <= 1e-8);
    assert!(iterations <= 6, "Newton took {iterations} iterations");
}

#[test]
fn a_long_drag_keeps_every_condition_and_moves_toward_the_target() {
    let m = miura();
    let set = ConstraintSet::default_for(&Reference::new(&m));
    let fixed = Solver::default_fixed(&m, &[0, 80]);
    let mut s = Solver::new(m.clone(), set, &fixed, Options::default()).unwrap();
    let targets = [
        (0usize, Vec3::new(-10.0, -10.0, 40.0)),
        (80, Vec3::new(150.0, 140.0, -30.0)),
    ];
    let dist = |s: &Solver| {
        targets
            .iter()
            .map(|(v, t)| (s.positions()[*v] - t).norm())
            .collect::<Vec<_>>()
    };
    let start = dist(&s);
    let steps = 60;
    for k in 0..steps {
        let mut dx0 = vec![Vec3::zeros(); m.vertex_count()];
        for (v, t) in targets {
            dx0[v] = (t - s.positions()[v]) / (steps - k) as f64;
        }
        s.step(&dx0).unwrap();
        assert!(s.residual() <= 1e-8, "step {k}: residual {}", s.residual());
        for &v in &fixed {
            assert_eq!(s.positions()[v], m.positions()[v], "fixed vertex {v} moved");
        }
    }
    let end = dist(&s);
    for (a, b) in start.iter().zip(&end) {
        assert!(b < &(0.5 * a), "dragged vertex got closer: {a} → {b}");
    }
    let report = verify(&s.into_mesh(), None, Tolerances::default());
    assert!(report.pass(), "{report}");
}

#[test]
fn a_solve_that_cannot_converge_fails_and_says_so() {
    let mut job = DesignJob::new(miura());
    job.stages.push(Stage {
        steps: 1,
        moves: vec![Move {
            vertex: 0,
            to: [0.0, 0.0, 30.0],
        }],
    });
    job.options.max_newton = 0;
    job.options.max_halvings = 0;
    job.options.tolerance = 1e-300;
    let err = run_design(job, &mut |_, _, _| {}).unwrap_err();
    assert!(
        matches!(err, PipelineError::Solver(SolverError::NotConverged { .. })),
        "{err}"
    );
    assert!(!err.is_input_error());
    assert!(err.to_string().contains("did not converge"));
}

#[test]
fn a_drag_from_the_flat_sheet_leaves_the_singular_point_first() {
    use crease::pipeline::{is_flat_start, LEAVE_FLAT_AMOUNT};
    let mut p = Params::defaults(PatternKind::Waterbomb);
    p.fold = None;
    let flat = generate(&p).unwrap();
    assert!(is_flat_start(&flat));
    let start = flat.positions()[40];
    let mut job = DesignJob::new(flat);
    job.stages.push(Stage {
        steps: 20,
        moves: vec![Move {
            vertex: 40,
            to: [start.x, start.y, start.z + 10.0],
        }],
    });
    let outcome = run_design(job, &mut |_, _, _| {}).unwrap();
    let fold = outcome
        .fold
        .expect("the flat sheet is folded a little first");
    assert!(
        (fold.mean_fraction - LEAVE_FLAT_AMOUNT).abs() < 0.01,
        "{fold:?}"
    );
    assert!(!is_flat_start(&outcome.mesh));
    let report = verify(&outcome.mesh, None, Tolerances::default());
    assert!(report.pass(), "{report}");
    let reached = outcome.drags[0].distances[0].2;
    assert!(
        reached < 1.0,
        "vertex 40 is still {reached} mm from its target"
    );
}

/// Drags corner 0 of a `cells`² Miura up by 0.05 mm a step (the benchmark's drag) and
/// returns the solver.
fn corner_drag(cells: usize, steps: usize, predict: Option<bool>) -> Solver {
    corner_path(cells, steps, predict, |_| Vec3::new(0.0, 0.0, 0.05))
}

/// Moves corner 0 of a `cells`² Miura by `wish(k)` at step k and returns the solver.
fn corner_path(
    cells: usize,
    steps: usize,
    predict: Option<bool>,
    wish: impl Fn(usize) -> Vec3,
) -> Solver {
    let m = generate(&Params::square(PatternKind::Miura, cells, 10.0)).unwrap();
    let set = ConstraintSet::default_for(&Reference::new(&m));
    let fixed = Solver::default_fixed(&m, &[0]);
    let options = Options {
        predict,
        ..Options::default()
    };
    let mut s = Solver::new(m.clone(), set, &fixed, options).unwrap();
    let mut dx0 = vec![Vec3::zeros(); m.vertex_count()];
    for k in 0..steps {
        dx0[0] = wish(k);
        s.step(&dx0).unwrap();
    }
    s
}

/// How far apart the same vertex of two solvers' sheets is, at most (mm).
fn farthest_apart(a: &Solver, b: &Solver) -> f64 {
    a.positions()
        .iter()
        .zip(b.positions())
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

#[test]
fn predicting_the_correction_saves_newton_iterations_and_keeps_every_condition() {
    let (plain, predicted) = (
        corner_drag(46, 40, Some(false)),
        corner_drag(46, 40, Some(true)),
    );
    let tolerance = Options::default().tolerance;
    for s in [&plain, &predicted] {
        assert!(s.residual() <= tolerance, "residual {:e}", s.residual());
        assert_eq!(s.stats.halvings, 0);
    }
    let (a, b) = (
        plain.stats.newton_iterations,
        predicted.stats.newton_iterations,
    );
    // The line through the last two corrections lands within the tolerance on most
    // steps, which then need no Newton iteration. (Measured: 26 against 71 here; 141
    // against 225 over 192 steps at 10k vertices.)
    assert!(
        2 * b <= a,
        "{b} Newton iterations with the predictor, {a} without"
    );
    // Once a correction is known, a step's projection rides on its Newton solves: every
    // step but the first and the one after each refactorisation solves only as often
    // as it iterates. (Measured: 27 solves against 111 here.)
    let p = &predicted.stats;
    assert!(p.one_solve_steps + 1 + p.factorisations >= p.steps, "{p:?}");
    assert_eq!(p.solves, p.newton_iterations + p.steps - p.one_solve_steps);
    assert_eq!(plain.stats.solves, a + plain.stats.steps);
    assert!(4 * p.solves <= plain.stats.solves, "{p:?}");
    // The paths differ by the tangential part of each prediction and by the lean of a
    // projection through a factor up to 48 steps old instead of 16: after 2 mm of drag
    // the two sheets are 3 µm apart, far below what a sheet of paper shows.
    let apart = farthest_apart(&plain, &predicted);
    assert!(
        apart > 0.0 && apart < 1e-2,
        "the two paths end {apart:e} mm apart"
    );
}

#[test]
fn the_predictor_is_on_by_default_only_for_large_meshes() {
    let same = |a: &Solver, b: &Solver| a.positions() == b.positions();
    // 15² cells: 450 faces, the designs' size; 46² cells: 4,232 faces.
    assert!(same(
        &corner_drag(15, 3, None),
        &corner_drag(15, 3, Some(false))
    ));
    let large = corner_drag(46, 3, None);
    assert!(large.mesh().faces().len() >= crease::solver::PREDICTOR_FACES);
    assert!(same(&large, &corner_drag(46, 3, Some(true))));
    assert!(!same(&large, &corner_drag(46, 3, Some(false))));
}

/// A corner lifted for 5 steps, then pulled sideways and down by `turn` a step.
fn turning_corner(turn: Vec3) -> Solver {
    corner_path(46, 40, None, |k| {
        if k < 5 {
            Vec3::new(0.0, 0.0, 0.05)
        } else {
            turn
        }
    })
}

#[test]
fn a_stalled_prediction_starts_again_from_the_last_correction() {
    // Some 30 steps after a sharp turn, the line through the last two corrections
    // leaves a residual the aged factor removes too slowly. Newton then starts again
    // from the last correction alone; were the stall a failure instead, the step would
    // be halved.
    let s = turning_corner(Vec3::new(0.1, 0.1, -0.04));
    assert!(s.stats.restarted_predictions >= 1, "{:?}", s.stats);
    assert_eq!(s.stats.halvings, 0);
    assert!(s.residual() <= Options::default().tolerance);
}

#[test]
fn a_slow_chord_that_one_more_iteration_finishes_is_kept() {
    // After a gentler turn a chord stalls too (without the rule, this drag restarts a
    // prediction), but at its rate one more iteration ends the correction, which is
    // cheaper than starting again: no step restarts or halves.
    let s = turning_corner(Vec3::new(0.05, 0.05, -0.02));
    assert_eq!(s.stats.restarted_predictions, 0, "{:?}", s.stats);
    assert_eq!(s.stats.halvings, 0);
    assert!(s.residual() <= Options::default().tolerance);
}

#[test]
fn a_pointer_drag_on_a_large_mesh_steps_live_near_the_full_steps_path_and_its_release_restores_the_tolerance(
) {
    use crease::solver::{
        default_radius, mean_edge, pointer_release, pointer_step, pull, PointerStep,
        POINTER_STEP_CAP, PREDICTOR_FACES,
    };
    use crease::tolerance::LIVE_RESIDUAL;
    // 46² cells: 4,232 faces, so a pointer step is a live one.
    let m = generate(&Params::square(PatternKind::Miura, 46, 10.0)).unwrap();
    assert!(m.faces().len() >= PREDICTOR_FACES);
    let set = ConstraintSet::default_for(&Reference::new(&m));
    let v = m.vertex_count() / 2;
    let fixed = Solver::default_fixed(&m, &[v]);
    let mut live = Solver::new(m.clone(), set.clone(), &fixed, Options::default()).unwrap();
    let mut full = Solver::new(m, set, &fixed, Options::default()).unwrap();
    let start = live.positions()[v];
    let target = start + Vec3::new(30.0, -20.0, 60.0);
    for _ in 0..30 {
        // The same Euler step (§5's pull, capped), taken at full precision.
        let x = full.positions();
        let gap = target - x[v];
        let share = gap * (POINTER_STEP_CAP * mean_edge(full.mesh(), x) / gap.norm()).min(1.0);
        let mut wish = vec![Vec3::zeros(); x.len()];
        pull(x, v, share, default_radius(x), &mut wish);
        full.step(&wish).unwrap();
        assert_eq!(
            pointer_step(&mut live, v, target).unwrap(),
            PointerStep::Moved
        );
        assert!(live.residual() <= LIVE_RESIDUAL, "{:e}", live.residual());
    }
    let tolerance = Options::default().tolerance;
    let (l, f) = (&live.stats, &full.stats);
    // The live steps stopped above the solver's tolerance, and so iterated less and
    // refactorised less. (Measured: 85 Newton iterations and 3 factorisations against
    // 150 and 7.)
    assert!(
        l.worst_residual > tolerance && l.worst_residual <= LIVE_RESIDUAL,
        "{l:?}"
    );
    assert!(f.worst_residual <= tolerance);
    assert!(
        l.newton_iterations * 3 < f.newton_iterations * 2,
        "{l:?} against {f:?}"
    );
    assert!(l.factorisations < f.factorisations, "{l:?} against {f:?}");
    // Near the same path: a looser correction and a factor kept longer let more of each
    // predicted correction's tangential part through, as the predictor's own paths do
    // (measured: the sheets end 0.56 mm apart after the vertex moved 25 mm, 2%; full
    // steps with and without the predictor end 0.06 mm apart). Every state on either
    // path keeps the conditions.
    let moved = (live.positions()[v] - start).norm();
    let apart = farthest_apart(&live, &full);
    assert!(moved > 20.0, "the vertex moved {moved} mm");
    assert!(
        apart < 0.05 * moved,
        "the paths end {apart:e} mm apart after {moved} mm"
    );
    // Let go, the design holds the solver's own tolerance again.
    assert!(pointer_release(&mut live));
    assert!(live.residual() <= tolerance, "{:e}", live.residual());
}
