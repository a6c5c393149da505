//! The `crease` command line: parse, call the library, print, exit.
//! Exit status: 0 success, 1 the design fails a check, 2 bad input or arguments.

mod cli;

// The solver builds and drops Jacobians of tens of megabytes every Newton iteration;
// glibc hands such blocks back to the kernel each time, and the page faults of taking them
// again cost a sixth of a step. mimalloc keeps them.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use clap::{Parser, Subcommand};
use cli::{design_failure, out, parse_drag, progress_bar, DragArg, GenerateArgs};
use crease::pipeline::{run_design, DesignJob};
use crease::solver::{Mode, Script, Stage};
use crease::{constraints::ConstraintSet, fab, generate, io};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "crease",
    version,
    about = "Design freeform origami and fabricate it on cutting plotters"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Generate one of the paper's starting patterns.
    Generate(GenerateArgs),
    /// Print counts, size and crease types of a pattern file.
    Info {
        /// Pattern file (.fold, .cp, .svg, .obj).
        file: PathBuf,
        /// Also list every vertex: id, 3D and crease-pattern position, creases, boundary
        /// or interior (the ids `--drag` and `--fix` take).
        #[arg(long)]
        vertices: bool,
    },
    /// Check a design against the origami conditions (exit 1 if one fails).
    Verify {
        /// Pattern file (.fold, .cp, .svg, .obj).
        file: PathBuf,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
        /// Tolerance for every condition (radians for angles, relative for lengths);
        /// default 1e-6.
        #[arg(long)]
        tol: Option<f64>,
        /// Comma-separated conditions: developability, boundary-angle, boundary-length,
        /// convexity, flat-foldability, angular-inequality, fold-angle-range, twist-range,
        /// edge-length, coincidence. Default: what the design's assignment calls for.
        #[arg(long)]
        conditions: Option<String>,
    },
    /// Fold a pattern in simulation mode (rigid panels), driving every crease toward a
    /// fraction of its target angle.
    Fold {
        /// Pattern file.
        file: PathBuf,
        /// Fraction of each crease's target angle, in [0, 1].
        #[arg(long)]
        amount: f64,
        /// Vertices held still, separated by spaces or commas (default: the face farthest
        /// from the dragged vertices, or nearest the middle when folding).
        #[arg(long, num_args = 1.., value_delimiter = ',')]
        fix: Vec<usize>,
        /// Output FOLD file.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Vary a pattern by dragging vertices while the chosen conditions keep holding.
    Deform {
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
        /// Euler steps for the --drag moves.
        #[arg(long, default_value_t = 20)]
        steps: usize,
        /// design (chosen conditions, lengths free) or simulation (lengths kept).
        #[arg(long)]
        mode: Option<String>,
        /// Comma-separated conditions (design mode), as for verify.
        #[arg(long)]
        conditions: Option<String>,
        /// Twist allowance α of flat creases (paper §2.4).
        #[arg(long)]
        alpha: Option<f64>,
        /// Drag falloff radius in mm (default: a quarter of the design's diagonal).
        #[arg(long)]
        radius: Option<f64>,
        /// Collapse degenerating edges (paper §4): edges shorter than this fraction of the
        /// mean edge (0.25 when given without a value).
        #[arg(long, num_args = 0..=1, default_missing_value = "0.25")]
        remesh: Option<f64>,
        /// Output FOLD file.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Fabricate a design: verify, unfold, lay out on the media, score folds with the
    /// machine's dash codes, and write sheet.svg, sheet.pdf, sheet.hpgl,
    /// crease-pattern.svg and report.json.
    Fab {
        /// Design file (.fold, .cp, .svg, .obj).
        design: PathBuf,
        /// Machine profile: a name from machines/ or a path to a .toml file.
        #[arg(long, default_value = "generic-hpgl")]
        machine: String,
        /// Media: a4, a3, letter, 12x12in, WxHmm (default: the machine's).
        #[arg(long)]
        media: Option<String>,
        /// Scale the pattern to this width in mm (default: design units are mm).
        #[arg(long)]
        width: Option<f64>,
        /// Output folder (default: out/DESIGN-NAME).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Cut even if the design fails verification.
        #[arg(long)]
        force: bool,
        /// Score mountains from the back: a second, mirrored job (sheet-back.hpgl).
        #[arg(long)]
        mountains_from_back: bool,
        /// Split a sheet too large for the media over several PDF pages, with overlap and
        /// registration marks, instead of refusing (no cutter job is written then).
        #[arg(long)]
        tile: bool,
    },
    /// List the machine profiles `--machine` can name.
    Machines,
    /// Send an HP-GL job to a plotter over a serial port, with flow control, progress
    /// confirmed by the plotter, and a journal for --resume.
    Plot(cli::plot::PlotArgs),
    /// Run an emulated HP-GL plotter on a pseudo-terminal until Ctrl-C.
    Emulate(cli::plot::EmulateArgs),
    /// Design by hand: a local web app where you drag the 3D form with the mouse and see
    /// the crease pattern and the flat-folded state beside it (paper §5). Serves on
    /// 127.0.0.1 only; Ctrl-C stops it.
    Studio(cli::studio::StudioArgs),
    /// Convert between pattern formats, chosen by extension (.fold, .cp, .svg, .obj).
    Convert {
        /// Input file.
        input: PathBuf,
        /// Output file.
        output: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    match run(cli) {
        Ok(code) => ExitCode::from(code),
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> Result<u8, String> {
    match cli.command {
        Command::Generate(args) => {
            let mesh = generate::generate(&args.params()?).map_err(|e| e.to_string())?;
            io::write(&mesh, &args.output).map_err(|e| e.to_string())?;
            eprintln!(
                "wrote {} ({} vertices, {} triangles)",
                args.output.display(),
                mesh.vertex_count(),
                mesh.faces().len()
            );
            Ok(0)
        }
        Command::Info { file, vertices } => {
            let imported = io::read_with_notes(&file).map_err(|e| e.to_string())?;
            for note in &imported.notes {
                eprintln!("note: {note}");
            }
            out(&format!(
                "file:         {}\n{}",
                file.display(),
                imported.mesh.info()
            ));
            if vertices {
                out(&format!("\n{}", imported.mesh.vertex_table()));
            }
            Ok(0)
        }
        Command::Verify {
            file,
            json,
            tol,
            conditions,
        } => {
            let set = conditions
                .as_deref()
                .map(ConstraintSet::parse)
                .transpose()?;
            let mut tolerances = fab::Tolerances::default();
            if let Some(t) = tol {
                if !(t.is_finite() && t > 0.0) {
                    return Err(format!("--tol must be a positive number (got {t})"));
                }
                tolerances = fab::Tolerances {
                    angle: t,
                    length: t,
                };
            }
            let mesh = io::read(&file).map_err(|e| e.to_string())?;
            let report = fab::verify(&mesh, set.as_ref(), tolerances);
            if json {
                out(&format!("{}\n", report.to_json()));
            } else {
                out(&report.to_string());
            }
            Ok(if report.pass() { 0 } else { 1 })
        }
        Command::Fold {
            file,
            amount,
            fix,
            output,
        } => {
            let mesh = io::read(&file).map_err(|e| e.to_string())?;
            let mut job = DesignJob::new(mesh);
            job.fold = Some(amount);
            job.fold_fixed = (!fix.is_empty()).then_some(fix);
            job.mode = Mode::Simulation;
            let outcome = match run_design(job, &mut progress_bar()) {
                Ok(o) => o,
                Err(e) => return design_failure(e),
            };
            io::write(&outcome.mesh, &output).map_err(|e| e.to_string())?;
            if let Some(f) = outcome.fold {
                eprintln!(
                    "folded in {} steps to {:.1}% of the target angles on average (largest miss {:.3} rad); wrote {}",
                    f.steps,
                    100.0 * f.mean_fraction,
                    f.error,
                    output.display()
                );
            }
            Ok(0)
        }
        Command::Deform {
            file,
            drag,
            fix,
            script,
            steps,
            mode,
            conditions,
            alpha,
            radius,
            remesh,
            output,
        } => {
            let mesh = file
                .as_deref()
                .map(io::read)
                .transpose()
                .map_err(|e| e.to_string())?;
            let mut job = match &script {
                Some(path) => {
                    let text = std::fs::read_to_string(path)
                        .map_err(|e| format!("{}: {e}", path.display()))?;
                    let parsed =
                        Script::parse(&text).map_err(|e| format!("{}: {e}", path.display()))?;
                    let dir = path.parent().unwrap_or(std::path::Path::new("."));
                    DesignJob::from_script(&parsed, dir, mesh)
                        .map_err(|e| format!("{}: {e}", path.display()))?
                }
                None => DesignJob::new(mesh.ok_or("give a pattern file or a --script")?),
            };
            if !drag.is_empty() {
                let moves = drag
                    .iter()
                    .map(|d| d.resolve(&job.mesh))
                    .collect::<Result<_, _>>()?;
                job.stages.push(Stage { steps, moves });
            }
            if job.stages.is_empty() && job.fold.is_none() {
                return Err(
                    "nothing to do: give --drag V=X,Y,Z or a --script with stages or a fold".into(),
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
            let job_remesh = job.remesh.is_some();
            let outcome = match run_design(job, &mut progress_bar()) {
                Ok(o) => o,
                Err(e) => return design_failure(e),
            };
            io::write(&outcome.mesh, &output).map_err(|e| e.to_string())?;
            let s = &outcome.stats;
            eprintln!(
                "{} steps, {} Newton iterations, {} halvings, largest residual {:.1e}; wrote {}",
                s.steps,
                s.newton_iterations,
                s.halvings,
                s.worst_residual,
                output.display()
            );
            let (collapses, flips) = outcome
                .drags
                .iter()
                .fold((0, 0), |(c, f), d| (c + d.collapses, f + d.flips));
            if collapses + flips > 0 || job_remesh {
                eprintln!("remeshing: {collapses} edge collapse(s), {flips} flip(s)");
            }
            for d in outcome.drags.iter().flat_map(|d| &d.distances) {
                eprintln!(
                    "vertex {}: {:.2} mm from its target (was {:.2} mm)",
                    d.0, d.2, d.1
                );
            }
            Ok(0)
        }
        Command::Fab {
            design,
            machine,
            media,
            width,
            out: out_dir,
            force,
            mountains_from_back,
            tile,
        } => {
            let machine = crease::plotter::Machine::load(&machine).map_err(|e| e.to_string())?;
            let media = media
                .as_deref()
                .map(crease::fab::Media::parse)
                .transpose()?;
            let mesh = io::read(&design).map_err(|e| e.to_string())?;
            let options = crease::pipeline::FabOptions {
                media,
                width,
                force,
                mountains_from_back,
                tile,
            };
            let result = match crease::pipeline::fabricate(&mesh, &machine, &options) {
                Ok(r) => r,
                Err(crease::pipeline::FabError::Input(m)) => return Err(m),
                Err(crease::pipeline::FabError::Rejected(r)) => {
                    eprintln!("error: {r}");
                    eprintln!("nothing was written");
                    return Ok(1);
                }
            };
            let dir = out_dir.unwrap_or_else(|| {
                PathBuf::from("out").join(design.file_stem().unwrap_or_default())
            });
            io::write_all_atomic(&dir, &result.files).map_err(|e| e.to_string())?;
            let s = &result.report["sheet"];
            if s["tiled"] == true {
                eprintln!(
                    "{}: the sheet is larger than {}; sheet.pdf is tiled over pages with {} mm overlap and registration marks (no cutter job written)",
                    dir.display(),
                    machine.media,
                    crease::pipeline::TILE_OVERLAP_MM
                );
                return Ok(0);
            }
            eprintln!(
                "{}: {} strokes, pen-up travel {:.0} mm, {} bytes of HP-GL, about {:.0} s to plot",
                dir.display(),
                s["strokes"],
                s["pen_up_travel_mm"].as_f64().unwrap_or(0.0),
                s["hpgl_bytes"],
                s["estimated_plot_time_s"].as_f64().unwrap_or(0.0)
            );
            if !result.verification.pass() {
                eprintln!("warning: the design fails verification; cut anyway because of --force");
            }
            Ok(0)
        }
        Command::Machines => cli::machines(),
        Command::Plot(args) => cli::plot::plot(args),
        Command::Studio(args) => cli::studio::studio(args),
        Command::Emulate(args) => cli::plot::emulate(args),
        Command::Convert { input, output } => cli::convert(&input, &output),
    }
}
