//! `cargo bench --bench solver`: one full design step (Jacobian, projection, Newton
//! correction) on Miura-ori of growing size, with a corner being dragged. Set
//! CREASE_BENCH_LARGE=1 to include the 100k-vertex case (a few minutes).
//!
//! Each size is timed over several windows of consecutive steps (each long enough to
//! hold the refactorisations steps share) and the median window is reported with the
//! fastest and slowest: a shared VM's neighbours move single windows by ±15%.

use crease::constraints::{ConstraintSet, Reference};
use crease::generate::{generate, Params, PatternKind};
use crease::mesh::Vec3;
use crease::solver::{Options, Solver};
use std::time::Instant;

// As in the binary (src/main.rs), so the figures are the tool's.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    crease::allocator::set_up();
    // (cells, steps a window, windows): a 10k or 100k window holds one refactorisation,
    // as one in PREDICTED_FACTOR_AGE = 48 steps of a long drag does.
    let mut sizes = vec![(15usize, 400usize, 5usize), (99, 48, 5)];
    if std::env::var("CREASE_BENCH_LARGE").is_ok() {
        sizes.push((315, 48, 3));
    }
    println!(
        "{:>9} {:>8} {:>8} {:>12} {:>16} {:>10} {:>9} {:>9} {:>9}",
        "vertices",
        "rows",
        "steps",
        "ms/step",
        "(min–max)",
        "steps/s",
        "newton/st",
        "solves/st",
        "factor/st"
    );
    for (cells, steps, windows) in sizes {
        let mesh = generate(&Params::square(PatternKind::Miura, cells, 10.0)).unwrap();
        let n = mesh.vertex_count();
        let set = ConstraintSet::default_for(&Reference::new(&mesh));
        let rows = set
            .evaluate(&mesh, &Reference::new(&mesh), mesh.positions())
            .residuals
            .len();
        let fixed = Solver::default_fixed(&mesh, &[0]);
        let mut dx0 = vec![Vec3::zeros(); n];
        dx0[0] = Vec3::new(0.0, 0.0, 0.05);
        // Every window drags the same corner up from the flat sheet, so the windows
        // differ only by the machine's noise.
        let (mut newton, mut solves, mut factorisations) = (0, 0, 0);
        let mut per_window: Vec<f64> = (0..windows)
            .map(|_| {
                let mut solver =
                    Solver::new(mesh.clone(), set.clone(), &fixed, Options::default()).unwrap();
                // One warm-up step (symbolic factorisation), then timed steps.
                solver.step(&dx0).unwrap();
                let before = solver.stats.clone();
                let t = Instant::now();
                for _ in 0..steps {
                    solver.step(&dx0).unwrap();
                }
                let elapsed = t.elapsed().as_secs_f64();
                newton += solver.stats.newton_iterations - before.newton_iterations;
                solves += solver.stats.solves - before.solves;
                factorisations += solver.stats.factorisations - before.factorisations;
                elapsed / steps as f64
            })
            .collect();
        per_window.sort_by(f64::total_cmp);
        let per = per_window[windows / 2];
        let all = (steps * windows) as f64;
        println!(
            "{n:>9} {rows:>8} {:>8} {:>12.3} {:>16} {:>10.1} {:>9.2} {:>9.2} {:>9.2}",
            steps * windows,
            per * 1e3,
            format!(
                "({:.2}–{:.2})",
                per_window[0] * 1e3,
                per_window[windows - 1] * 1e3
            ),
            1.0 / per,
            newton as f64 / all,
            solves as f64 / all,
            factorisations as f64 / all
        );
    }
}
