//! The `crease` command line: parse, call the library, print, exit.
//! Exit status: 0 success, 1 the design fails a check, 2 bad input or arguments.

mod cli;

// The solver builds and drops Jacobians of tens of megabytes every Newton iteration;
// glibc hands such blocks back to the kernel each time, and the page faults of taking them
// again cost a sixth of a step. mimalloc keeps them (see crease::allocator).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use clap::{Parser, Subcommand};
use cli::GenerateArgs;
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
    Info(cli::verify::InfoArgs),
    /// Check a design against the origami conditions (exit 1 if one fails).
    Verify(cli::verify::VerifyArgs),
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
        Command::Generate(args) => cli::generate(args),
        Command::Info(args) => cli::verify::info(args),
        Command::Verify(args) => cli::verify::verify(args),
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
