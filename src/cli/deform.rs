//! `crease deform`: the paper's design method from the command line.

use super::{design_failure, parse_drag, progress_bar, DragArg, Remedy};
use crease::constraints::ConstraintSet;
use crease::io;
use crease::pipeline::Script;
use crease::pipeline::{run_design, DesignJob, DesignOutcome};
use crease::solver::{Mode, Stage};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct DeformArgs {
    /// Pattern file (may be omitted when the script names its base).
    file: Option<PathBuf>,
    /// Drag a vertex to a point, V=X,Y,Z (mm), or by an offset, V=+DX,+DY,+DZ (a `+`
    /// on any component makes the move relative). Repeat for several vertices.
    #[arg(long, value_parser = parse_drag)]
    drag: Vec<DragArg>,
    /// Vertices held still, separated by spaces or commas (default: the face farthest
    /// from the dragged vertices, or nearest the middle when folding).
    #[arg(long, num_args = 1.., value_delimiter = ',')]
    fix: Vec<usize>,
    /// A TOML script of drags (see patterns/*.toml).
    #[arg(long)]
    script: Option<PathBuf>,
    /// Euler steps for the --drag moves [default: 20].
    #[arg(long)]
    steps: Option<usize>,
    /// design (chosen conditions, lengths free) or simulation (lengths kept); default
    /// design, or the script's.
    #[arg(long)]
    mode: Option<String>,
    /// Comma-separated conditions held in design mode: developability, boundary-angle,
    /// boundary-length, convexity, flat-foldability, angular-inequality, fold-angle-range,
    /// twist-range, edge-length, coincidence, layer-order (a step that would lose the
    /// flat-folded state's layer order is halved, then refused), smoothness (curved creases'
    /// turning varies smoothly; on by default where a crease chain curves). Default: the
    /// script's, or what the design's assignment calls for (as verify).
    #[arg(long)]
    conditions: Option<String>,
    /// Twist allowance α in [0, 1) of flat creases (paper §2.4); default: the script's,
    /// or each crease's own from the file (0 for generated patterns).
    #[arg(long)]
    alpha: Option<f64>,
    /// Drag falloff radius in mm (default: a quarter of the design's diagonal).
    #[arg(long)]
    radius: Option<f64>,
    /// Fold toward this fraction of every crease's target angle before the drags (0 flat,
    /// 1 fully folded; as `fold --amount`). Default: the script's; a flat pattern is
    /// folded to 5%, since no drag leaves the flat state.
    #[arg(long)]
    fold: Option<f64>,
    /// Collapse degenerating edges (paper §4): edges shorter than this fraction of the
    /// mean edge, in (0, 1). Default: off (the script's); 0.25 when given without a value.
    #[arg(long, num_args = 0..=1, default_missing_value = "0.25")]
    remesh: Option<f64>,
    /// Hold the crease pattern's outline too: its angles and the lengths of its straight
    /// runs (boundary-angle and boundary-length added to the conditions). Design mode
    /// otherwise frees them and the drag redraws the outline.
    #[arg(long)]
    keep_outline: bool,
    /// When a step cannot be corrected, write the last state that held every condition
    /// (exit 1, naming the step and the condition that stopped it) instead of nothing.
    #[arg(long)]
    keep_partial: bool,
    /// Output FOLD file.
    #[arg(short, long)]
    output: PathBuf,
}

/// Euler steps of the --drag moves unless `--steps` says.
const DEFAULT_STEPS: usize = 20;

pub fn deform(args: DeformArgs) -> Result<u8, String> {
    let DeformArgs {
        file,
        drag,
        fix,
        script,
        steps,
        mode,
        conditions,
        alpha,
        radius,
        fold,
        remesh,
        keep_outline,
        keep_partial,
        output,
    } = args;
    let mut job = base_job(file.as_deref(), script.as_deref())?;
    if !drag.is_empty() {
        let moves = drag
            .iter()
            .map(|d| d.resolve(&job.mesh))
            .collect::<Result<_, _>>()?;
        job.stages.push(Stage {
            steps: steps.unwrap_or(DEFAULT_STEPS),
            moves,
        });
    }
    if job.stages.is_empty() && job.fold.is_none() && job.fit.is_none() {
        return Err(
            "nothing to do: give --drag V=X,Y,Z or a --script with stages, a fold or a fit".into(),
        );
    }
    if !fix.is_empty() {
        job.fixed = Some(fix);
    }
    if let Some(mode) = mode.as_deref() {
        job.mode = Mode::parse(mode)?;
    }
    if let Some(c) = conditions {
        job.conditions = Some(ConstraintSet::parse(&c)?);
    }
    job.alpha = alpha.or(job.alpha);
    job.radius = radius.or(job.radius);
    job.remesh = remesh.or(job.remesh);
    job.fold = fold.or(job.fold);
    let job_remesh = job.remesh.is_some();
    let asked_fold = job.fold.is_some();
    job.keep_partial = keep_partial;
    job.keep_outline = keep_outline;
    let source = script.as_deref().or(file.as_deref()).unwrap_or(&output);
    let remedies = remedies(&job, steps);
    let outcome = match run_design(job, &mut progress_bar()) {
        Ok(o) => o,
        Err(e) => return design_failure(e, source, &remedies),
    };
    io::write(&outcome.mesh, &output).map_err(|e| e.to_string())?;
    print_summary(&outcome, &output, asked_fold, job_remesh);
    let hint = " (--keep-outline holds the outline's angles and lengths)";
    super::say_if_the_sheet_changed(outcome.resized, if keep_outline { "" } else { hint });
    if let Some((stage, drag)) = outcome.stalled() {
        eprintln!(
            "error: stage {} did not finish ({}); {} holds the last state that held every condition",
            stage + 1,
            drag.refused.as_deref().unwrap_or("a step could not be corrected"),
            output.display()
        );
        return Ok(1);
    }
    Ok(0)
}

/// The job of the pattern `file`, or of the `script` (on `file` when both are given).
fn base_job(file: Option<&Path>, script: Option<&Path>) -> Result<DesignJob, String> {
    let mesh = file.map(io::read).transpose().map_err(|e| e.to_string())?;
    match script {
        Some(path) => {
            let text = crease::io::read_file_text(path).map_err(|e| e.to_string())?;
            let parsed = Script::parse(&text).map_err(|e| format!("{}: {e}", path.display()))?;
            let dir = path.parent().unwrap_or(Path::new("."));
            DesignJob::from_script(&parsed, dir, mesh)
                .map_err(|e| format!("{}: {e}", path.display()))
        }
        None => Ok(DesignJob::new(
            mesh.ok_or("give a pattern file or a --script")?,
        )),
    }
}

/// What to try when a drag's step cannot be corrected; what the run already set (by an
/// option or its script) is not suggested again.
fn remedies(job: &DesignJob, steps: Option<usize>) -> [Remedy; 4] {
    [
        Remedy::new(
            match steps {
                Some(n) => format!("a smaller move or more steps than --steps {n}"),
                None => "a smaller move or more --steps".into(),
            },
            false,
        ),
        Remedy::new("a twist allowance (--alpha 0.1)", job.alpha.is_some()),
        Remedy::new("holding other vertices (--fix)", job.fixed.is_some()),
        Remedy::new(
            "--keep-partial, which writes the last state that held every condition",
            false,
        ),
    ]
}

/// What the run did, on stderr: solver counters, a flat start, remeshing, and how close
/// each dragged vertex came to its target.
fn print_summary(outcome: &DesignOutcome, output: &Path, asked_fold: bool, job_remesh: bool) {
    let s = &outcome.stats;
    eprintln!(
        "{} steps, {} Newton iterations, {} halvings, largest residual {:.1e}; wrote {}",
        s.steps,
        s.newton_iterations,
        s.halvings,
        s.worst_residual,
        output.display()
    );
    if let (Some(f), false) = (&outcome.fold, asked_fold) {
        eprintln!(
            "note: the pattern was flat, a singular point no drag leaves; it was folded to {:.0}% of its target angles first (--fold sets another amount)",
            100.0 * f.mean_fraction
        );
    }
    let (collapses, flips) = outcome
        .drags
        .iter()
        .fold((0, 0), |(c, f), d| (c + d.collapses, f + d.flips));
    if collapses + flips > 0 || job_remesh {
        eprintln!("remeshing: {collapses} edge collapse(s), {flips} flip(s)");
    }
    if let Some(fit) = &outcome.fit {
        eprintln!("{}", fit.summary());
    }
    // A stalled stage is the error `deform` ends with.
    for (i, d) in outcome.drags.iter().enumerate().filter(|(_, d)| !d.stalled) {
        if let Some(why) = &d.refused {
            eprintln!("stage {} stopped at {why}", i + 1);
        }
    }
    for d in outcome.drags.iter().flat_map(|d| &d.distances) {
        eprintln!(
            "vertex {}: {:.2} mm from its target (was {:.2} mm)",
            d.0, d.2, d.1
        );
    }
}
