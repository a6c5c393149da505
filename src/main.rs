//! The `crease` command line: parse, call the library, print, exit.
//! Exit status: 0 success, 1 the design fails a check, 2 bad input or arguments.

mod cli;

// The solver builds and drops Jacobians of tens of megabytes every Newton iteration;
// glibc hands such blocks back to the kernel each time, and the page faults of taking them
// again cost a sixth of a step. mimalloc keeps them (see crease::allocator).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
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

/// The shapes people ask of `deform` first, on the Miura-ori of `crease generate miura
/// --nx 6 --ny 10 --fold 0.5 -o m.fold` (each checked to verify).
const DEFORM_RECIPES: &str = "\
Recipes, on m.fold from `crease generate miura --nx 6 --ny 10 --fold 0.5 -o m.fold`
(corners 0, 6, 70, 76, middle 38; `crease info m.fold --vertices` lists every vertex):
  arch:   crease deform m.fold --drag 0=+0,+15,-45 --drag 6=+0,+15,-45 --drag 70=+0,-15,-45
          --drag 76=+0,-15,-45 --keep-outline --alpha 0.1 -o arch.fold
  twist:  crease deform m.fold --drag 0=+0,+0,+20 --drag 76=+0,+0,+20 --drag 6=+0,+0,-20
          --drag 70=+0,+0,-20 --keep-outline --alpha 0.1 -o twist.fold
  bump:   crease deform m.fold --drag 38=+0,+0,+25 --keep-outline --alpha 0.1 -o bump.fold
  a dome, a saddle or any surface: `crease surface cap --radius 250 -o cap.obj`, then
          `crease fit m.fold --to cap.obj -o dome.fold` (`surface saddle` for a saddle)
Design mode frees lengths: without --keep-outline a drag redraws the sheet's outline (the
arch's 130 x 173 mm sheet becomes 155 x 177 mm with a ragged edge); --alpha 0.1 lets the
flat creases twist a little (paper section 2.4). A script (patterns/miura-bent.toml) makes
a design repeatable.";

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
    /// Write the folding motion from the flat sheet to the design (the path `verify
    /// --path` checks) as glTF (.glb, .gltf), a multi-frame FOLD or an animated PNG.
    Animate(cli::animate::AnimateArgs),
    /// Vary a pattern by dragging vertices while the chosen conditions keep holding.
    #[command(after_help = DEFORM_RECIPES)]
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
    /// Convert between pattern formats, chosen by extension (.fold, .cp, .svg, .obj; .opx is read only).
    Convert {
        /// Input file.
        input: PathBuf,
        /// Output file.
        output: PathBuf,
        /// Give a crease pattern's unassigned creases the mountains and valleys of a
        /// flat-folded state found for it, its own kept (exit 1 naming the faces when none exists, 3
        /// when the search stops).
        #[arg(long)]
        assign: bool,
        /// Write a FOLD design with its crease pattern as frame 0 and its 3D form in the
        /// frame after it, the order Origami Simulator, Rabbit Ear and ORIPA open
        /// (crease writes the 3D form first by default and reads both).
        #[arg(long)]
        crease_pattern_first: bool,
        /// The layer search's time and memory (with --assign).
        #[command(flatten)]
        search: cli::SearchArgs,
    },
}

fn main() -> ExitCode {
    crease::allocator::set_up();
    // A negative number is a value (`--width -3` is out of range, not an unknown flag).
    let command = Cli::command().mut_subcommands(|sub| sub.allow_negative_numbers(true));
    let cli = match command
        .try_get_matches()
        .and_then(|m| Cli::from_arg_matches(&m))
    {
        Ok(c) => c,
        Err(e) if e.use_stderr() => {
            let tip = file_taken_as_value(&e);
            // clap prints no usage with a bad value; its command is the one typed.
            let typed = std::env::args().nth(1).filter(|word| {
                Cli::command()
                    .get_subcommands()
                    .any(|sub| sub.get_name() == word)
            });
            eprintln!(
                "{}",
                usage_error_line(&e.render().to_string(), tip.as_deref(), typed.as_deref())
            );
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

/// clap's error message as one line, as every other error is: the message with what it
/// lists (the missing arguments, the values a flag takes) and its tips ("a similar
/// argument exists"), the usage it printed, and which help to read. clap writes these
/// over several lines; only the first used to be kept, which for a missing argument was
/// "the following required arguments were not provided:" with the list cut off.
fn usage_error_line(rendered: &str, tip: Option<&str>, typed: Option<&str>) -> String {
    let mut message = String::new();
    let mut usage = None;
    for line in rendered.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if let Some(rest) = line.strip_prefix("Usage:") {
            usage = Some(rest.trim().to_string());
            break;
        }
        if !message.is_empty() {
            // A list follows its "…:" heading; anything else is a sentence of its own.
            message.push_str(if message.ends_with(':') { " " } else { "; " });
        }
        message.push_str(line);
        // The tip belongs with the error it explains, before clap's pointers to help.
        if let Some(tip) = tip.filter(|_| line.starts_with("error:")) {
            message.push_str("; ");
            message.push_str(tip);
        }
    }
    if message.is_empty() {
        message.push_str("error: bad arguments");
    }
    // The command's help: `crease SUB --help` where the usage names a subcommand, or
    // else the subcommand typed.
    let help = usage
        .as_deref()
        .and_then(|u| {
            let mut words = u.split_whitespace();
            (words.next() == Some("crease")).then(|| words.next())?
        })
        .filter(|sub| sub.chars().all(|c| c.is_ascii_lowercase() || c == '-'))
        .or(typed)
        .map_or("crease --help".to_string(), |sub| {
            format!("crease {sub} --help")
        });
    match usage {
        Some(usage) => format!("{message} (usage: {usage}; see `{help}`)"),
        None => format!("{message} (see `{help}`)"),
    }
}

/// What to do when a flag whose value is optional (`--count`, `--remesh`) or repeated
/// (`--fix`) took the file named after it as its value: `crease verify --count
/// design.fold` reads `design.fold` as the cap, and clap's own message ("invalid digit
/// found in string") does not say why. A value that names a file, or ends in a file
/// extension (a number's "extension" is digits), is taken for a file.
fn file_taken_as_value(e: &clap::Error) -> Option<String> {
    use clap::error::{ContextKind, ContextValue};
    let (Some(ContextValue::String(value)), Some(ContextValue::String(arg))) = (
        e.get(ContextKind::InvalidValue),
        e.get(ContextKind::InvalidArg),
    ) else {
        return None;
    };
    let path = std::path::Path::new(value);
    let named_like_a_file = path
        .extension()
        .is_some_and(|x| x.to_string_lossy().chars().any(|c| c.is_ascii_alphabetic()));
    if !(named_like_a_file || path.is_file()) {
        return None;
    }
    let flag = arg.split_whitespace().next()?;
    Some(format!(
        "tip: '{value}' was read as {flag}'s value; if it is the file, give it before {flag}"
    ))
}

fn run(cli: Cli) -> Result<u8, String> {
    match cli.command {
        Command::Generate(args) => cli::generate(args),
        Command::Info(args) => cli::verify::info(args),
        Command::Verify(args) => cli::verify::verify(args),
        Command::Fold(args) => cli::fold::fold(args),
        Command::Animate(args) => cli::animate::animate(args),
        Command::Deform(args) => cli::deform::deform(args),
        Command::Fit(args) => cli::fit::fit(args),
        Command::Surface(args) => cli::fit::surface(args),
        Command::Fab(args) => cli::fab::fab(args),
        Command::Machines => cli::machines(),
        Command::Materials => cli::materials(),
        Command::Plot(args) => cli::plot::plot(args),
        Command::Studio(args) => cli::studio::studio(args),
        Command::Emulate(args) => cli::plot::emulate(args),
        Command::Convert {
            input,
            output,
            assign,
            crease_pattern_first,
            search,
        } => cli::convert(&input, &output, assign, crease_pattern_first, &search),
    }
}
