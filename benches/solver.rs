//! `cargo bench --bench solver`: one full design step (Jacobian, projection, Newton
//! correction) on Miura-ori of growing size, with a corner being dragged. Set
//! CREASE_BENCH_LARGE=1 to include the 100k-vertex case (tens of seconds).

use crease::constraints::{ConstraintSet, Reference};
use crease::generate::{generate, Params, PatternKind};
use crease::mesh::Vec3;
use crease::solver::{Options, Solver};
use std::time::Instant;

// As in the binary (src/main.rs), so the figures are the tool's.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    let mut sizes = vec![(15usize, 400usize), (99, 40)];
    if std::env::var("CREASE_BENCH_LARGE").is_ok() {
        sizes.push((315, 20));
    }
    println!(
        "{:>9} {:>8} {:>8} {:>12} {:>10} {:>9} {:>9}",
        "vertices", "rows", "steps", "ms/step", "steps/s", "newton/st", "factor/st"
    );
    for (cells, steps) in sizes {
        let mesh = generate(&Params::square(PatternKind::Miura, cells, 10.0)).unwrap();
        let n = mesh.vertex_count();
        let set = ConstraintSet::default_for(&Reference::new(&mesh));
        let rows = set
            .evaluate(&mesh, &Reference::new(&mesh), mesh.positions())
            .residuals
            .len();
        let fixed = Solver::default_fixed(&mesh, &[0]);
        let mut solver = Solver::new(mesh, set, &fixed, Options::default()).unwrap();
        let mut dx0 = vec![Vec3::zeros(); n];
        dx0[0] = Vec3::new(0.0, 0.0, 0.05);
        // One warm-up step (symbolic factorisation), then timed steps.
        solver.step(&dx0).unwrap();
        let before = solver.stats.clone();
        let t = Instant::now();
        for _ in 0..steps {
            solver.step(&dx0).unwrap();
        }
        let per = t.elapsed().as_secs_f64() / steps as f64;
        println!(
            "{n:>9} {rows:>8} {steps:>8} {:>12.3} {:>10.1} {:>9.2} {:>9.2}",
            per * 1e3,
            1.0 / per,
            (solver.stats.newton_iterations - before.newton_iterations) as f64 / steps as f64,
            (solver.stats.factorisations - before.factorisations) as f64 / steps as f64
        );
    }
}
