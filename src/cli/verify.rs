//! `crease verify` and `crease info`: what a design is and whether it holds.

use super::out;
use crease::{constraints::ConstraintSet, fab, io};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct VerifyArgs {
    /// Pattern file (.fold, .cp, .opx, .svg, .obj).
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
    /// The layer search's time and memory.
    #[command(flatten)]
    search: super::SearchArgs,
    /// Also count the flat-folded states (layer orders): each independent group of
    /// overlapping faces enumerated up to CAP states (default 10000, as Flat-Folder), and
    /// their product.
    #[arg(long, value_name = "CAP", num_args = 0..=1, default_missing_value = "10000")]
    count: Option<u64>,
}

#[derive(clap::Args)]
pub struct InfoArgs {
    /// Pattern file (.fold, .cp, .opx, .svg, .obj).
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

/// `crease verify`: the report (text or JSON) and, with --path, the fold from flat; exit
/// 0 pass, 1 a condition fails or the path collides, 3 undecided (the verdict's code).
pub fn verify(args: VerifyArgs) -> Result<u8, String> {
    let set = args
        .conditions
        .as_deref()
        .map(ConstraintSet::parse)
        .transpose()?;
    let mut tolerances = fab::Tolerances::default();
    if let Some(t) = args.tol {
        crease::limits::VERIFY_TOL
            .check("--tol", t)
            .map_err(|e| e.to_string())?;
        tolerances = fab::Tolerances::exactly(t);
    }
    let (time, memory) = args.search.checked()?;
    let imported = io::read_with_notes(&args.file).map_err(|e| e.to_string())?;
    for note in &imported.notes {
        eprintln!("note: {note}");
    }
    let mesh = imported.mesh;
    let budget = fab::Budget::search(time, memory);
    let report = fab::verify_within(&mesh, set.as_ref(), tolerances, &budget);
    // The file was read: a path the solver cannot follow is undecided, not bad input.
    let path = args.path.then(|| {
        crease::pipeline::folding_path(&mesh, &mut super::progress_bar())
            .map_err(|e| format!("the solver stopped: {e}"))
    });
    let cap = args
        .count
        .map(|c| crease::limits::STATE_CAP.check_count("--count", c))
        .transpose()
        .map_err(|e| e.to_string())?;
    let states = cap.map(|cap| fab::count_flat_states(&mesh, &budget, cap));
    // One verdict: the report's, weighed with the path when there is one.
    let verdict = match &path {
        Some(p) => crease::pipeline::verdict_with_path(&report, p),
        None => report.verdict(),
    };
    if args.json {
        let mut value = report.to_json_with(&verdict);
        value["import_notes"] = serde_json::json!(imported.notes);
        if let Some(states) = &states {
            value["states"] = states_json(states);
        }
        match &path {
            Some(Ok(p)) => value["path"] = serde_json::to_value(p).expect("a path report is JSON"),
            Some(Err(why)) => {
                value["path"] = serde_json::json!({"verdict": "UNDECIDED", "why": why});
            }
            None => {}
        }
        out(&format!("{value}\n"));
    } else {
        let mut more = Vec::new();
        if let Some(states) = &states {
            more.push(states_line(states));
        }
        match &path {
            Some(Ok(p)) => more.push(p.to_string()),
            Some(Err(why)) => more.push(format!("path from flat: UNDECIDED — {why}")),
            None => {}
        }
        out(&report.text_with(&more, &verdict));
    }
    // 0 pass, 1 fail, 3 undecided.
    Ok(verdict.exit_code())
}

type Counted = Result<Option<Vec<fab::GroupCount>>, fab::LayerError>;

/// "flat-folded states: 48 (3 independent groups: 1 × 3 × 16)".
fn states_line(states: &Counted) -> String {
    match states {
        Ok(Some(groups)) => {
            let total = fab::StateTotal::product(groups);
            let capped = groups.iter().any(|g| g.capped);
            let shown: Vec<String> = groups
                .iter()
                .take(12)
                .map(|g| g.count.to_string())
                .collect();
            let more = if groups.len() > 12 { " × …" } else { "" };
            format!(
                "flat-folded states: {}{total} ({} independent group(s): {}{more}){}",
                if capped { "at least " } else { "" },
                groups.len(),
                shown.join(" × "),
                if capped {
                    "; a group reached the cap: raise --count to count further"
                } else {
                    ""
                }
            )
        }
        Ok(None) => "flat-folded states: 0 (no layer order)".into(),
        Err(e) => format!("flat-folded states: not counted: {e}"),
    }
}

/// `{"total": "48", "groups": [1, 3, 16], "capped": false}`, or the reason it was not
/// counted.
fn states_json(states: &Counted) -> serde_json::Value {
    match states {
        Ok(Some(groups)) => serde_json::json!({
            "total": fab::StateTotal::product(groups).to_string(),
            "groups": groups.iter().map(|g| g.count).collect::<Vec<_>>(),
            "capped": groups.iter().any(|g| g.capped),
        }),
        Ok(None) => serde_json::json!({"total": "0", "groups": [], "capped": false}),
        Err(e) => serde_json::json!({"not_counted": e.to_string()}),
    }
}
