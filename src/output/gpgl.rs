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
}

/// Writes a toolpath as GP-GL. The cutter's origin is the media's top-left corner, its
/// carriage axis the sheet's x and its feed axis runs down the sheet (the toolpath's y
/// grows upward, so feed = height − y); strokes whose kind has no tool are an error.
pub fn to_string(path: &Toolpath, settings: &GpglSettings) -> Result<String, String> {
    let u = settings.units_per_mm;
    let order = |(x, y): (i64, i64)| if settings.feed_first { (y, x) } else { (x, y) };
    let h = path.media.height;
    let down = |p: crate::mesh::Vec2| crate::mesh::Vec2::new(p.x, h - p.y);
    let point = |p: crate::mesh::Vec2| order(((p.x * u).round() as i64, (p.y * u).round() as i64));
    let mut out = String::from(RESET);
    let command = |out: &mut String, text: &str| {
        out.push_str(text);
        out.push(ETX);
    };
    command(&mut out, "FN0");
    let (limit_a, limit_b) = point(crate::mesh::Vec2::new(path.media.width, path.media.height));
    command(&mut out, "\\0,0");
    command(&mut out, &format!("Z{limit_a},{limit_b}"));
    // `at` in (x, y) steps, the order the sheet has; `order` turns it into the cutter's.
    let mut at = (0i64, 0i64);
    let mut tool: Option<LineKind> = None;
    for (kind, points) in runs_in_cutting_order(path) {
        if tool != Some(kind) {
            let t = settings
                .tools
                .get(&kind)
                .ok_or_else(|| format!("the machine has no tool for {} lines", kind.name()))?;
            command(&mut out, &format!("J{}", t.pen));
            if let Some(v) = t.speed {
                command(
                    &mut out,
                    &format!("!{}", (v / 10.0).round().clamp(1.0, 30.0) as i64),
                );
            }
            if let Some(f) = t.force {
                command(
                    &mut out,
                    &format!("FX{}", f.round().clamp(1.0, 33.0) as i64),
                );
            }
            let offset = (settings.blade_offset_mm * 20.0).round() as i64;
            command(&mut out, &format!("FC{offset}"));
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

/// The toolpath as runs of joined strokes of one kind, (kind, points), in the toolpath's
/// cutting order: only strokes that follow each other join, so the job cuts as routed.
fn runs_in_cutting_order(path: &Toolpath) -> Vec<(LineKind, Vec<crate::mesh::Vec2>)> {
    let mut runs: Vec<(LineKind, Vec<crate::mesh::Vec2>)> = Vec::new();
    for s in &path.strokes {
        match runs.last_mut() {
            Some((kind, points))
                if *kind == s.kind && (points[points.len() - 1] - s.from).norm() < 1e-9 =>
            {
                points.push(s.to)
            }
            _ => runs.push((s.kind, vec![s.from, s.to])),
        }
    }
    runs
}

/// Snaps a run of points (in steps) to the step grid: each point to one of the four grid
/// corners around it (so no point moves a step or more), chosen by dynamic programming so
/// the largest error in any segment's length is smallest (then the points nearest). A
/// dash is then as long as its code says to within a step, where rounding each end to its
/// nearest step would allow √2 of one.
fn snap_chain(points: &[(f64, f64)]) -> Vec<(i64, i64)> {
    let corners = |p: (f64, f64)| {
        let (x0, x1) = (p.0.floor() as i64, p.0.ceil() as i64);
        let (y0, y1) = (p.1.floor() as i64, p.1.ceil() as i64);
        [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
    };
    let offset = |c: (i64, i64), p: (f64, f64)| (c.0 as f64 - p.0).hypot(c.1 as f64 - p.1);
    // cost[k] = (largest length error so far, summed offsets) ending on corner k.
    let first = corners(points[0]);
    let mut cost: Vec<(f64, f64)> = first.iter().map(|&c| (0.0, offset(c, points[0]))).collect();
    let mut back: Vec<[usize; 4]> = Vec::with_capacity(points.len());
    let mut previous = first;
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let want = (b.0 - a.0).hypot(b.1 - a.1);
        let here = corners(b);
        let mut next = [(f64::INFINITY, f64::INFINITY); 4];
        let mut from = [0usize; 4];
        for (k, &c) in here.iter().enumerate() {
            for (j, &p) in previous.iter().enumerate() {
                let got = ((c.0 - p.0) as f64).hypot((c.1 - p.1) as f64);
                let candidate = (cost[j].0.max((got - want).abs()), cost[j].1 + offset(c, b));
                if candidate.0 < next[k].0 - 1e-12
                    || (candidate.0 <= next[k].0 + 1e-12 && candidate.1 < next[k].1)
                {
                    next[k] = candidate;
                    from[k] = j;
                }
            }
        }
        back.push(from);
        cost = next.to_vec();
        previous = here;
    }
    let mut k = (0..4)
        .min_by(|&i, &j| {
            (cost[i].0, cost[i].1)
                .partial_cmp(&(cost[j].0, cost[j].1))
                .expect("finite costs")
        })
        .expect("four corners");
    let mut snapped = vec![(0, 0); points.len()];
    for i in (0..points.len()).rev() {
        snapped[i] = corners(points[i])[k];
        if i > 0 {
            k = back[i - 1][k];
        }
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
