//! `cargo bench --bench verify`: how long verification takes on real patterns.
//! A plain timing harness (median of repeated runs) keeps the dependency list short.

use crease::fab::{verify, Tolerances};
use std::path::Path;
use std::time::{Duration, Instant};

// As in the binary (src/main.rs), so the figures are those of `crease verify`.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

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
    crease::allocator::set_up();
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
    flat_folder_sets(root);
}

/// Flat-Folder's examples (tests/data/flat-folder): the verdict over the grid set and the
/// sample, each file read and verified once on one core, beside Flat-Folder's own setup
/// and solve seconds from its CSVs (in a browser, on the machine that made them).
fn flat_folder_sets(root: &Path) {
    let data = root.join("tests/data/flat-folder");
    for (folder, table) in [
        ("grids", Some("grids_data.csv")),
        (
            "instagram-sample",
            Some("instagram-sample/instagram_data_sample.csv"),
        ),
        // No times published for these: Flat-Folder's page says only that none folds.
        ("unsatisfiable", None),
    ] {
        let mut files: Vec<_> = std::fs::read_dir(data.join(folder))
            .expect("the flat-folder data is in the repository")
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "fold"))
            .collect();
        files.sort();
        let (mut total, mut slowest, mut verdicts) =
            (Duration::ZERO, (Duration::ZERO, String::new()), [0usize; 4]);
        for path in &files {
            let t = Instant::now();
            let Ok(mesh) = crease::io::read(path) else {
                verdicts[3] += 1;
                continue;
            };
            let verdict = verify(&mesh, None, Tolerances::default()).verdict();
            let took = t.elapsed();
            verdicts[usize::from(verdict.exit_code()).min(2)] += 1;
            total += took;
            if took > slowest.0 {
                slowest = (
                    took,
                    path.file_name().unwrap().to_string_lossy().into_owned(),
                );
            }
        }
        let theirs = table.map_or("not published".to_string(), |t| {
            format!("{:.1} s", flat_folder_seconds(&data.join(t)))
        });
        println!(
            "{folder}: {} files in {total:.2?} ({} pass, {} fail, {} undecided, {} not read); slowest {} in {:.2?}; Flat-Folder's setup + solve {theirs}",
            files.len(),
            verdicts[0],
            verdicts[1],
            verdicts[2],
            verdicts[3],
            slowest.1,
            slowest.0,
        );
    }
}

/// The sum of a Flat-Folder CSV's `setup_sec` and `solve_sec`.
fn flat_folder_seconds(table: &Path) -> f64 {
    let text = std::fs::read_to_string(table).expect("the CSV is in the repository");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (setup, solve) = (at("setup_sec"), at("solve_sec"));
    lines
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            cells[setup].parse::<f64>().unwrap_or(0.0) + cells[solve].parse::<f64>().unwrap_or(0.0)
        })
        .sum()
}
