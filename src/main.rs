//! The `crease` command line: parse, call the library, print, exit.
//! Exit status: 0 success, 1 the design fails a check, 2 bad input or arguments.

use clap::{Parser, Subcommand};
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
        /// convexity, flat-foldability, angular-inequality, fold-angle-range, edge-length.
        /// Default: what the design's assignment calls for.
        #[arg(long)]
        conditions: Option<String>,
    },
    /// Convert between pattern formats, chosen by extension (.fold, .cp, .svg, .obj).
    Convert {
        /// Input file.
        input: PathBuf,
        /// Output file.
        output: PathBuf,
    },
}

#[derive(clap::Args)]
struct GenerateArgs {
    /// Pattern: miura, waterbomb, yoshimura, resch, plane, curved.
    pattern: String,
    /// Cells across.
    #[arg(long, default_value_t = 8)]
    nx: usize,
    /// Cells along.
    #[arg(long, default_value_t = 8)]
    ny: usize,
    /// Cell edge length in mm.
    #[arg(long, default_value_t = 20.0)]
    size: f64,
    /// Miura parallelogram angle in degrees.
    #[arg(long, default_value_t = 60.0)]
    angle: f64,
    /// Fold amount in [0, 1] for the closed-form 3D state (Miura, Yoshimura, plane,
    /// curved); default 0.5 for those, flat-only for waterbomb and Resch.
    #[arg(long)]
    fold: Option<f64>,
    /// Write only the flat crease pattern.
    #[arg(long, conflicts_with = "fold")]
    flat: bool,
    /// Twist allowance α of triangulation creases (paper §2.4).
    #[arg(long, default_value_t = 0.0)]
    alpha: f64,
    /// Output file (.fold, .svg, .cp, .obj).
    #[arg(short, long)]
    output: PathBuf,
}

impl GenerateArgs {
    fn params(&self) -> Result<generate::Params, String> {
        let kind = generate::PatternKind::from_name(&self.pattern).ok_or_else(|| {
            let names: Vec<&str> = generate::PatternKind::ALL
                .iter()
                .map(|k| k.name())
                .collect();
            format!(
                "unknown pattern \"{}\" (choose one of: {})",
                self.pattern,
                names.join(", ")
            )
        })?;
        let defaults = generate::Params::defaults(kind);
        Ok(generate::Params {
            kind,
            nx: self.nx,
            ny: self.ny,
            size: self.size,
            angle_deg: self.angle,
            fold: if self.flat {
                None
            } else {
                self.fold.or(defaults.fold)
            },
            alpha: self.alpha,
        })
    }
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
        Command::Info { file } => {
            let imported = io::read_with_notes(&file).map_err(|e| e.to_string())?;
            for note in &imported.notes {
                eprintln!("note: {note}");
            }
            println!("file:         {}", file.display());
            print!("{}", imported.mesh.info());
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
                println!("{}", report.to_json());
            } else {
                print!("{report}");
            }
            Ok(if report.pass() { 0 } else { 1 })
        }
        Command::Convert { input, output } => {
            let imported = io::read_with_notes(&input).map_err(|e| e.to_string())?;
            for note in &imported.notes {
                eprintln!("note: {note}");
            }
            io::write(&imported.mesh, &output).map_err(|e| e.to_string())?;
            eprintln!("wrote {}", output.display());
            Ok(0)
        }
    }
}
