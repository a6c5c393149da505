//! `crease fit`: a design pulled onto a target surface, and `crease surface`: the target
//! shapes a maker asks for by name.

use super::{design_failure, progress_bar, Remedy};
use crease::constraints::ConstraintSet;
use crease::fit::{FitOptions, SurfaceChoice};
use crease::io;
use crease::pipeline::{run_design, DesignJob, FitStage};
use crease::surface::shapes::Shape;
use std::path::PathBuf;
use std::sync::Arc;

#[derive(clap::Args)]
pub struct FitArgs {
    /// Pattern file (.fold, .cp, .opx, .svg, .obj): a generated pattern or a design.
    pattern: PathBuf,
    /// The target surface: a triangle mesh in mm (.obj, or .stl ASCII or binary). It is
    /// never moved: the design is placed on it.
    #[arg(long = "to")]
    to: PathBuf,
    /// Output FOLD file; the report goes beside it as OUT.fit.json.
    #[arg(short, long)]
    output: PathBuf,
    /// Which points represent the design's surface: mid (each facet's mean, so a
    /// corrugated pattern's mid-surface follows the target and keeps its depth; a plain
    /// sheet is measured vertex by vertex) or all (every vertex).
    #[arg(long, default_value = "mid")]
    surface: String,
    /// Steps at most.
    #[arg(long, default_value_t = crease::fit::DEFAULT_STEPS)]
    steps: usize,
    /// Distance goal in mm for the largest distance of a surface point to the target
    /// (exit 1 when not met). Default: 1% of the fitted design's bounding-box diagonal.
    #[arg(long)]
    within: Option<f64>,
    /// Keep the pattern where it is (no rigid placement, the face nearest the middle
    /// held), instead of placing it on the target first.
    #[arg(long)]
    no_align: bool,
    /// Comma-separated conditions held while fitting (as `deform --conditions`).
    /// Default: what the design's assignment calls for.
    #[arg(long)]
    conditions: Option<String>,
    /// Twist allowance α in [0, 1) of flat creases (paper §2.4).
    #[arg(long)]
    alpha: Option<f64>,
    /// Vertices held still while fitting (comma-separated).
    #[arg(long, num_args = 1.., value_delimiter = ',')]
    fix: Vec<usize>,
    /// Collapse degenerating edges (paper §4) shorter than this fraction of the mean
    /// edge; 0.25 when given without a value.
    #[arg(long, num_args = 0..=1, default_missing_value = "0.25")]
    remesh: Option<f64>,
    /// Print the report as JSON on stdout.
    #[arg(long)]
    json: bool,
    /// Write the fitted design even when faces pass through each other in it.
    #[arg(long)]
    force: bool,
}

pub fn fit(args: FitArgs) -> Result<u8, String> {
    let surface = SurfaceChoice::parse(&args.surface).map_err(|e| format!("--surface: {e}"))?;
    let conditions = args
        .conditions
        .as_deref()
        .map(ConstraintSet::parse)
        .transpose()?;
    io::Format::from_path(&args.output).map_err(|e| e.to_string())?;
    let mesh = io::read(&args.pattern).map_err(|e| e.to_string())?;
    let target = io::read_target(&args.to).map_err(|e| e.to_string())?;
    let mut job = DesignJob::new(mesh);
    job.conditions = conditions;
    let (alpha_given, fix_given) = (args.alpha.is_some(), !args.fix.is_empty());
    job.alpha = args.alpha;
    job.remesh = args.remesh;
    if !args.fix.is_empty() {
        job.fixed = Some(args.fix);
    }
    job.fit = Some(FitStage {
        target: Arc::new(target),
        target_name: args.to.display().to_string(),
        align: !args.no_align,
        options: FitOptions {
            surface,
            max_steps: args.steps,
            goal: args.within,
            remesh: args.remesh,
        },
    });
    let outcome = match run_design(job, &mut progress_bar()) {
        Ok(o) => o,
        Err(e) => {
            let remedies = [
                Remedy::new("a twist allowance (--alpha 0.1)", alpha_given),
                Remedy::new("holding other vertices (--fix)", fix_given),
            ];
            return design_failure(e, &args.pattern, &remedies);
        }
    };
    let mut report = outcome.fit.expect("a fit job reports its fit");
    report.target = args.to.display().to_string();
    if let Some(why) = report.refusal().filter(|_| !args.force) {
        eprintln!("{}", report.summary());
        eprintln!("error: {why}; nothing was written (--force writes it anyway)");
        return Ok(1);
    }
    let json = serde_json::to_string_pretty(&report).expect("a report serialises");
    let report_file = crease::pipeline::names::fit_report_path(&args.output);
    io::write(&outcome.mesh, &args.output).map_err(|e| e.to_string())?;
    io::write_atomic(&report_file, json.as_bytes()).map_err(|e| e.to_string())?;
    if args.json {
        super::out(&format!("{json}\n"));
    }
    eprintln!("{}", report.summary());
    super::say_if_the_sheet_changed(outcome.resized, "");
    eprintln!(
        "wrote {} and {}",
        args.output.display(),
        report_file.display()
    );
    Ok(if report.distance.met { 0 } else { 1 })
}

#[derive(clap::Args)]
pub struct SurfaceArgs {
    /// Shape: cap (a sphere's, apex up), saddle (a hyperbolic paraboloid) or cylinder
    /// (a vault along y).
    shape: String,
    /// Width of the square patch seen from above (mm).
    #[arg(long, default_value_t = 300.0)]
    span: f64,
    /// Radius of the sphere or cylinder (mm).
    #[arg(long, default_value_t = 400.0)]
    radius: f64,
    /// Saddle: rise at the middles of two opposite sides, fall at the other two (mm).
    #[arg(long, default_value_t = 40.0)]
    depth: f64,
    /// Squares along a side (two triangles each).
    #[arg(long, default_value_t = 64)]
    resolution: usize,
    /// Output file (.obj or .stl).
    #[arg(short, long)]
    output: PathBuf,
}

pub fn surface(args: SurfaceArgs) -> Result<u8, String> {
    let shape = match args.shape.as_str() {
        "cap" => Shape::Cap {
            radius: args.radius,
        },
        "saddle" => Shape::Saddle { depth: args.depth },
        "cylinder" => Shape::Cylinder {
            radius: args.radius,
        },
        other => {
            return Err(format!(
                "unknown shape \"{other}\" (choose from: {})",
                Shape::NAMES.join(", ")
            ))
        }
    };
    let surface = shape
        .surface(args.span, args.resolution)
        .map_err(|e| e.to_string())?;
    let size = match shape {
        Shape::Saddle { depth } => format!("--depth {depth}"),
        Shape::Cap { radius } | Shape::Cylinder { radius } => format!("--radius {radius}"),
    };
    let comment = format!(
        "crease surface {} --span {} {size} --resolution {} (mm)",
        args.shape, args.span, args.resolution
    );
    io::write_target(&surface, &args.output, &comment).map_err(|e| e.to_string())?;
    eprintln!(
        "wrote {} ({} triangles)",
        args.output.display(),
        surface.triangles().len()
    );
    Ok(0)
}
