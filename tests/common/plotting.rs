//! Helpers for the plotting tests: scratch folders and real cutter jobs.

use std::path::Path;

/// A scratch folder of its own for the plotting test `name`.
pub fn scratch(name: &str) -> super::Scratch {
    super::Scratch::new(&format!("plot-{name}"))
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
