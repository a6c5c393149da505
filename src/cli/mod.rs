//! Helpers of the `crease` binary: argument types, output, progress bars. (Part of the
//! binary, not of the library.)

pub mod animate;
pub mod deform;
pub mod fab;
pub mod fit;
pub mod fold;
pub mod plot;
pub mod studio;
pub mod verify;

use crease::generate;
use crease::io;
use crease::pipeline::PipelineError;
use crease::solver::Move;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};

/// How long and how large the layer-order search may grow: `verify`'s, `convert
/// --assign`'s and `fold --flat`'s, each past them UNDECIDED (exit 3) naming what ran out.
#[derive(clap::Args)]
pub struct SearchArgs {
    /// Seconds the layer-order search may take; past them the verdict is UNDECIDED
    /// (exit 3), saying what was left.
    #[arg(long, default_value_t = crease::limits::DEFAULT_SEARCH_TIME.as_secs_f64())]
    budget: f64,
    /// Megabytes the layer-order problem may take (10 – 200,000); past them the verdict
    /// is UNDECIDED (exit 3). The default keeps the process under about 2 GB.
    #[arg(long, value_name = "MB", default_value_t = crease::fab::budget::DEFAULT_LAYER_MEMORY_MB as f64)]
    memory: f64,
}

impl SearchArgs {
    /// The search's time and memory (MB), range-checked ([`crease::limits`]) before any
    /// work; the caller starts the clock ([`crease::fab::Budget::search`]) when the
    /// search is about to begin, so reading the file does not count against it.
    pub fn checked(&self) -> Result<(std::time::Duration, f64), String> {
        let seconds = crease::limits::SEARCH_TIME
            .check("--budget", self.budget)
            .map_err(|e| e.to_string())?;
        let memory = crease::limits::LAYER_MEMORY
            .check("--memory", self.memory)
            .map_err(|e| e.to_string())?;
        Ok((std::time::Duration::from_secs_f64(seconds), memory))
    }
}

#[derive(clap::Args)]
pub struct GenerateArgs {
    /// Pattern: miura, waterbomb, yoshimura, resch, plane, curved, arc (one curved
    /// crease, folded exactly by the mirror construction), concentric (circular creases
    /// alternating mountain and valley, the construction repeated ring by ring), pleat
    /// (sinusoidal creases alternating, a ruled strip reflected crease by crease),
    /// waterbomb-tube, yoshimura-tube, kresling (tubes: a strip whose two ends are one
    /// seam, paper §7; --nx cells around, --ny along).
    pattern: String,
    /// Cells across (arc, concentric: chords along each crease, a quarter turn; pleat: one
    /// wave across, four rulings a cell).
    #[arg(long, default_value_t = 8)]
    nx: usize,
    /// Cells along (arc: strips across, an even number, half inside the crease;
    /// concentric: strips, a crease between each two, at least 3; pleat: strips, at
    /// least 2).
    #[arg(long, default_value_t = 8)]
    ny: usize,
    /// Cell edge length in mm.
    #[arg(long, default_value_t = 20.0)]
    size: f64,
    /// Miura parallelogram angle in degrees.
    #[arg(long, default_value_t = 60.0)]
    angle: f64,
    /// Fold amount in [0, 1] for the closed-form 3D state (Miura, Yoshimura, plane,
    /// curved, arc, concentric, pleat): the creases reach this fraction of their target angles on average,
    /// as with `fold --amount` (the plane: this fraction of a half turn of bending; the
    /// target of arc, concentric and pleat is 0.8 π, since a curved crease never folds
    /// flat). Default 0.3 Miura, 0.065 Yoshimura, 0.5 plane, curved, arc, concentric and
    /// pleat. Resch: only 1, fully folded
    /// (tucks closed); waterbomb: flat only (fold it with `crease fold`).
    #[arg(long)]
    fold: Option<f64>,
    /// Write only the crease pattern, with no folded 3D form (`--flat` is read as this
    /// too; "flat" alone names the flat-folded state, `fold --flat`).
    #[arg(long = "crease-pattern", alias = "flat", conflicts_with = "fold")]
    crease_pattern: bool,
    /// Twist allowance α of triangulation creases (paper §2.4).
    #[arg(long, default_value_t = 0.0)]
    alpha: f64,
    /// Output file (.fold, .svg, .cp, .obj).
    #[arg(short, long)]
    pub output: PathBuf,
}

impl GenerateArgs {
    pub fn params(&self) -> Result<generate::Params, String> {
        let kind = generate::PatternKind::parse(&self.pattern)?;
        if self.crease_pattern && kind.is_tube() {
            return Err(format!(
                "{} is a tube: it is generated closed and has no flat state of its own, no crease pattern (`crease fab` lays out its strip); drop --crease-pattern",
                kind.name()
            ));
        }
        let defaults = generate::Params::defaults(kind);
        Ok(generate::Params {
            kind,
            nx: self.nx,
            ny: self.ny,
            size: self.size,
            angle_deg: self.angle,
            fold: if self.crease_pattern {
                None
            } else {
                self.fold.or(defaults.fold)
            },
            alpha: self.alpha,
        })
    }
}

/// `crease generate`: the pattern written to the output file.
pub fn generate(args: GenerateArgs) -> Result<u8, String> {
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

/// Prints to standard output; a closed pipe (`crease info x | head`) is not an error.
pub fn out(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

/// A `--drag` argument: `V=X,Y,Z` to a point, or `V=+DX,+DY,+DZ` by an offset (a
/// component written with an explicit `+` makes the whole move relative, so
/// `40=+0,+0,-15` lowers vertex 40 by 15 mm).
#[derive(Clone, Debug)]
pub struct DragArg {
    vertex: usize,
    coords: [f64; 3],
    relative: bool,
}

impl DragArg {
    /// The move in absolute coordinates of `mesh`'s 3D form; refuses unknown vertices.
    pub fn resolve(&self, mesh: &crease::mesh::Mesh) -> Result<Move, String> {
        let n = mesh.vertex_count();
        let at = mesh.positions().get(self.vertex).ok_or_else(|| {
            format!(
                "--drag names vertex {}, which does not exist (the pattern has {n} vertices, 0 to {}); `crease info FILE --vertices` lists them",
                self.vertex,
                n.saturating_sub(1)
            )
        })?;
        let c = self.coords;
        let to = if self.relative {
            [at.x + c[0], at.y + c[1], at.z + c[2]]
        } else {
            c
        };
        Ok(Move {
            vertex: self.vertex,
            to,
        })
    }
}

pub fn parse_drag(text: &str) -> Result<DragArg, String> {
    let bad = || format!("expected V=X,Y,Z or V=+DX,+DY,+DZ, got \"{text}\"");
    let (v, xyz) = text.split_once('=').ok_or_else(bad)?;
    let vertex = v.trim().parse().map_err(|_| bad())?;
    let parts: Vec<&str> = xyz.split(',').map(str::trim).collect();
    let relative = parts.iter().any(|p| p.starts_with('+'));
    let c: Vec<f64> = parts
        .iter()
        .map(|s| s.parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    if c.len() != 3 || !c.iter().all(|x| x.is_finite()) {
        return Err(bad());
    }
    Ok(DragArg {
        vertex,
        coords: [c[0], c[1], c[2]],
        relative,
    })
}

/// A progress bar on standard error, shown only on a terminal and for long runs.
pub fn progress_bar() -> impl FnMut(&str, usize, usize) {
    let mut bar: Option<ProgressBar> = None;
    let mut phase = String::new();
    move |name: &str, done: usize, total: usize| {
        if phase != name {
            if let Some(b) = bar.take() {
                b.finish_and_clear();
            }
            phase = name.to_string();
            let b = ProgressBar::new(total as u64);
            b.set_style(
                ProgressStyle::with_template(
                    "{msg:>6} [{bar:40}] {pos}/{len} steps, {elapsed} (eta {eta})",
                )
                .expect("valid template")
                .progress_chars("=> "),
            );
            b.set_message(name.to_string());
            bar = Some(b);
        }
        if let Some(b) = &bar {
            b.set_position(done as u64);
            if done >= total {
                b.finish_and_clear();
            }
        }
    }
}

/// Exit status for a failed design job: 2 for bad input (named after `input`, the file
/// or script at fault), 1 for a solve that failed, after which a solve that did not
/// converge gets a hint of what to try: the `remedies` of the command not already given.
pub fn design_failure(e: PipelineError, input: &Path, remedies: &[Remedy]) -> Result<u8, String> {
    if e.is_input_error() {
        Err(format!("{}: {e}", input.display()))
    } else {
        eprintln!("error: {e}; nothing was written");
        let untried: Vec<&str> = remedies
            .iter()
            .filter(|r| !r.given)
            .map(|r| r.advice.as_str())
            .collect();
        let stalled = matches!(
            e,
            PipelineError::Solver(crease::solver::SolverError::NotConverged { .. })
        );
        if stalled && !untried.is_empty() {
            eprintln!("hint: try {}", join_or(&untried));
        }
        Ok(1)
    }
}

/// Something to try after a solve that did not converge, and whether the run already
/// did it (then it is not suggested again).
pub struct Remedy {
    /// What to try, naming its option.
    pub advice: String,
    /// The option was given.
    pub given: bool,
}

impl Remedy {
    /// A remedy the run has or has not tried.
    pub fn new(advice: impl Into<String>, given: bool) -> Remedy {
        Remedy {
            advice: advice.into(),
            given,
        }
    }
}

/// "a", "a or b", "a, b or c".
fn join_or(items: &[&str]) -> String {
    match items {
        [] => String::new(),
        [one] => one.to_string(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

/// `crease convert`: any format to any other ([`crease::pipeline::convert`]); exit 1
/// when `--assign` finds no assignment, 3 when its search stops.
pub fn convert(
    input: &Path,
    output: &Path,
    assign: bool,
    crease_pattern_first: bool,
    search: &SearchArgs,
) -> Result<u8, String> {
    let (time, memory) = search.checked()?;
    let imported = io::read_with_notes(input).map_err(|e| e.to_string())?;
    for note in &imported.notes {
        eprintln!("note: {note}");
    }
    let format = io::Format::from_path(output).map_err(|e| e.to_string())?;
    if crease_pattern_first {
        if format != io::Format::Fold || assign {
            return Err(format!(
                "{}: --crease-pattern-first writes a FOLD design (a .fold output, without --assign)",
                output.display()
            ));
        }
        let text = crease::pipeline::crease_pattern_first(imported.mesh)
            .map_err(|e| format!("{}: {e}", input.display()))?;
        io::write_atomic(output, text.as_bytes()).map_err(|e| e.to_string())?;
        eprintln!("wrote {} (frame 0 the crease pattern)", output.display());
        return Ok(0);
    }
    let budget = crease::fab::Budget::search(time, memory);
    let converted = match crease::pipeline::convert(imported.mesh, format, assign, &budget) {
        Ok(c) => c,
        Err(e) if e.exit_code() == 2 => return Err(format!("{}: {e}", input.display())),
        Err(e) => {
            eprintln!("error: {}: {e}; nothing was written", input.display());
            return Ok(e.exit_code());
        }
    };
    for note in &converted.notes {
        eprintln!("note: {}: {note}", input.display());
    }
    match &converted.face_orders {
        Some(orders) => {
            let text = io::fold::to_string_with_orders(&converted.mesh, Some(orders));
            io::write_atomic(output, text.as_bytes()).map_err(|e| e.to_string())?;
            eprintln!(
                "wrote {} (with the layer order as faceOrders)",
                output.display()
            );
        }
        None => {
            io::write(&converted.mesh, output).map_err(|e| e.to_string())?;
            eprintln!("wrote {}", output.display());
        }
    }
    Ok(0)
}

/// `crease machines`: the profiles `--machine` can name, with protocol and media.
/// `crease materials`: the materials `--material` can name, with what they set.
pub fn materials() -> Result<u8, String> {
    let mut table = String::new();
    for name in crease::machine::known_materials() {
        match crease::machine::Material::load(&name) {
            Ok(m) => table.push_str(&format!(
                "{name:<22} {:>5.2} mm  mountain {:?} valley {:?}  clearance {} mm  force x{} speed x{}  {}\n",
                m.thickness_mm,
                m.dash.mountain,
                m.dash.valley,
                m.clearance_mm,
                m.force_scale,
                m.speed_scale,
                m.name
            )),
            Err(e) => table.push_str(&format!("{name:<22} (unusable: {e})\n")),
        }
    }
    out(&table);
    Ok(0)
}

pub fn machines() -> Result<u8, String> {
    let mut table = String::new();
    for name in crease::machine::known_machines() {
        match crease::machine::Machine::load(&name) {
            Ok(m) => table.push_str(&format!(
                "{name:<18} {:<6} {:<8} {}\n",
                m.protocol, m.media, m.name
            )),
            Err(e) => table.push_str(&format!("{name:<18} (unusable: {e})\n")),
        }
    }
    out(&table);
    Ok(0)
}

/// A note when design mode changed the sheet's size, `hint` after it (the flag that
/// would have held it, or nothing).
fn say_if_the_sheet_changed(resized: Option<crease::pipeline::SheetResize>, hint: &str) {
    if let Some(crease::pipeline::SheetResize { before, after }) = resized {
        eprintln!(
            "note: the sheet is {:.1} × {:.1} mm flat, where it was {:.1} × {:.1} mm: design mode frees lengths{hint}",
            after.x, after.y, before.x, before.y
        );
    }
}
