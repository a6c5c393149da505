//! The `crease` command line: parse, call the library, print, exit.
//! Exit status: 0 success, 1 the design fails a check, 2 bad input or arguments.

mod cli;

// The solver builds and drops Jacobians of tens of megabytes every Newton iteration;
// glibc hands such blocks back to the kernel each time, and the page faults of taking them
// again cost a sixth of a step. mimalloc keeps them (see crease::allocator).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use clap::{Parser, Subcommand};
use cli::{out, GenerateArgs};
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
    },
    /// Fold a pattern in simulation mode (rigid panels), driving every crease toward a
    /// fraction of its target angle; or, with --flat, write its flat-folded state.
    Fold(cli::fold::FoldArgs),
    /// Vary a pattern by dragging vertices while the chosen conditions keep holding.
    Deform(cli::deform::DeformArgs),
    /// Fit a pattern to a target surface (OBJ or STL, mm): placed on it, then pulled
    /// onto it while the chosen conditions keep holding; writes OUT and OUT.fit.json
    /// (exit 1 when the distance goal is not met; the best design is still written).
    Fit(cli::fit::FitArgs),
    /// Write a target surface for `fit`: a spherical cap, a saddle or a cylinder.
    Surface(cli::fit::SurfaceArgs),
    /// Fabricate a design: verify, unfold, lay out on the media, score folds with the
    /// machine's dash codes, and write sheet.svg, sheet.pdf, the cutter's job (sheet.hpgl
    /// or sheet.gpgl), sheet.dxf, the previews sheet.png and design.png,
    /// crease-pattern.svg, crease-pattern.fold (with faceOrders when it folds flat) and
    /// report.json.
    Fab(cli::fab::FabArgs),
    /// List the machine profiles `--machine` can name.
    Machines,
    /// List the materials `fab --material` can name.
    Materials,
    /// Send an HP-GL or GP-GL job to a plotter or cutter over a serial port, with flow
    /// control, progress confirmed by the machine, and a journal for --resume.
    Plot(cli::plot::PlotArgs),
    /// Run an emulated HP-GL plotter or GP-GL cutter on a pseudo-terminal until Ctrl-C.
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
    crease::allocator::keep_freed_memory();
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) if e.use_stderr() => {
            // One line, as every other error: clap's first, and where the rest is.
            let text = e.render().to_string();
            let first = text.lines().next().unwrap_or("bad arguments");
            eprintln!("{first} (see `crease --help`, or `crease COMMAND --help`)");
            return ExitCode::from(2);
        }
        Err(e) => {
            let _ = e.print();
            return ExitCode::SUCCESS;
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
            path,
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
                tolerances = fab::Tolerances::exactly(t);
            }
            let mesh = io::read(&file).map_err(|e| e.to_string())?;
            let report = fab::verify(&mesh, set.as_ref(), tolerances);
            let path = path
                .then(|| crease::pipeline::folding_path(&mesh, &mut cli::progress_bar()))
                .transpose()
                .map_err(|e| format!("{}: the path from flat: {e}", file.display()))?;
            let collides = path.as_ref().is_some_and(|p| p.collision.is_some());
            if json {
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
        Command::Fold(args) => cli::fold::fold(args),
        Command::Deform(args) => cli::deform::deform(args),
        Command::Fit(args) => cli::fit::fit(args),
        Command::Surface(args) => cli::fit::surface(args),
        Command::Fab(args) => cli::fab::fab(args),
        Command::Machines => cli::machines(),
        Command::Materials => cli::materials(),
        Command::Plot(args) => cli::plot::plot(args),
        Command::Studio(args) => cli::studio::studio(args),
        Command::Emulate(args) => cli::plot::emulate(args),
        Command::Convert { input, output } => cli::convert(&input, &output),
    }
}
