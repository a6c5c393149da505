//! `crease fab`: verify, unfold, lay out, score and write the sheet's files.

use crease::io;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct FabArgs {
    /// Design file (.fold, .cp, .opx, .svg, .obj).
    design: PathBuf,
    /// Machine profile: a name from machines/ or a path to a .toml file.
    #[arg(long, default_value = "generic-hpgl")]
    machine: String,
    /// Material: a name from materials/ (`crease materials` lists them) or a path to a
    /// .toml file; sets the dash codes, clearance, force and speed for that sheet
    /// (default: none, the machine profile's own values, set for 250 g/m² cardstock).
    #[arg(long)]
    material: Option<String>,
    /// Media: a4, a3, letter, 12x12in, WxHmm (default: the machine's).
    #[arg(long)]
    media: Option<String>,
    /// Scale the pattern so the laid-out sheet is this wide in mm, measured after it is
    /// turned to fit (default: design units are mm).
    #[arg(long, conflicts_with = "fit")]
    width: Option<f64>,
    /// Scale the pattern to the largest size the media takes within the margins, in the
    /// orientation that allows most (default: off).
    #[arg(long)]
    fit: bool,
    /// Margin kept free on every side, mm (default: the machine's).
    #[arg(long)]
    margin: Option<f64>,
    /// Output folder (default: out/DESIGN-NAME). `-o`/`--output` as in every other
    /// command; `--out` kept for the scripts that use it.
    #[arg(short = 'o', long = "output", visible_alias = "out")]
    out: Option<PathBuf>,
    /// Cut even if the design fails verification.
    #[arg(long)]
    force: bool,
    /// Score mountains from the back: a second, mirrored job (sheet-back.*) that also cuts
    /// the outline, last, so the piece stays in the sheet until both sides are scored.
    #[arg(long)]
    mountains_from_back: bool,
    /// Split a sheet too large for the media over several PDF pages, with overlap and
    /// registration marks, instead of refusing (no cutter job is written then).
    #[arg(long)]
    tile: bool,
    /// Leave flat (triangulation) lines off the printed template (default: drawn light
    /// grey and dotted; they are never cut or scored).
    #[arg(long)]
    hide_flat: bool,
    /// Also write motion.png, the folding motion from the flat sheet to the design (30
    /// steps of the path `verify --path` checks; `crease animate` for glTF and FOLD).
    #[arg(long)]
    motion: bool,
    /// End sheet.pdf with the folding guide whatever the design's size (default: for
    /// designs of up to 1000 vertices with a 3D form, where the path from flat is clear).
    #[arg(long, conflicts_with = "no_guide")]
    guide: bool,
    /// Leave the folding guide off sheet.pdf.
    #[arg(long)]
    no_guide: bool,
    /// Print-then-cut: lay the sheet out on a printed page (--media, default a4 for
    /// Silhouette, letter for Cricut) with the machine's registration marks, and cut in
    /// their frame (default: off; the machine's profile names its marks).
    #[arg(long)]
    print_and_cut: bool,
    /// Print-then-cut: print the paper's face in this colour, #RRGGBB (default: none,
    /// white paper).
    #[arg(long, requires = "print_and_cut")]
    print_fill: Option<String>,
    /// A tube's glue tab width in mm, before scaling (default 6): the tab hangs from one
    /// side of the seam, its hinge scored as a valley, its outline cut.
    #[arg(long)]
    tab: Option<f64>,
    /// Route the cutting order by local moves only, skipping the long search: the files
    /// come in a fraction of the time with more pen-up travel (for checking a layout; cut
    /// the job of a run without it).
    #[arg(long)]
    draft_route: bool,
}

pub fn fab(args: FabArgs) -> Result<u8, String> {
    let mut machine = crease::machine::Machine::load(&args.machine).map_err(|e| e.to_string())?;
    if let Some(name) = &args.material {
        machine = machine
            .with_material(&crease::machine::Material::load(name).map_err(|e| e.to_string())?);
    }
    let options = options_of(&args)?;
    let mesh = io::read(&args.design).map_err(|e| e.to_string())?;
    let result = match crease::pipeline::fabricate(&mesh, &machine, &options) {
        Ok(r) => r,
        Err(e) if e.is_input() => return Err(e.naming(&flag)),
        Err(rejected) => {
            eprintln!("error: {}", rejected.naming(&flag));
            eprintln!("nothing was written");
            return Ok(1);
        }
    };
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| crease::pipeline::names::fab_folder(&args.design));
    io::write_all_atomic(&dir, &result.files).map_err(|e| e.to_string())?;
    let removed = crease::pipeline::remove_stale_outputs(&dir, &result.files);
    if !removed.is_empty() {
        eprintln!(
            "{}: removed {} from an earlier run",
            dir.display(),
            removed.join(", ")
        );
    }
    if result.report.sheet.tiled {
        eprintln!(
            "{}: the sheet is larger than {}; sheet.pdf is tiled over pages with {} mm overlap and registration marks (no cutter job written)",
            dir.display(),
            options.media.as_ref().map_or(&machine.media, |m| &m.name),
            crease::pipeline::TILE_OVERLAP_MM
        );
        return Ok(0);
    }
    say_what_was_made(&dir, &result);
    Ok(0)
}

/// The run's options from the command line; a media or colour that does not parse is
/// refused naming the option.
fn options_of(args: &FabArgs) -> Result<crease::pipeline::FabOptions, String> {
    let print_fill = args
        .print_fill
        .as_deref()
        .map(|c| crease::output::colour::parse_hex("--print-fill", c))
        .transpose()?;
    let media = args
        .media
        .as_deref()
        .map(crease::fab::Media::parse)
        .transpose()?;
    Ok(crease::pipeline::FabOptions {
        media,
        width: args.width,
        fit: args.fit,
        margin: args.margin,
        force: args.force,
        mountains_from_back: args.mountains_from_back,
        tile: args.tile,
        hide_flat: args.hide_flat,
        motion: args.motion,
        guide: match (args.guide, args.no_guide) {
            (true, _) => crease::pipeline::Guide::Always,
            (_, true) => crease::pipeline::Guide::Never,
            _ => crease::pipeline::Guide::Auto,
        },
        print_and_cut: args.print_and_cut,
        print_fill,
        tab: args.tab,
        route: if args.draft_route {
            crease::fab::RouteSearch::Draft
        } else {
            crease::fab::RouteSearch::Full
        },
    })
}

/// The summary on stderr: the job, the steps to take, and what the maker must do by hand.
fn say_what_was_made(dir: &std::path::Path, result: &crease::pipeline::FabOutput) {
    let sheet = &result.report.sheet;
    let material = sheet
        .material
        .as_deref()
        .map_or(String::new(), |m| format!(", {m}"));
    eprintln!(
        "{}: the pattern is {:.1} × {:.1} mm on {} ({:.0} × {:.0} mm{material}); {} strokes; {}",
        dir.display(),
        sheet.size_mm[0],
        sheet.size_mm[1],
        sheet.media.name,
        sheet.media.width_mm,
        sheet.media.height_mm,
        sheet.strokes,
        result.job_line
    );
    for note in result.template_note.iter().chain(&result.guide_note) {
        eprintln!("{note}");
    }
    if !result.steps.is_empty() {
        eprintln!("two-sided job:");
        for step in &result.steps {
            eprintln!("  {step}");
        }
    }
    if let Some(next) = &result.next_steps {
        eprintln!("next, in {}:", next.software);
        // The library names the output folder OUT (report.json keeps it so); here the
        // folder is known, and the command is given as the maker types it.
        let plot = format!("crease plot {}", dir.display());
        for (i, step) in next.steps.iter().enumerate() {
            eprintln!("  {}. {}", i + 1, step.replace("crease plot OUT", &plot));
        }
    }
    if let Some(hinge) = &result.report.hinge {
        let widest = hinge.folds.iter().map(|f| f.gap_mm).fold(0.0, f64::max);
        eprintln!(
            "panels.svg, panels.dxf: {} panels of {:?} mm sheet, set back from each valley by half its hinge gap (widest {widest:.1} mm); glue them on a membrane along the scored sheet",
            hinge.panels, hinge.thickness_mm
        );
    }
    if let Some(seam) = &result.report.seam {
        eprintln!(
            "a tube: one strip with a {} mm glue tab; fold the tab under and glue its {} numbered edges onto the edges numbered alike (sheet.pdf prints the numbers, report.json pairs them)",
            seam.tab_mm,
            seam.pairs.len()
        );
    }
    for warning in &result.warnings {
        eprintln!("warning: {warning}");
    }
    if !result.verification.pass() {
        eprintln!(
            "warning: verdict {}; cut anyway because of --force",
            result.verification.verdict()
        );
    }
}

/// The flag of a fabrication option a message asks to change: `fab`'s flags are the
/// options' words (a test reads `fab --help` for every one).
pub(crate) fn flag(option: crease::fab::FabOption) -> String {
    format!("--{}", option.word())
}
