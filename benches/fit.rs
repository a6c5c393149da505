//! `RAYON_NUM_THREADS=1 cargo bench --bench fit`: time for `crease fit`'s job to converge,
//! a Miura-ori pulled onto a spherical cap of radius 1.5 × its folded span, at about 1k
//! and 5k vertices (the aim: 5k converged in at most 10 s on one core).

use crease::fit::{FitOptions, DEFAULT_STEPS};
use crease::generate::{generate, Params, PatternKind};
use crease::pipeline::{run_design, DesignJob, FitStage};
use crease::surface::shapes::Shape;
use std::sync::Arc;
use std::time::Instant;

fn main() {
    crease::allocator::keep_freed_memory();
    println!(
        "{:<18} {:>9} {:>7} {:>9} {:>9} {:>9} {:>12} {:>10} {:>10}",
        "pattern",
        "vertices",
        "steps",
        "Newton",
        "factors",
        "seconds",
        "largest mm",
        "% diag",
        "stopped"
    );
    for (nx, ny) in [(30, 30), (50, 100)] {
        let mut p = Params::square(PatternKind::Miura, nx, 10.0);
        p.ny = ny;
        let mesh = generate(&p).expect("the Miura-ori generates");
        let (lo, hi) = mesh.bounding_box();
        let span = (hi.x - lo.x).max(hi.y - lo.y);
        let radius = 1.5 * span;
        let target = Shape::Cap { radius }
            .surface(1.6 * span, 64)
            .expect("the cap fits its sphere");
        let vertices = mesh.vertex_count();
        let mut job = DesignJob::new(mesh);
        job.fit = Some(FitStage {
            target: Arc::new(target),
            target_name: "cap".into(),
            align: true,
            options: FitOptions {
                max_steps: DEFAULT_STEPS,
                ..Default::default()
            },
        });
        let started = Instant::now();
        let outcome = run_design(job, &mut |_, _, _| {}).expect("the fit runs");
        let seconds = started.elapsed().as_secs_f64();
        let report = outcome.fit.expect("a fit report");
        println!(
            "{:<18} {:>9} {:>7} {:>9} {:>9} {:>9.2} {:>12.3} {:>10.3} {:>10}",
            format!("miura {nx}x{ny}"),
            vertices,
            report.steps,
            report.newton_iterations,
            outcome.stats.factorisations,
            seconds,
            report.distance.hausdorff_mm,
            100.0 * report.distance.hausdorff_relative,
            report.stopped
        );
    }
}
