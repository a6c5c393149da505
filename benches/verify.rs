//! `cargo bench --bench verify`: how long verification takes on real patterns.
//! A plain timing harness (median of repeated runs) keeps the dependency list short.

use crease::fab::{verify, Tolerances};
use std::path::Path;
use std::time::{Duration, Instant};

fn median(mut f: impl FnMut(), runs: usize) -> Duration {
    let mut times: Vec<Duration> = (0..runs)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed()
        })
        .collect();
    times.sort();
    times[runs / 2]
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let cases = [
        root.join("tests/data/origamisimulator/BoxPleatPyramid.fold"),
        root.join("patterns/resch.fold"),
        root.join("patterns/miura.fold"),
    ];
    println!(
        "{:<24} {:>9} {:>12} {:>12}",
        "pattern", "vertices", "read", "verify"
    );
    for path in cases {
        if !path.exists() {
            eprintln!("skipping {} (not found)", path.display());
            continue;
        }
        let mesh = crease::io::read(&path).expect("bench input reads");
        let read = median(|| drop(crease::io::read(&path).unwrap()), 11);
        let check = median(
            || assert!(verify(&mesh, None, Tolerances::default()).pass()),
            11,
        );
        println!(
            "{:<24} {:>9} {:>10.2?} {:>10.2?}",
            path.file_name().unwrap().to_string_lossy(),
            mesh.vertex_count(),
            read,
            check
        );
    }
    // Self-intersection on a large folded design: a Miura-ori of 224 × 224 cells
    // (100,352 triangles) at 30% of its fold.
    let mut p = crease::generate::Params::square(crease::generate::PatternKind::Miura, 224, 5.0);
    p.fold = Some(0.3);
    let mesh = crease::generate::generate(&p).expect("a large Miura-ori generates");
    let time = median(
        || assert!(crease::fab::self_intersections(&mesh).is_empty()),
        5,
    );
    println!(
        "self-intersection: {} triangles, none crossing, in {:.1?}",
        mesh.faces().len(),
        time
    );
    // Layer order of the flat-folded BoxPleatPyramid (every crease ±180°).
    let pyramid = root.join("tests/data/origamisimulator/BoxPleatPyramid.fold");
    let mesh = crease::io::read(&pyramid).expect("bench input reads");
    let mut pairs = 0;
    let time = median(
        || match crease::fab::layer_order(&mesh) {
            Ok(crease::fab::LayerOrder::Found(o)) => pairs = o.len(),
            other => panic!("BoxPleatPyramid has an order: {other:?}"),
        },
        5,
    );
    println!("layer order: BoxPleatPyramid, {pairs} overlapping pairs ordered in {time:.1?}");
    // Layer order of a flat 16 × 16 waterbomb: 1,056 faces stacked deep, the largest
    // problem the issue sets (under 20 s and 2 GB). Run once: it is the slow one.
    let p = crease::generate::Params::square(crease::generate::PatternKind::Waterbomb, 16, 20.0);
    let mesh = crease::generate::generate(&p).expect("a 16 × 16 waterbomb generates");
    let t = Instant::now();
    let pairs = match crease::fab::layer_order(&mesh) {
        Ok(crease::fab::LayerOrder::Found(o)) => o.len(),
        other => panic!("the flat waterbomb has an order: {other:?}"),
    };
    println!(
        "layer order: waterbomb 16 × 16 flat, {pairs} overlapping pairs ordered in {:.1?}",
        t.elapsed()
    );
}
