//! The studio's session: the design being varied, its solver, the user's pins and
//! settings, and the undo history. One thread owns it (see [`super::hub`]); requests
//! reach it as [`Command`]s and every change is published as a [`Frame`].
//!
//! It turns requests into library calls and holds no geometry of its own: dragging is the
//! solver's null-space step and Newton correction (§3), the crease pattern is
//! [`crate::fab::unfold`], the x-ray is [`crate::fab::flat_folded`], the verdict is
//! [`crate::fab::verify`], saving is [`crate::pipeline::finish_design`] as `deform` does.

use super::frame::{self, Frame, Meter};
use crate::constraints::{ConstraintSet, Family, Reference};
use crate::fab::{self, Report, Tolerances};
use crate::generate::{self, Params, PatternKind};
use crate::mesh::{Mesh, Vec2, Vec3};
use crate::pipeline::{self, FabError, FabOptions};
use crate::solver::{fold_toward, pull, Mode, Options, Solver};
use serde::Deserialize;
use std::collections::BTreeSet;
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A request to the session, already parsed from JSON.
#[derive(Debug)]
pub enum Command {
    /// The full state (`GET /api/state`).
    State,
    /// Pull `vertex` toward `target` (mm, 3D frame) until released.
    Drag {
        /// The vertex.
        vertex: usize,
        /// Where the pointer is.
        target: [f64; 3],
    },
    /// End the drag.
    Release,
    /// Pin or unpin a vertex.
    Pin {
        /// The vertex.
        vertex: usize,
        /// Pinned afterwards.
        pinned: bool,
    },
    /// Undo the last change.
    Undo,
    /// Redo the last undone change.
    Redo,
    /// Change mode, conditions, α or remeshing.
    Settings(Settings),
    /// Fold toward a fraction of every crease's target (simulation mode).
    Fold {
        /// The fraction, in [0, 1].
        amount: f64,
    },
    /// Start from a generated pattern.
    Generate(GenerateRequest),
    /// Start from a file's bytes.
    Open {
        /// Its name (the extension picks the format).
        name: String,
        /// Its content.
        bytes: Vec<u8>,
    },
    /// The design as the FOLD file `deform` writes.
    SaveFold,
    /// Run `fab` on the design.
    Fabricate(FabRequest),
    /// A file of the last fabrication.
    FabFile(String),
}

/// Settings a request may change; absent fields stay.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// "design" or "simulation".
    pub mode: Option<String>,
    /// Condition families held in design mode; empty means the design's default set.
    pub conditions: Option<Vec<String>>,
    /// Twist allowance α of facet lines, [0, 1).
    pub alpha: Option<f64>,
    /// Remeshing threshold (fraction of the mean edge), or `null`/absent to leave it.
    pub remesh: Option<f64>,
    /// Turn remeshing off.
    pub remesh_off: Option<bool>,
}

/// A generated starting pattern.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GenerateRequest {
    /// miura, waterbomb, yoshimura, resch, plane, curved.
    pub pattern: String,
    /// Cells across.
    pub nx: Option<usize>,
    /// Cells along.
    pub ny: Option<usize>,
    /// Cell size (mm).
    pub size: Option<f64>,
    /// Miura angle (degrees).
    pub angle: Option<f64>,
    /// Closed-form fold amount, or none for flat.
    pub fold: Option<f64>,
}

/// A fabrication request.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FabRequest {
    /// Machine profile name.
    pub machine: String,
    /// Media (a4, a3, letter, WxHmm); default the machine's.
    pub media: Option<String>,
    /// Scale to this width (mm).
    pub width: Option<f64>,
    /// Fabricate even if verification fails.
    pub force: Option<bool>,
}

/// What a request produced.
#[derive(Debug)]
pub enum Reply {
    /// JSON.
    Json(serde_json::Value),
    /// A file to download.
    File {
        /// File name.
        name: String,
        /// Bytes.
        bytes: Vec<u8>,
    },
}

/// Why a request was refused: an HTTP status (4xx) and a one-line message.
#[derive(Debug, Clone, PartialEq)]
pub struct Refusal {
    /// 400 bad request, 404 unknown, 409 conflicts with the state, 422 cannot be done.
    pub status: u16,
    /// What is wrong and what to do.
    pub message: String,
}

impl Refusal {
    fn bad(message: impl Into<String>) -> Refusal {
        Refusal {
            status: 400,
            message: message.into(),
        }
    }
    fn conflict(message: impl Into<String>) -> Refusal {
        Refusal {
            status: 409,
            message: message.into(),
        }
    }
    fn failed(message: impl Into<String>) -> Refusal {
        Refusal {
            status: 422,
            message: message.into(),
        }
    }
}

/// Largest grid a request may generate (cells per side): 200 × 200 cells is over 40k
/// vertices, already past interactive speed.
const MAX_CELLS: usize = 200;
/// Largest file the studio opens.
pub const MAX_UPLOAD: usize = 64 << 20;
/// Minimum time between verifications during a drag; the verdict at rest is always fresh.
const VERIFY_EVERY: Duration = Duration::from_millis(150);
/// Minimum time between crease-pattern rebuilds during a design-mode drag.
const RELAY_EVERY: Duration = Duration::from_millis(200);

#[derive(Clone)]
struct Snapshot {
    mesh: Mesh,
    pinned: BTreeSet<usize>,
    mode: Mode,
    conditions: Option<Vec<Family>>,
    alpha: f64,
    remesh: Option<f64>,
    relaid: bool,
}

struct DragState {
    vertex: usize,
    target: Vec3,
    /// The solver cannot go on toward this target (a step failed, or no progress).
    stuck: bool,
    moved: bool,
}

/// The studio's design session.
pub struct Session {
    mesh: Mesh,
    title: String,
    pinned: BTreeSet<usize>,
    mode: Mode,
    conditions: Option<Vec<Family>>,
    alpha: f64,
    remesh: Option<f64>,
    /// Design mode changed lengths since the pattern was loaded: saving unfolds anew.
    relaid: bool,
    solver: Option<Solver>,
    anchor: Vec<usize>,
    drag: Option<DragState>,
    history: Vec<Snapshot>,
    future: Vec<Snapshot>,
    message: String,
    blocked: Option<String>,
    report: Option<Report>,
    verified_at: Option<Instant>,
    pattern: Option<Vec<Vec2>>,
    relaid_at: Option<Instant>,
    versions: frame::Versions,
    meter: Meter,
    fab_files: Vec<(String, Vec<u8>)>,
}

impl Session {
    /// A session around a design.
    pub fn new(mesh: Mesh, title: &str) -> Session {
        let mut s = Session {
            mesh,
            title: title.to_string(),
            pinned: BTreeSet::new(),
            mode: Mode::Design,
            conditions: None,
            alpha: 0.0,
            remesh: None,
            relaid: false,
            solver: None,
            anchor: Vec::new(),
            drag: None,
            history: Vec::new(),
            future: Vec::new(),
            message: "ready: drag a vertex; Shift-click pins it".into(),
            blocked: None,
            report: None,
            verified_at: None,
            pattern: None,
            relaid_at: None,
            versions: frame::Versions::default(),
            meter: Meter::default(),
            fab_files: Vec::new(),
        };
        s.alpha = s.mesh_alpha();
        s.design_changed(true);
        s
    }

    /// The starting design without a file: the bundled Miura-ori at half fold.
    pub fn default_design() -> Mesh {
        generate::generate(&Params::defaults(PatternKind::Miura))
            .expect("the default Miura-ori parameters are valid")
    }

    fn mesh_alpha(&self) -> f64 {
        self.mesh
            .edges()
            .iter()
            .filter(|e| e.target == 0.0)
            .map(|e| e.alpha)
            .fold(0.0, f64::max)
    }

    /// Solver steps in the last second.
    pub fn steps_per_second(&self) -> f64 {
        self.meter.rate()
    }

    /// Whether the session has work to do without a request: a drag that can go on.
    pub fn wants_to_step(&self) -> bool {
        self.drag.as_ref().is_some_and(|d| !d.stuck)
    }

    /// The design as it stands (the solver's positions during a drag).
    pub fn current(&self) -> Mesh {
        match &self.solver {
            Some(s) => {
                let mut m = s.mesh().clone();
                m.set_positions(s.positions().to_vec());
                m
            }
            None => self.mesh.clone(),
        }
    }

    fn positions(&self) -> &[Vec3] {
        match &self.solver {
            Some(s) => s.positions(),
            None => self.mesh.positions(),
        }
    }

    /// Moves the solver's state into `mesh` and drops the solver (settings or anchor change).
    fn settle(&mut self) {
        if let Some(s) = self.solver.take() {
            self.mesh = s.into_mesh();
        }
    }

    fn snapshot(&self) -> Snapshot {
        Snapshot {
            mesh: self.current(),
            pinned: self.pinned.clone(),
            mode: self.mode,
            conditions: self.conditions.clone(),
            alpha: self.alpha,
            remesh: self.remesh,
            relaid: self.relaid,
        }
    }

    fn restore(&mut self, s: Snapshot) {
        self.solver = None;
        self.drag = None;
        self.mesh = s.mesh;
        self.pinned = s.pinned;
        self.mode = s.mode;
        self.conditions = s.conditions;
        self.alpha = s.alpha;
        self.remesh = s.remesh;
        self.relaid = s.relaid;
        self.blocked = None;
        self.design_changed(true);
    }

    /// Records the state before a change, for undo.
    fn remember(&mut self) {
        let snap = self.snapshot();
        self.history.push(snap);
        self.future.clear();
        // Each snapshot holds a whole mesh; a long session keeps the last hundred.
        if self.history.len() > 100 {
            self.history.remove(0);
        }
    }

    fn design_changed(&mut self, topology: bool) {
        self.versions.positions += 1;
        self.versions.pattern += 1;
        if topology {
            self.versions.topology += 1;
            self.pattern = None;
        }
        self.report = None;
        self.fab_files.clear();
    }

    fn condition_set(&self, mesh: &Mesh) -> ConstraintSet {
        match (self.mode, &self.conditions) {
            (Mode::Simulation, _) => Mode::simulation_set(),
            (Mode::Design, Some(f)) if !f.is_empty() => ConstraintSet {
                families: f.clone(),
            },
            (Mode::Design, _) => ConstraintSet::default_for(&Reference::new(mesh)),
        }
    }

    /// The anchor for dragging `vertex`: the pins, plus the face farthest from the dragged
    /// vertex while fewer than three are pinned (fewer cannot hold the rigid motions).
    fn anchor_for(&self, vertex: usize) -> Vec<usize> {
        let mut anchor: BTreeSet<usize> = self.pinned.clone();
        if anchor.len() < 3 {
            let avoid: Vec<usize> = std::iter::once(vertex).collect();
            anchor.extend(Solver::default_fixed(&self.mesh, &avoid));
        }
        anchor.remove(&vertex);
        anchor.into_iter().collect()
    }

    fn ensure_solver(&mut self, vertex: usize) -> Result<(), String> {
        let anchor = self.anchor_for(vertex);
        if self.solver.is_some() && anchor == self.anchor {
            return Ok(());
        }
        self.settle();
        let set = self.condition_set(&self.mesh);
        let mut solver = Solver::new(self.mesh.clone(), set, &anchor, Options::default())
            .map_err(|e| e.to_string())?;
        solver.correct().map_err(|e| {
            format!("the design does not hold the chosen conditions, so it cannot be dragged: {e}")
        })?;
        self.anchor = anchor;
        self.solver = Some(solver);
        Ok(())
    }

    /// Handles one request; the caller publishes [`Session::frame`] afterwards.
    pub fn handle(&mut self, command: Command) -> Result<Reply, Refusal> {
        match command {
            Command::State => Ok(Reply::Json(self.state_json())),
            Command::Drag { vertex, target } => self.drag(vertex, target),
            Command::Release => {
                self.release();
                Ok(ok())
            }
            Command::Pin { vertex, pinned } => self.pin(vertex, pinned),
            Command::Undo => self.undo(true),
            Command::Redo => self.undo(false),
            Command::Settings(s) => self.settings(s),
            Command::Fold { amount } => self.fold(amount),
            Command::Generate(g) => self.generate(g),
            Command::Open { name, bytes } => self.open(&name, bytes),
            Command::SaveFold => {
                let mesh = self.finished()?;
                Ok(Reply::File {
                    name: format!("{}.fold", file_stem(&self.title)),
                    bytes: crate::io::fold::to_string(&mesh).into_bytes(),
                })
            }
            Command::Fabricate(r) => self.fabricate(r),
            Command::FabFile(name) => self
                .fab_files
                .iter()
                .find(|(n, _)| *n == name)
                .map(|(n, b)| Reply::File {
                    name: n.clone(),
                    bytes: b.clone(),
                })
                .ok_or_else(|| Refusal {
                    status: 404,
                    message: format!(
                        "no fabricated file \"{name}\": press Fabricate first (files: {})",
                        self.fab_files
                            .iter()
                            .map(|(n, _)| n.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                }),
        }
    }

    fn check_vertex(&self, vertex: usize) -> Result<(), Refusal> {
        let n = self.positions().len();
        if vertex >= n {
            return Err(Refusal {
                status: 404,
                message: format!("vertex {vertex} does not exist (the design has {n} vertices)"),
            });
        }
        Ok(())
    }

    fn drag(&mut self, vertex: usize, target: [f64; 3]) -> Result<Reply, Refusal> {
        self.check_vertex(vertex)?;
        let t = Vec3::new(target[0], target[1], target[2]);
        if !t.iter().all(|c| c.is_finite()) {
            return Err(Refusal::bad("the drag target is not a finite point"));
        }
        let (lo, hi) = self.mesh.bounding_box();
        let size = (hi - lo).norm().max(1.0);
        if (t - self.positions()[vertex]).norm() > 10.0 * size {
            return Err(Refusal::bad(format!(
                "the drag target is {:.0} mm away, more than ten times the design's size",
                (t - self.positions()[vertex]).norm()
            )));
        }
        if self.pinned.contains(&vertex) {
            return Err(Refusal::conflict(format!(
                "vertex {vertex} is pinned: Shift-click it to unpin it before dragging"
            )));
        }
        match &mut self.drag {
            Some(d) if d.vertex == vertex => {
                d.target = t;
                d.stuck = false;
            }
            _ => {
                self.release();
                self.remember();
                if let Err(m) = self.ensure_solver(vertex) {
                    self.history.pop();
                    self.blocked = Some(m.clone());
                    self.message = m.clone();
                    return Err(Refusal::failed(m));
                }
                self.blocked = None;
                self.drag = Some(DragState {
                    vertex,
                    target: t,
                    stuck: false,
                    moved: false,
                });
                self.message = format!("dragging vertex {vertex}");
            }
        }
        Ok(ok())
    }

    fn release(&mut self) {
        if let Some(d) = self.drag.take() {
            if !d.moved {
                self.history.pop();
            }
            if self.blocked.is_none() {
                self.message = format!("released vertex {}", d.vertex);
            }
            self.report = None;
            self.versions.positions += 1;
        }
    }

    /// One Euler step of the drag (§3, §5): pull the dragged vertex a bounded share of its
    /// way to the pointer, project into the null space, correct with Newton.
    pub fn step(&mut self) {
        let Some(drag) = &self.drag else { return };
        let (v, target) = (drag.vertex, drag.target);
        let Some(solver) = self.solver.as_mut() else {
            return;
        };
        let x = solver.positions();
        let gap = target - x[v];
        let mean = mean_edge(solver.mesh(), x);
        if gap.norm() < 1e-3 * mean {
            self.drag.as_mut().expect("dragging").stuck = true;
            return;
        }
        // A step longer than half an edge leaves Newton's basin; the drag is integrated.
        let share = if gap.norm() > 0.5 * mean {
            gap * (0.5 * mean / gap.norm())
        } else {
            gap
        };
        let (lo, hi) = crate::mesh::bounds(x);
        let radius = 0.25 * (hi - lo).norm();
        let mut wish = vec![Vec3::zeros(); x.len()];
        pull(x, v, share, radius, &mut wish);
        let before = x[v];
        match solver.step(&wish) {
            Ok(_) => {
                let progress = (solver.positions()[v] - before).dot(&share) / share.norm();
                self.meter.tick();
                let drag = self.drag.as_mut().expect("dragging");
                drag.moved = true;
                self.relaid |= self.mode == Mode::Design;
                self.versions.positions += 1;
                if progress < 1e-3 * share.norm() {
                    drag.stuck = true;
                    self.message = format!(
                        "vertex {v} cannot get closer: the conditions hold it (pin elsewhere or switch conditions off)"
                    );
                }
                self.remesh_after_step();
            }
            Err(e) => {
                self.drag.as_mut().expect("dragging").stuck = true;
                let m = format!("the step was blocked: {e}");
                self.message = m.clone();
                self.blocked = Some(m);
            }
        }
    }

    fn remesh_after_step(&mut self) {
        let (Some(threshold), Some(solver), Some(drag)) =
            (self.remesh, self.solver.as_mut(), self.drag.as_mut())
        else {
            return;
        };
        let outcome = solver.remesh(&[drag.vertex], threshold);
        if let Some(map) = outcome.renumbered {
            drag.vertex = map[drag.vertex];
            self.pinned = self.pinned.iter().map(|&p| map[p]).collect();
            self.anchor = self.anchor.iter().map(|&p| map[p]).collect();
        }
        if outcome.collapses + outcome.flips > 0 {
            self.message = format!(
                "remeshed: {} edge collapse(s), {} flip(s)",
                outcome.collapses, outcome.flips
            );
            self.versions.topology += 1;
            self.pattern = None;
        }
    }

    fn pin(&mut self, vertex: usize, pinned: bool) -> Result<Reply, Refusal> {
        self.check_vertex(vertex)?;
        if self.drag.as_ref().is_some_and(|d| d.vertex == vertex) {
            return Err(Refusal::conflict(format!(
                "vertex {vertex} is being dragged; release it first"
            )));
        }
        if self.pinned.contains(&vertex) != pinned {
            self.remember();
            if pinned {
                self.pinned.insert(vertex);
            } else {
                self.pinned.remove(&vertex);
            }
            self.versions.positions += 1;
        }
        self.message = format!(
            "vertex {vertex} {}",
            if pinned { "pinned" } else { "unpinned" }
        );
        Ok(ok())
    }

    fn undo(&mut self, back: bool) -> Result<Reply, Refusal> {
        self.release();
        let (from, word) = if back {
            (&mut self.history, "undo")
        } else {
            (&mut self.future, "redo")
        };
        let Some(s) = from.pop() else {
            return Err(Refusal::conflict(format!("nothing to {word}")));
        };
        let now = self.snapshot();
        if back {
            self.future.push(now);
        } else {
            self.history.push(now);
        }
        self.restore(s);
        self.message = format!("{word}: done");
        Ok(ok())
    }

    fn settings(&mut self, s: Settings) -> Result<Reply, Refusal> {
        let mode = s
            .mode
            .as_deref()
            .map(Mode::parse)
            .transpose()
            .map_err(Refusal::bad)?;
        let conditions = s
            .conditions
            .as_ref()
            .map(|list| {
                if list.is_empty() {
                    return Ok(Vec::new());
                }
                ConstraintSet::parse(&list.join(",")).map(|c| c.families)
            })
            .transpose()
            .map_err(Refusal::bad)?;
        if let Some(a) = s.alpha {
            if !(0.0..1.0).contains(&a) {
                return Err(Refusal::bad(format!("alpha must be in [0, 1) (got {a})")));
            }
        }
        if let Some(r) = s.remesh {
            if !(r > 0.0 && r < 1.0) {
                return Err(Refusal::bad(format!(
                    "the remesh threshold must be in (0, 1), a fraction of the mean edge (got {r})"
                )));
            }
        }
        self.release();
        self.remember();
        self.settle();
        if let Some(m) = mode {
            self.mode = m;
        }
        if let Some(c) = conditions {
            self.conditions = (!c.is_empty()).then_some(c);
        }
        if let Some(a) = s.alpha {
            pipeline::set_alpha(&mut self.mesh, a).map_err(|e| Refusal::bad(e.to_string()))?;
            self.alpha = a;
        }
        if s.remesh_off == Some(true) {
            self.remesh = None;
        } else if let Some(r) = s.remesh {
            self.remesh = Some(r);
        }
        self.blocked = None;
        self.report = None;
        self.versions.positions += 1;
        self.message = "settings changed".into();
        Ok(ok())
    }

    fn fold(&mut self, amount: f64) -> Result<Reply, Refusal> {
        if !(0.0..=1.0).contains(&amount) {
            return Err(Refusal::bad(format!(
                "the fold amount must be in [0, 1] (got {amount})"
            )));
        }
        if self.mode != Mode::Simulation {
            return Err(Refusal::conflict(
                "folding keeps every edge length: switch to simulation mode first",
            ));
        }
        self.release();
        self.settle();
        let centre = Solver::default_fixed(&self.mesh, &[]);
        let mut solver = Solver::new(
            self.mesh.clone(),
            Mode::folding_set(),
            &centre,
            Options::default(),
        )
        .map_err(|e| Refusal::failed(e.to_string()))?;
        let report = fold_toward(&mut solver, amount, 4000, &mut |_| {})
            .map_err(|e| Refusal::failed(format!("folding failed: {e}")))?;
        self.remember();
        self.mesh = solver.into_mesh();
        pipeline::record_fold_angles(&mut self.mesh);
        self.design_changed(false);
        self.message = format!(
            "folded to {:.0}% of the targets on average",
            100.0 * report.mean_fraction
        );
        Ok(Reply::Json(serde_json::json!({
            "ok": true, "steps": report.steps, "meanFraction": report.mean_fraction,
            "error": report.error
        })))
    }

    fn replace_design(&mut self, mesh: Mesh, title: String) {
        self.release();
        self.remember();
        self.solver = None;
        self.mesh = mesh;
        self.title = title;
        self.pinned.clear();
        self.relaid = false;
        self.blocked = None;
        self.alpha = self.mesh_alpha();
        self.design_changed(true);
    }

    fn generate(&mut self, g: GenerateRequest) -> Result<Reply, Refusal> {
        let kind = PatternKind::from_name(&g.pattern).ok_or_else(|| {
            let names: Vec<&str> = PatternKind::ALL.iter().map(|k| k.name()).collect();
            Refusal::bad(format!(
                "unknown pattern \"{}\" (choose one of: {})",
                g.pattern,
                names.join(", ")
            ))
        })?;
        let d = Params::defaults(kind);
        let p = Params {
            kind,
            nx: g.nx.unwrap_or(d.nx),
            ny: g.ny.unwrap_or(d.ny),
            size: g.size.unwrap_or(d.size),
            angle_deg: g.angle.unwrap_or(d.angle_deg),
            fold: g.fold.or(d.fold),
            alpha: d.alpha,
        };
        if p.nx > MAX_CELLS || p.ny > MAX_CELLS {
            return Err(Refusal::bad(format!(
                "at most {MAX_CELLS} cells a side (asked for {} × {})",
                p.nx, p.ny
            )));
        }
        let mesh = generate::generate(&p).map_err(|e| Refusal::bad(e.to_string()))?;
        let title = format!("{} {}x{}", kind.name(), p.nx, p.ny);
        self.replace_design(mesh, title);
        self.message = format!("generated {}", self.title);
        Ok(ok())
    }

    fn open(&mut self, name: &str, bytes: Vec<u8>) -> Result<Reply, Refusal> {
        let path = Path::new(name);
        let imported =
            crate::io::read_bytes(path, bytes).map_err(|e| Refusal::bad(e.to_string()))?;
        let stem = file_stem(name);
        self.replace_design(imported.mesh, stem);
        self.message = format!("opened {name}");
        Ok(Reply::Json(
            serde_json::json!({"ok": true, "notes": imported.notes}),
        ))
    }

    /// The design as `deform` writes it: residual polished to 1e-12, fold angles recorded,
    /// the crease pattern unfolded anew when design mode changed lengths.
    fn finished(&mut self) -> Result<Mesh, Refusal> {
        self.release();
        if let Some(s) = self.solver.as_mut() {
            s.polish(1e-12);
        }
        let mut mesh = self.current();
        pipeline::finish_design(&mut mesh, self.relaid)
            .map_err(|e| Refusal::failed(format!("the design cannot be unfolded: {e}")))?;
        mesh.title.clone_from(&self.title);
        Ok(mesh)
    }

    fn fabricate(&mut self, r: FabRequest) -> Result<Reply, Refusal> {
        let machine = crate::plotter::Machine::load(&r.machine)
            .map_err(|e| Refusal::bad(format!("machine: {e}")))?;
        let media = r
            .media
            .as_deref()
            .filter(|m| !m.trim().is_empty())
            .map(fab::Media::parse)
            .transpose()
            .map_err(|e| Refusal::bad(format!("media: {e}")))?;
        if let Some(w) = r.width {
            if !(w.is_finite() && w > 0.0) {
                return Err(Refusal::bad(format!(
                    "width must be a positive length in mm (got {w})"
                )));
            }
        }
        let mesh = self.finished()?;
        let options = FabOptions {
            media,
            width: r.width,
            force: r.force.unwrap_or(false),
            ..FabOptions::default()
        };
        match pipeline::fabricate(&mesh, &machine, &options) {
            Ok(out) => {
                let names: Vec<&str> = out.files.iter().map(|(n, _)| n.as_str()).collect();
                let reply = serde_json::json!({"ok": true, "files": names, "report": out.report});
                self.fab_files = out.files;
                self.message = format!("fabricated for {}", machine.name);
                Ok(Reply::Json(reply))
            }
            Err(FabError::Input(m)) => Err(Refusal::bad(m)),
            Err(FabError::Rejected(r)) => Err(Refusal::failed(format!(
                "{r} (tick \"cut anyway\" to fabricate regardless)"
            ))),
        }
    }

    fn refresh_report(&mut self, force: bool) {
        let due = self.verified_at.is_none_or(|t| t.elapsed() >= VERIFY_EVERY);
        if self.report.is_some() && !(force && due) {
            return;
        }
        let mut mesh = self.current();
        pipeline::record_fold_angles(&mut mesh);
        let set = self.condition_set(&mesh);
        self.report = Some(fab::verify(&mesh, Some(&set), Tolerances::default()));
        self.verified_at = Some(Instant::now());
    }

    fn refresh_pattern(&mut self) {
        let moving = self.wants_to_step();
        let due = self.relaid_at.is_none_or(|t| t.elapsed() >= RELAY_EVERY);
        let stale = self.pattern.is_none() || (self.relaid && self.pattern_stale());
        if !stale || (moving && !due && self.pattern.is_some()) {
            return;
        }
        let mesh = self.current();
        self.pattern = match (self.relaid, mesh.flat()) {
            (false, Some(f)) => Some(f.to_vec()),
            _ => fab::unfold(&mesh).ok(),
        };
        self.relaid_at = Some(Instant::now());
        self.versions.pattern_built = self.versions.positions;
        self.versions.pattern += 1;
    }

    fn pattern_stale(&self) -> bool {
        self.versions.pattern_built != self.versions.positions
    }

    /// The frame the page draws, rebuilt from what changed.
    pub fn frame(&mut self, previous: Option<&Frame>) -> Frame {
        let moving = self.wants_to_step();
        if self.report.is_none() || moving {
            self.refresh_report(moving);
        }
        self.refresh_pattern();
        let mesh_for_parts = (previous.is_none_or(|p| {
            p.topology_version != self.versions.topology
                || p.pattern_version != self.versions.pattern
        }))
        .then(|| self.current());
        let topology = match (previous, &mesh_for_parts) {
            (Some(p), _) if p.topology_version == self.versions.topology => p.topology.clone(),
            (_, Some(m)) => Arc::new(frame::topology_json(m)),
            (_, None) => unreachable!("a mesh is built when a part is stale"),
        };
        let pattern = match (previous, &mesh_for_parts) {
            (Some(p), _) if p.pattern_version == self.versions.pattern => p.pattern.clone(),
            (_, Some(m)) => Arc::new(frame::pattern_json(m, self.pattern.as_deref())),
            (_, None) => unreachable!("a mesh is built when a part is stale"),
        };
        Frame {
            version: self.versions.next_frame(),
            topology_version: self.versions.topology,
            pattern_version: self.versions.pattern,
            topology,
            pattern,
            steps_per_second: self.meter.rate(),
            live: frame::live_json(&frame::Live {
                positions: self.positions(),
                pinned: &self.pinned,
                anchor: &self.anchor,
                mode: self.mode,
                report: self.report.as_ref(),
                dragging: self.drag.as_ref().map(|d| d.vertex),
                message: &self.message,
                blocked: self.blocked.as_deref(),
                steps_per_second: self.meter.rate(),
                undo: self.history.len(),
                redo: self.future.len(),
                conditions: &self.condition_set(&self.mesh).families,
                custom_conditions: self.conditions.is_some(),
                alpha: self.alpha,
                remesh: self.remesh,
                title: &self.title,
            }),
        }
    }

    /// `GET /api/state`: the documented object, positions at full precision.
    pub fn state_json(&mut self) -> serde_json::Value {
        self.refresh_report(true);
        let report = self.report.as_ref().expect("refreshed");
        let residuals: serde_json::Map<String, serde_json::Value> = report
            .families
            .iter()
            .filter(|f| f.gating)
            .map(|f| (f.name.to_string(), f.max.into()))
            .collect();
        let positions: Vec<[f64; 3]> = self.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
        serde_json::json!({
            "vertices": positions.len(),
            "positions": positions,
            "pinned": self.pinned,
            "mode": mode_name(self.mode),
            "residuals": residuals,
            "pass": report.pass(),
            "title": self.title,
            "dragging": self.drag.as_ref().map(|d| d.vertex),
            "settled": !self.wants_to_step(),
            "blocked": self.blocked,
            "message": self.message,
            "anchor": self.anchor,
            "undo": self.history.len(),
            "redo": self.future.len(),
            "alpha": self.alpha,
            "remesh": self.remesh,
            "conditions": self.condition_set(&self.mesh).families.iter().map(|f| f.name()).collect::<Vec<_>>(),
            "stepsPerSecond": self.meter.rate(),
        })
    }
}

fn ok() -> Reply {
    Reply::Json(serde_json::json!({"ok": true}))
}

/// "design" or "simulation".
pub fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Design => "design",
        Mode::Simulation => "simulation",
    }
}

fn file_stem(name: &str) -> String {
    let stem = Path::new(name)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let clean: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect();
    if clean.is_empty() {
        "design".into()
    } else {
        clean
    }
}

fn mean_edge(mesh: &Mesh, x: &[Vec3]) -> f64 {
    let e = mesh.edges();
    e.iter()
        .map(|e| (x[e.vertices[1]] - x[e.vertices[0]]).norm())
        .sum::<f64>()
        / e.len().max(1) as f64
}
