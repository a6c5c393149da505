//! GP-GL for Graphtec and Silhouette cutters: every command ends with ETX (0x03), moves
//! (`M`) and cuts (`D`) are absolute and integer, in the axis order the cutter expects.
//! Positions are rounded from millimetres once, so rounding never drifts, and a run of
//! joined strokes is one `D` with all its points.

use crate::fab::{LineKind, Toolpath};
use crate::output::ToolSetting;
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// End of every GP-GL command.
pub const ETX: char = '\u{3}';
/// Resets the cutter (`ESC EOT`) before a job.
pub const RESET: &str = "\u{1b}\u{4}";

/// What the writer needs from a machine profile.
#[derive(Clone, Debug, PartialEq)]
pub struct GpglSettings {
    /// Cutter steps per mm (20: 0.05 mm on Silhouette and most Graphtec settings).
    pub units_per_mm: f64,
    /// `M feed,carriage` (portrait, `FN0`) when true, `M carriage,feed` otherwise.
    pub feed_first: bool,
    /// Drag-knife offset, mm (`FC`, sent in 0.05 mm); 0 for a pen.
    pub blade_offset_mm: f64,
    /// Tool per line kind: `pen` is the tool holder (`J`), `speed` mm/s (`!`, in cm/s),
    /// `force` the pressure (`FX`, 1–33).
    pub tools: BTreeMap<LineKind, ToolSetting>,
    /// Print-and-cut: find these registration marks first and cut in their frame.
    pub registration: Option<Registration>,
}

/// Registration marks a print-and-cut job finds before it cuts
/// ([`crate::fab::print_and_cut`]): once found, the cutter's (0, 0) is the marks' origin
/// and it cuts nothing outside their frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Registration {
    /// The origin (the top-left corner of the square mark) on the sheet, mm, y up.
    pub origin: crate::mesh::Vec2,
    /// The frame: distance from the origin to the top-right mark (width) and to the
    /// bottom-left mark (length), mm.
    pub size: [f64; 2],
}

/// The command that searches for the marks; the cutter answers `0` (found) when done.
pub const SEARCH_MARKS: &str = "TB123";

/// Silhouette's registration set-up, as inkscape-silhouette's `Graphtec.py` sends it: mark
/// mode on (`TB50,0`, `TB99`), Cameo portrait marks (`TB52,2`), marks 20 mm long
/// (`TB51,400`) and 0.5 mm wide (`TB53,10`), `TB55,1`, then the automatic search
/// (`TB123,length,width,top,left`, in steps) starting 10 mm before the origin.
fn registration_commands(r: &Registration, page_height: f64, u: f64) -> Vec<String> {
    let steps = |mm: f64| (mm * u).round() as i64;
    let top = page_height - r.origin.y;
    vec![
        "TB50,0".into(),
        "TB99".into(),
        "TB52,2".into(),
        "TB51,400".into(),
        "TB53,10".into(),
        "TB55,1".into(),
        format!(
            "{SEARCH_MARKS},{},{},{},{}",
            steps(r.size[1]),
            steps(r.size[0]),
            steps(top - 10.0),
            steps(r.origin.x - 10.0)
        ),
    ]
}

/// The answer a cutter gives to `cmd`, if it answers: the mark search's `0` (found),
/// right-aligned in five characters as a Cameo sends it.
pub fn reply_to(cmd: &str) -> Option<String> {
    cmd.trim()
        .starts_with(SEARCH_MARKS)
        .then(|| format!("    0{ETX}"))
}

/// Writes a toolpath as GP-GL. The cutter's origin is the media's top-left corner (or,
/// registered, the marks' origin), its carriage axis the sheet's x and its feed axis runs
/// down the sheet (the toolpath's y grows upward, so feed = top − y); strokes whose kind
/// has no tool are an error.
pub fn to_string(path: &Toolpath, settings: &GpglSettings) -> Result<String, String> {
    use crate::mesh::Vec2;
    let u = settings.units_per_mm;
    let order = |(x, y): (i64, i64)| if settings.feed_first { (y, x) } else { (x, y) };
    let h = path.media.height;
    let (origin, limits) = match &settings.registration {
        Some(r) => (r.origin, Vec2::new(r.size[0], r.size[1])),
        None => (
            Vec2::new(0.0, h),
            Vec2::new(path.media.width, path.media.height),
        ),
    };
    let down = |p: Vec2| Vec2::new(p.x - origin.x, origin.y - p.y);
    let point = |p: Vec2| order(((p.x * u).round() as i64, (p.y * u).round() as i64));
    let mut out = String::from(RESET);
    let command = |out: &mut String, text: &str| {
        out.push_str(text);
        out.push(ETX);
    };
    command(&mut out, "FN0");
    if let Some(r) = &settings.registration {
        for c in registration_commands(r, h, u) {
            command(&mut out, &c);
        }
    }
    let (limit_a, limit_b) = point(limits);
    command(&mut out, "\\0,0");
    command(&mut out, &format!("Z{limit_a},{limit_b}"));
    // `at` in (x, y) steps, the order the sheet has; `order` turns it into the cutter's.
    let mut at = (0i64, 0i64);
    let mut tool: Option<LineKind> = None;
    let mut current = ToolState::default();
    for (kind, points) in runs_in_cutting_order(path) {
        if tool != Some(kind) {
            let t = settings
                .tools
                .get(&kind)
                .ok_or_else(|| format!("the machine has no tool for {} lines", kind.name()))?;
            set_tool(&mut out, &mut current, t, settings.blade_offset_mm);
            tool = Some(kind);
        }
        let exact: Vec<(f64, f64)> = points
            .iter()
            .map(|&p| (down(p).x * u, down(p).y * u))
            .collect();
        let steps = snap_chain(&exact);
        let mut cut = String::new();
        let mut last = steps[0];
        for &q in &steps[1..] {
            if q != last {
                let (a, b) = order(q);
                let _ = write!(cut, "{}{a},{b}", if cut.is_empty() { 'D' } else { ',' });
                last = q;
            }
        }
        if cut.is_empty() {
            continue; // shorter than a cutter step
        }
        if steps[0] != at {
            let (a, b) = order(steps[0]);
            command(&mut out, &format!("M{a},{b}"));
        }
        command(&mut out, &cut);
        at = last;
    }
    // Lift and go home, so the next sheet can be loaded.
    command(&mut out, "M0,0");
    command(&mut out, "H");
    Ok(out)
}

/// What the cutter has been told so far: each of the tool holder, speed, force and blade
/// offset is sent when it changes, not at every change of line kind (mountains and
/// valleys on one holder share their settings).
#[derive(Default)]
struct ToolState {
    holder: Option<u32>,
    speed: Option<i64>,
    force: Option<i64>,
    offset: Option<i64>,
}

fn set_tool(out: &mut String, current: &mut ToolState, t: &ToolSetting, blade_offset_mm: f64) {
    let mut send = |text: String| {
        out.push_str(&text);
        out.push(ETX);
    };
    if current.holder != Some(t.pen) {
        send(format!("J{}", t.pen));
        current.holder = Some(t.pen);
    }
    if let Some(v) = t.speed {
        let v = (v / 10.0).round().clamp(1.0, 30.0) as i64;
        if current.speed != Some(v) {
            send(format!("!{v}"));
            current.speed = Some(v);
        }
    }
    if let Some(f) = t.force {
        let f = f.round().clamp(1.0, 33.0) as i64;
        if current.force != Some(f) {
            send(format!("FX{f}"));
            current.force = Some(f);
        }
    }
    let offset = (blade_offset_mm * 20.0).round() as i64;
    if current.offset != Some(offset) {
        send(format!("FC{offset}"));
        current.offset = Some(offset);
    }
}

/// The toolpath as runs of joined strokes of one kind, (kind, points), in the toolpath's
/// cutting order: only strokes that follow each other join, so the job cuts as routed.
/// A bent stroke goes as its chords.
fn runs_in_cutting_order(path: &Toolpath) -> Vec<(LineKind, Vec<crate::mesh::Vec2>)> {
    let mut runs: Vec<(LineKind, Vec<crate::mesh::Vec2>)> = Vec::new();
    for s in &path.strokes {
        let points = s.polyline();
        match runs.last_mut() {
            Some((kind, run)) if *kind == s.kind && (run[run.len() - 1] - s.from).norm() < 1e-9 => {
                run.extend_from_slice(&points[1..])
            }
            _ => runs.push((s.kind, points)),
        }
    }
    runs
}

/// Rounds a run of points (in steps) each to its nearest step, so every end lies within
/// half a step of the toolpath's on each axis (snapping to minimise length errors instead
/// moved ends up to a full step and opened closed outlines). A run that comes back to its
/// start ends on the very step it started from, so the piece comes free.
fn snap_chain(points: &[(f64, f64)]) -> Vec<(i64, i64)> {
    let nearest = |p: &(f64, f64)| (p.0.round() as i64, p.1.round() as i64);
    let mut snapped: Vec<(i64, i64)> = points.iter().map(nearest).collect();
    let (first, last) = (points[0], points[points.len() - 1]);
    if points.len() > 2 && (first.0 - last.0).hypot(first.1 - last.1) < 1e-6 {
        let n = snapped.len();
        snapped[n - 1] = snapped[0];
    }
    snapped
}

/// The name of a GP-GL command: two capitals (`FX`, `FC`, `FN`, `TB`) or one character
/// (`M`, `D`, `J`, `Z`, `H`, `!`, `\`).
pub fn command_name(cmd: &str) -> &str {
    let b = cmd.as_bytes();
    let two = b.len() >= 2 && b[0].is_ascii_uppercase() && b[1].is_ascii_uppercase();
    &cmd[..if two { 2 } else { b.len().min(1) }]
}

/// A cutter executing GP-GL one command at a time, as the emulator and the sender's
/// journal need it: `M` and `D` move (absolute, in the job's own axis order), `J` picks
/// the tool holder, `H` goes home; set-up commands are accepted. Drawn segments are
/// recorded as (tool holder, from, to) in cutter steps, as sent.
#[derive(Clone, Debug, Default)]
pub struct Interpreter {
    /// Everything cut so far.
    pub path: crate::output::hpgl::PenPath,
    tool: u32,
}

impl Interpreter {
    /// A cutter just reset (`ESC EOT`): at the origin, tool holder 1.
    pub fn new() -> Interpreter {
        Interpreter {
            path: crate::output::hpgl::PenPath {
                pen_up_at_end: true,
                ..Default::default()
            },
            tool: 1,
        }
    }

    /// Where the tool is (steps, as sent) and which holder is selected.
    pub fn state(&self) -> ([i64; 2], u32) {
        (self.path.end, self.tool)
    }

    /// Executes one command (without its ETX). GP-GL commands have no replies.
    pub fn execute(&mut self, cmd: &str) -> Result<(), String> {
        let cmd = cmd.trim();
        if cmd.is_empty() {
            return Ok(());
        }
        let name = command_name(cmd);
        let numbers = || -> Result<Vec<i64>, String> {
            cmd[name.len()..]
                .split(',')
                .map(str::trim)
                .filter(|s| !s.is_empty())
                .map(|s| s.parse::<i64>())
                .collect::<Result<_, _>>()
                .map_err(|_| format!("bad numbers in \"{cmd}\""))
        };
        match name {
            "M" | "D" => {
                let n = numbers()?;
                if n.is_empty() || !n.len().is_multiple_of(2) || (name == "M" && n.len() != 2) {
                    return Err(format!("wrong number of coordinates in \"{cmd}\""));
                }
                for p in n.chunks(2) {
                    let next = [p[0], p[1]];
                    if name == "D" && next != self.path.end {
                        self.path.segments.push((self.tool, self.path.end, next));
                    }
                    self.path.end = next;
                }
                self.path.pen_up_at_end = name == "M";
            }
            "J" => {
                self.tool = numbers()?
                    .first()
                    .copied()
                    .filter(|t| (0..=2).contains(t))
                    .ok_or_else(|| format!("bad tool holder in \"{cmd}\""))?
                    as u32
            }
            "H" => {
                self.path.end = [0, 0];
                self.path.pen_up_at_end = true;
            }
            "FN" | "\\" | "Z" | "!" | "FX" | "FC" | "FE" | "TB" | "SO" => {
                numbers()?;
            }
            _ => return Err(format!("unknown command \"{cmd}\"")),
        }
        Ok(())
    }
}

/// Interprets a whole GP-GL job (after its reset). Errors name the command.
pub fn interpret(job: &str) -> Result<crate::output::hpgl::PenPath, String> {
    let mut cutter = Interpreter::new();
    for cmd in job.trim_start_matches(RESET).split(ETX) {
        cutter.execute(cmd)?;
    }
    Ok(cutter.path)
}
