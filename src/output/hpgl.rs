//! HP-GL/1 for plotters and cutters: integers only, relative moves computed from rounded
//! absolute positions (so rounding never drifts), one tool selection per tool, pen up and
//! parked at the end. Every byte costs plot time on a 960 B/s line, so nothing is sent
//! twice. Also an interpreter of what we write, to read a job back.

pub use crate::fab::toolpath::ToolSetting;
use crate::fab::{LineKind, Stroke, Toolpath};
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// What the writer needs from a machine profile.
#[derive(Clone, Debug, PartialEq)]
pub struct HpglSettings {
    /// Plotter units per millimetre (40 for HP-GL).
    pub units_per_mm: f64,
    /// Tool per line kind.
    pub tools: BTreeMap<LineKind, ToolSetting>,
}

fn round(v: f64) -> i64 {
    v.round() as i64
}

/// Writes a toolpath. Strokes whose kind has no tool are an error.
pub fn to_string(path: &Toolpath, settings: &HpglSettings) -> Result<String, String> {
    let mut out = String::from("IN;PR;");
    let mut at = (0i64, 0i64);
    let mut tool: Option<LineKind> = None;
    let mut pen_down_open = false;
    // Pen, speed and force as last sent: each is sent when it changes, not at every change
    // of line kind (mountains and valleys on one pen share their settings).
    let mut current: (Option<u32>, Option<i64>, Option<i64>) = (None, None, None);
    let pos = |p: crate::mesh::Vec2| {
        (
            round(p.x * settings.units_per_mm),
            round(p.y * settings.units_per_mm),
        )
    };
    for s in &path.strokes {
        if tool != Some(s.kind) {
            let t = settings
                .tools
                .get(&s.kind)
                .ok_or_else(|| format!("the machine has no tool for {} lines", s.kind.name()))?;
            if pen_down_open {
                out.push(';');
                pen_down_open = false;
            }
            if current.0 != Some(t.pen) {
                let _ = write!(out, "SP{};", t.pen);
                current.0 = Some(t.pen);
            }
            if let Some(v) = t.speed.map(|v| round(v / 10.0).max(1)) {
                if current.1 != Some(v) {
                    let _ = write!(out, "VS{v};");
                    current.1 = Some(v);
                }
            }
            if let Some(f) = t.force.map(|f| round(f).max(1)) {
                if current.2 != Some(f) {
                    let _ = write!(out, "FS{f};");
                    current.2 = Some(f);
                }
            }
            tool = Some(s.kind);
        }
        // A bent stroke goes as its chords (HP-GL/1 has arcs only of circles).
        let points: Vec<_> = s.polyline().into_iter().map(pos).collect();
        let from = points[0];
        if from != at {
            if pen_down_open {
                out.push(';');
                pen_down_open = false;
            }
            let _ = write!(out, "PU{},{};", from.0 - at.0, from.1 - at.1);
        }
        at = from;
        for &to in &points[1..] {
            if to == at {
                continue; // shorter than a plotter unit
            }
            if pen_down_open {
                let _ = write!(out, ",{},{}", to.0 - at.0, to.1 - at.1);
            } else {
                let _ = write!(out, "PD{},{}", to.0 - at.0, to.1 - at.1);
                pen_down_open = true;
            }
            at = to;
        }
    }
    if pen_down_open {
        out.push(';');
    }
    // Pen up, back to the origin, tool put away.
    let _ = write!(out, "PU{},{};SP0;", -at.0, -at.1);
    Ok(out)
}

/// What a plotter draws when it runs an HP-GL job: pen-down segments in plotter units.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PenPath {
    /// (pen, from, to) for every pen-down move.
    pub segments: Vec<(u32, [i64; 2], [i64; 2])>,
    /// Where the pen ended.
    pub end: [i64; 2],
    /// Whether the pen ended up.
    pub pen_up_at_end: bool,
}

/// The state of a plotter executing HP-GL/1 one command at a time: IN, SP, PU, PD, PA, PR
/// move the pen; OA, OI, OS answer; VS, FS and others are accepted and ignored.
#[derive(Clone, Debug, Default)]
pub struct Interpreter {
    /// Everything drawn so far.
    pub path: PenPath,
    pen: u32,
    down: bool,
    relative: bool,
}

impl Interpreter {
    /// A plotter just switched on.
    pub fn new() -> Interpreter {
        Interpreter {
            path: PenPath {
                pen_up_at_end: true,
                ..Default::default()
            },
            ..Default::default()
        }
    }

    /// Current pen position (plotter units), pen number and whether it is down.
    pub fn state(&self) -> ([i64; 2], u32, bool) {
        (self.path.end, self.pen, self.down)
    }

    /// Executes one command (without its `;`). Returns the reply of an output command.
    pub fn execute(&mut self, cmd: &str) -> Result<Option<String>, String> {
        let cmd = cmd.trim();
        if cmd.is_empty() {
            return Ok(None);
        }
        if cmd.len() < 2 || !cmd.is_char_boundary(2) {
            return Err(format!("bad command \"{cmd}\""));
        }
        let (name, args) = cmd.split_at(2);
        let numbers: Vec<i64> = args
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(|s| s.parse::<f64>().map(|v| v.round() as i64))
            .collect::<Result<_, _>>()
            .map_err(|_| format!("bad numbers in \"{cmd}\""))?;
        let at = &mut self.path.end;
        match name.to_ascii_uppercase().as_str() {
            "IN" => {
                *at = [0, 0];
                self.down = false;
                self.relative = false;
                self.pen = 0;
            }
            "SP" => self.pen = numbers.first().copied().unwrap_or(0) as u32,
            "PA" | "PR" => {
                self.relative = name.eq_ignore_ascii_case("PR");
                return self.moves(&numbers, cmd).map(|_| None);
            }
            "PU" | "PD" => {
                self.down = name.eq_ignore_ascii_case("PD");
                return self.moves(&numbers, cmd).map(|_| None);
            }
            "OA" => {
                return Ok(Some(format!(
                    "{},{},{}\r",
                    at[0],
                    at[1],
                    u8::from(self.down)
                )))
            }
            "OI" => return Ok(Some("7475A\r".into())),
            "OS" => return Ok(Some(format!("{}\r", if self.down { 1 } else { 0 } + 8))),
            _ => {}
        }
        self.path.pen_up_at_end = !self.down;
        Ok(None)
    }

    fn moves(&mut self, numbers: &[i64], cmd: &str) -> Result<(), String> {
        if !numbers.len().is_multiple_of(2) {
            return Err(format!("odd number of coordinates in \"{cmd}\""));
        }
        for xy in numbers.chunks(2) {
            let at = self.path.end;
            let next = if self.relative {
                [at[0] + xy[0], at[1] + xy[1]]
            } else {
                [xy[0], xy[1]]
            };
            if self.down && next != at {
                self.path.segments.push((self.pen, at, next));
            }
            self.path.end = next;
        }
        self.path.pen_up_at_end = !self.down;
        Ok(())
    }
}

/// Interprets a whole job. Errors name the command.
pub fn interpret(job: &str) -> Result<PenPath, String> {
    let mut plotter = Interpreter::new();
    for cmd in job.split(';') {
        plotter.execute(cmd)?;
    }
    Ok(plotter.path)
}

/// The pen-down segments a toolpath should produce, in plotter units, for comparison.
pub fn expected_segments(
    path: &Toolpath,
    settings: &HpglSettings,
) -> Vec<(u32, [i64; 2], [i64; 2])> {
    let pos = |p: crate::mesh::Vec2| {
        [
            round(p.x * settings.units_per_mm),
            round(p.y * settings.units_per_mm),
        ]
    };
    path.strokes
        .iter()
        .flat_map(|s: &Stroke| {
            let pen = settings.tools[&s.kind].pen;
            let points: Vec<[i64; 2]> = s.polyline().into_iter().map(pos).collect();
            let segments: Vec<_> = points
                .windows(2)
                .filter(|w| w[0] != w[1])
                .map(|w| (pen, w[0], w[1]))
                .collect();
            segments
        })
        .collect()
}
