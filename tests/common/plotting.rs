//! Helpers for the plotting tests: scratch folders and real cutter jobs.

use std::path::{Path, PathBuf};

/// A scratch folder of this process for `name`.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("crease-plot-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A real job: a bundled design's cutter job (sheet.hpgl or sheet.gpgl, as `machine`
/// speaks) from the fabrication pipeline, on A3.
pub fn cutter_job(design: &str, machine: &str) -> String {
    let machine = crease::machine::Machine::load(machine).unwrap();
    let mesh = crease::io::read(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("patterns")
            .join(design),
    )
    .unwrap();
    let options = crease::pipeline::FabOptions {
        media: Some(crease::fab::Media::parse("a3").unwrap()),
        // The job is what the plotting tests send; sheet.pdf's guide is not read here.
        guide: crease::pipeline::Guide::Never,
        ..Default::default()
    };
    let out = crease::pipeline::fabricate(&mesh, &machine, &options).unwrap();
    let job = out
        .files
        .iter()
        .find(|f| f.0 == "sheet.hpgl" || f.0 == "sheet.gpgl")
        .expect("a cutter job");
    String::from_utf8(job.1.clone()).unwrap()
}
