//! `crease verify` and `crease info`: what a design is and whether it holds.

use super::out;
use crease::{constraints::ConstraintSet, fab, io};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct VerifyArgs {
    /// Pattern file (.fold, .cp, .svg, .obj).
    file: PathBuf,
    /// Print the report as JSON.
    #[arg(long)]
    json: bool,
    /// Tolerance for every condition (radians for angles, relative for lengths), used
    /// exactly as given. Default: 1e-6 plus, per vertex or edge, what the file's
    /// coordinate rounding can explain there.
    #[arg(long)]
    tol: Option<f64>,
    /// Comma-separated conditions: developability, boundary-angle, boundary-length,
    /// convexity, flat-foldability, angular-inequality, fold-angle-range, twist-range,
    /// edge-length, coincidence, layer-order (the flat-folded state's, failing for a
    /// freeform design too), smoothness (curved creases drawn as chords turn smoothly:
    /// second differences at most 0.5°). Default: what the design's assignment calls
    /// for, smoothness where a crease chain curves.
    #[arg(long)]
    conditions: Option<String>,
    /// Also fold the crease pattern from flat to the design's own angles in
    /// simulation mode and report the first step where faces pass through each other
    /// (exit 1), or that the path is clear.
    #[arg(long)]
    path: bool,
}

#[derive(clap::Args)]
pub struct InfoArgs {
    /// Pattern file (.fold, .cp, .svg, .obj).
    file: PathBuf,
    /// Also list every vertex: id, 3D and crease-pattern position, creases, boundary
    /// or interior (the ids `--drag` and `--fix` take).
    #[arg(long)]
    vertices: bool,
}

/// `crease info`: counts, size, crease types and shape; with --vertices every vertex.
pub fn info(args: InfoArgs) -> Result<u8, String> {
    let imported = io::read_with_notes(&args.file).map_err(|e| e.to_string())?;
    for note in &imported.notes {
        eprintln!("note: {note}");
    }
    out(&format!(
        "file:         {}\n{}",
        args.file.display(),
        imported.mesh.info()
    ));
    if args.vertices {
        out(&format!("\n{}", imported.mesh.vertex_table()));
    }
    Ok(0)
}

/// `crease verify`: the report (text or JSON) and, with --path, the fold from flat; exit 1
/// when a condition fails, the layer order is undecided or the path collides.
pub fn verify(args: VerifyArgs) -> Result<u8, String> {
    let set = args
        .conditions
        .as_deref()
        .map(ConstraintSet::parse)
        .transpose()?;
    let mut tolerances = fab::Tolerances::default();
    if let Some(t) = args.tol {
        if !(t.is_finite() && t > 0.0) {
            return Err(format!("--tol must be a positive number (got {t})"));
        }
        tolerances = fab::Tolerances::exactly(t);
    }
    let mesh = io::read(&args.file).map_err(|e| e.to_string())?;
    let report = fab::verify(&mesh, set.as_ref(), tolerances);
    let path = args
        .path
        .then(|| crease::pipeline::folding_path(&mesh, &mut super::progress_bar()))
        .transpose()
        .map_err(|e| format!("{}: the path from flat: {e}", args.file.display()))?;
    let collides = path.as_ref().is_some_and(|p| p.collision.is_some());
    if args.json {
        let mut value = report.to_json();
        if let Some(p) = &path {
            value["path"] = serde_json::to_value(p).expect("a path report is JSON");
        }
        out(&format!("{value}\n"));
    } else {
        out(&report.to_string());
        if let Some(p) = &path {
            out(&format!("{p}\n"));
        }
    }
    let decided = report.undecided().is_none();
    Ok(if report.pass() && decided && !collides {
        0
    } else {
        1
    })
}
