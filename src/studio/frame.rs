//! What the page draws, as JSON in three parts that change at different rates: the
//! topology (faces and creases: on load, remesh, undo), the pattern (crease pattern and
//! x-ray: while design mode changes lengths, a few times a second), and the live part
//! (positions and numbers: every solver step). A long-poll sends only the parts the page
//! does not have yet.

use crate::constraints::{Element, Family};
use crate::fab::{flat_folded, LineKind, Report};
use crate::mesh::{Mesh, Vec2, Vec3};
use crate::solver::Mode;
use serde_json::{json, Value};
use std::collections::{BTreeSet, VecDeque};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Version counters of the session's parts.
#[derive(Clone, Debug, Default)]
pub struct Versions {
    /// Every published frame.
    pub frame: u64,
    /// Faces and creases.
    pub topology: u64,
    /// Crease pattern and x-ray.
    pub pattern: u64,
    /// Positions.
    pub positions: u64,
}

impl Versions {
    /// The next frame number.
    pub fn next_frame(&mut self) -> u64 {
        self.frame += 1;
        self.frame
    }
}

/// A published frame.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Increases with every publication.
    pub version: u64,
    /// Version of `topology`.
    pub topology_version: u64,
    /// Version of `pattern`.
    pub pattern_version: u64,
    /// `{"faces": [...], "edges": [[a, b, kind], ...]}`.
    pub topology: Arc<String>,
    /// `{"creasePattern": [...], "xray": {...} | {"reason": ...}}`.
    pub pattern: Arc<String>,
    /// Positions and numbers.
    pub live: String,
    /// Solver steps per second shown in `live`.
    pub steps_per_second: f64,
}

impl Frame {
    /// The JSON a page gets, leaving out the parts whose versions it already has, with
    /// the session's `instance` (the page sends it back; another means start again).
    pub fn to_json_for(
        &self,
        topology: Option<u64>,
        pattern: Option<u64>,
        instance: u64,
    ) -> String {
        let mut out = format!(
            "{{\"instance\":{instance},\"version\":{},\"topologyVersion\":{},\"patternVersion\":{},\"live\":{}",
            self.version, self.topology_version, self.pattern_version, self.live
        );
        if topology != Some(self.topology_version) {
            out.push_str(",\"topology\":");
            out.push_str(&self.topology);
        }
        if pattern != Some(self.pattern_version) {
            out.push_str(",\"pattern\":");
            out.push_str(&self.pattern);
        }
        out.push('}');
        out
    }
}

/// Solver steps per second over the last second.
#[derive(Default)]
pub struct Meter {
    ticks: VecDeque<Instant>,
}

impl Meter {
    /// Counts a step.
    pub fn tick(&mut self) {
        let now = Instant::now();
        self.ticks.push_back(now);
        while self
            .ticks
            .front()
            .is_some_and(|t| now.duration_since(*t) > Duration::from_secs(1))
        {
            self.ticks.pop_front();
        }
    }

    /// Steps in the last second (0 when idle for a second).
    pub fn rate(&self) -> f64 {
        match self.ticks.back() {
            Some(t) if t.elapsed() <= Duration::from_secs(1) => self.ticks.len() as f64,
            _ => 0.0,
        }
    }
}

/// A crease's kind as the page colours it.
fn kind_name(kind: LineKind) -> &'static str {
    match kind {
        LineKind::Mountain => "M",
        LineKind::Valley => "V",
        LineKind::Cut => "B",
        _ => "F",
    }
}

/// Faces and creases.
pub fn topology_json(mesh: &Mesh) -> String {
    topology_value(mesh).to_string()
}

fn topology_value(mesh: &Mesh) -> Value {
    let faces: Vec<usize> = mesh.faces().iter().flatten().copied().collect();
    let edges: Vec<Value> = mesh
        .edges()
        .iter()
        .zip(LineKind::of_mesh(mesh))
        .map(|(e, kind)| json!([e.vertices[0], e.vertices[1], kind_name(kind)]))
        .collect();
    json!({"vertices": mesh.vertex_count(), "faces": faces, "edges": edges, "title": mesh.title})
}

/// A tube's crease pattern: the strip it is cut open to (issue 31), with the strip's own
/// faces and creases, since its seam's vertices are there twice.
pub fn strip_pattern_json(strip: &Mesh) -> String {
    let mut value = pattern_value(strip, strip.crease_pattern());
    let topology = topology_value(strip);
    value["faces"] = topology["faces"].clone();
    value["edges"] = topology["edges"].clone();
    value.to_string()
}

/// The folding motion for the page to play: the sheet it moves (a tube's strip has its
/// own faces and creases), every frame's positions, and what the path found.
pub fn motion_value(motion: &crate::pipeline::Motion) -> Value {
    let mut value = topology_value(&motion.sheet);
    let frames: Vec<Vec<f64>> = motion
        .frames
        .iter()
        .map(|x| {
            x.iter()
                .flat_map(|p| [micro(p.x), micro(p.y), micro(p.z)])
                .collect()
        })
        .collect();
    value["frames"] = json!(frames);
    value["summary"] = json!(motion.summary());
    value["exitCode"] = json!(motion.exit_code());
    value["rigid"] = json!(motion.bending.is_rigid());
    value
}

/// Rounds to 1 µm: the page needs no more, and the numbers print shorter.
fn micro(x: f64) -> f64 {
    (x * 1e3).round() / 1e3
}

fn flat2(points: impl Iterator<Item = Vec2>) -> Vec<f64> {
    points.flat_map(|p| [micro(p.x), micro(p.y)]).collect()
}

/// The crease pattern and the flat-folded x-ray (or why there is none).
pub fn pattern_json(mesh: &Mesh, pattern: Option<&[Vec2]>) -> String {
    pattern_value(mesh, pattern).to_string()
}

fn pattern_value(mesh: &Mesh, pattern: Option<&[Vec2]>) -> Value {
    let cp = pattern.map(|p| flat2(p.iter().copied()));
    let xray = match pattern {
        None => json!({"reason": "the design cannot be unfolded into a crease pattern"}),
        Some(p) => match flat_folded(mesh, Some(p)) {
            // Where the layers close up (by verification's own tolerance, so the pane and
            // the verdict agree) every vertex has one image, and the page needs only
            // those (a sixth of the triangles' numbers); otherwise each face's own.
            Ok(f) if f.layers_close() => {
                let points = f.vertex_images(mesh.faces(), p.len());
                json!({
                    "points": flat2(points.into_iter()),
                    "flipped": f.motions.iter().map(|m| m.flips()).collect::<Vec<_>>(),
                    "mismatch": f.mismatch,
                    "worstVertex": f.worst_vertex,
                    "closes": true,
                })
            }
            Ok(f) => json!({
                "triangles": flat2(f.triangles.iter().flatten().copied()),
                "flipped": f.motions.iter().map(|m| m.flips()).collect::<Vec<_>>(),
                "mismatch": f.mismatch,
                "worstVertex": f.worst_vertex,
                "closes": false,
            }),
            Err(e) => json!({"reason": e.to_string()}),
        },
    };
    // Curved creases as the smooth curves fabrication scores: cubics from `start`, each
    // (c1, c2, end); the page draws them in place of their chords.
    let curves: Vec<Value> = pattern
        .map(|p| {
            crate::fab::smooth_creases(mesh, p)
                .iter()
                .map(|c| {
                    let start = c.curve.pieces()[0].p0;
                    json!({
                        "kind": kind_name(c.kind),
                        "edges": c.edges,
                        "start": [micro(start.x), micro(start.y)],
                        "pieces": flat2(c.curve.pieces().iter().flat_map(|q| [q.c1, q.c2, q.p3])),
                    })
                })
                .collect()
        })
        .unwrap_or_default();
    json!({"creasePattern": cp, "xray": xray, "curves": curves})
}

/// The parts of the live frame.
pub struct Live<'a> {
    /// Positions.
    pub positions: &'a [Vec3],
    /// Pinned vertices.
    pub pinned: &'a BTreeSet<usize>,
    /// Vertices held by the solver.
    pub anchor: &'a [usize],
    /// Mode.
    pub mode: Mode,
    /// The latest verification.
    pub report: Option<&'a Report>,
    /// The dragged vertex.
    pub dragging: Option<usize>,
    /// Status line.
    pub message: &'a str,
    /// Why the last step was blocked.
    pub blocked: Option<&'a str>,
    /// Solver steps per second.
    pub steps_per_second: f64,
    /// Undo depth.
    pub undo: usize,
    /// Redo depth.
    pub redo: usize,
    /// Conditions in force.
    pub conditions: &'a [Family],
    /// Whether the user chose the conditions.
    pub custom_conditions: bool,
    /// α.
    pub alpha: f64,
    /// Remesh threshold.
    pub remesh: Option<f64>,
    /// Design title.
    pub title: &'a str,
    /// The target surface's name, version and placement (null without one).
    pub target: Value,
    /// The fit's progress (null without one).
    pub fit: Value,
}

/// The element to highlight: a vertex, or an edge (an index into the topology's edges).
fn element_json(element: Element) -> Value {
    match element {
        Element::Vertex(v) | Element::Sector(v, _, _, _) => json!({"vertex": v}),
        Element::Edge(e) => json!({"edge": e}),
        Element::Faces(a, b) => json!({"faces": [a, b]}),
    }
}

#[derive(serde::Serialize)]
#[serde(rename_all = "camelCase")]
struct LiveOut<'a> {
    positions: Vec<f64>,
    pinned: &'a BTreeSet<usize>,
    anchor: &'a [usize],
    mode: &'static str,
    residuals: Value,
    pass: Option<bool>,
    /// The report's verdict: PASS, FAIL or UNDECIDED ([`crate::fab::Verdict`]).
    verdict: Option<&'static str>,
    worst: Option<Value>,
    dragging: Option<usize>,
    message: &'a str,
    blocked: Option<&'a str>,
    steps_per_second: f64,
    vertices: usize,
    undo: usize,
    redo: usize,
    conditions: Vec<&'static str>,
    custom_conditions: bool,
    alpha: f64,
    remesh: Option<f64>,
    title: &'a str,
    target: &'a Value,
    fit: &'a Value,
}

/// Positions and numbers, serialised directly (no JSON tree of the positions).
pub fn live_json(l: &Live) -> String {
    let positions: Vec<f64> = l
        .positions
        .iter()
        .flat_map(|p| [micro(p.x), micro(p.y), micro(p.z)])
        .collect();
    let (residuals, pass, verdict, worst) = match l.report {
        Some(r) => {
            let families: Vec<Value> = r
                .families
                .iter()
                .map(|f| {
                    // A finding without a size (faces that admit no order) has no figure.
                    json!({"name": f.name, "max": f.figure(), "tolerance": f.tolerance,
                           "pass": f.pass(), "judged": f.gating, "worst": f.worst})
                })
                .collect();
            let worst = r.worst_family().map(|(f, e)| {
                json!({"family": f.name, "element": element_json(e),
                       "max": f.figure(), "pass": f.pass()})
            });
            let verdict = r.verdict();
            (
                Value::Array(families),
                Some(verdict.is_pass()),
                Some(verdict.word()),
                worst,
            )
        }
        None => (Value::Array(vec![]), None, None, None),
    };
    serde_json::to_string(&LiveOut {
        positions,
        pinned: l.pinned,
        anchor: l.anchor,
        mode: l.mode.name(),
        residuals,
        pass,
        verdict,
        worst,
        dragging: l.dragging,
        message: l.message,
        blocked: l.blocked,
        steps_per_second: l.steps_per_second,
        vertices: l.positions.len(),
        undo: l.undo,
        redo: l.redo,
        conditions: l.conditions.iter().map(|f| f.name()).collect(),
        custom_conditions: l.custom_conditions,
        alpha: l.alpha,
        remesh: l.remesh,
        title: l.title,
        target: &l.target,
        fit: &l.fit,
    })
    .expect("the live frame serialises")
}
