//! `cargo bench --bench fab`: routing quality (pen-up travel and HP-GL bytes for input
//! order, plain nearest neighbour, and nearest neighbour + 2-opt) on the bundled designs,
//! and the time of a whole `fab` run on a 45k-triangle Miura-ori.

use crease::fab::{route, route::nearest_neighbour_only, score, Toolpath};
use crease::generate::{generate, Params, PatternKind};
use crease::machine::Machine;
use crease::output::hpgl;
use crease::pipeline::{fabricate, FabOptions};
use std::path::Path;
use std::time::Instant;

fn main() {
    let machine = Machine::load("generic-hpgl").unwrap();
    let options = FabOptions {
        media: Some(crease::fab::Media::parse("a3").unwrap()),
        ..Default::default()
    };
    println!(
        "{:<22} {:>7} | {:>22} | {:>22} | {:>22}",
        "design",
        "strokes",
        "input order mm / bytes",
        "nearest mm / bytes",
        "nearest+2opt mm / bytes"
    );
    for name in [
        "miura-bent",
        "waterbomb-curved",
        "yoshimura-shell",
        "plane-crumpled",
        "resch",
        "resch-dome",
    ] {
        let mesh = crease::io::read(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("patterns/{name}.fold")),
        )
        .unwrap();
        let out = fabricate(&mesh, &machine, &options).unwrap();
        let strokes = score(&out.sheet, &machine.score_settings());
        let tools = machine.hpgl_settings().tools;
        let figures = |s: Vec<crease::fab::Stroke>| {
            let t = Toolpath {
                media: out.sheet.media.clone(),
                strokes: s,
            };
            (
                t.travel(),
                hpgl::to_string(&t, &machine.hpgl_settings()).unwrap().len(),
            )
        };
        let (a, b, c) = (
            figures(strokes.clone()),
            figures(nearest_neighbour_only(&strokes, &tools)),
            figures(route(&strokes, &tools)),
        );
        println!(
            "{name:<22} {:>7} | {:>12.0} / {:>7} | {:>12.0} / {:>7} | {:>12.0} / {:>7}",
            strokes.len(),
            a.0,
            a.1,
            b.0,
            b.1,
            c.0,
            c.1
        );
    }
    // The largest Miura-ori one job may cut: about a stroke per triangle, and a job is
    // held to 50,000 strokes (`crate::limits`).
    let mut p = Params::defaults(PatternKind::Miura);
    p.nx = 150;
    p.ny = 150;
    p.size = 5.0;
    let mesh = generate(&p).unwrap();
    let big = FabOptions {
        media: Some(crease::fab::Media::parse("1200x1200mm").unwrap()),
        ..Default::default()
    };
    let t = Instant::now();
    let out = fabricate(&mesh, &machine, &big).unwrap();
    let elapsed = t.elapsed();
    let bytes: usize = out.files.iter().map(|f| f.1.len()).sum();
    println!(
        "whole fab on a folded Miura-ori, {} triangles, {} vertices: {:.2?} ({} strokes, {} bytes of files)",
        mesh.faces().len(),
        mesh.vertex_count(),
        elapsed,
        out.toolpath.strokes.len(),
        bytes
    );
}
