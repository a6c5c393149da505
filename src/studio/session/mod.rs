//! The studio's session: the design being varied, its solver, the user's pins and
//! settings, and the undo history. One thread owns it (see [`super::hub`]); requests
//! reach it as [`Command`]s and every change is published as a `Frame`.
//!
//! It turns requests into library calls and holds no geometry of its own: dragging is the
//! solver's null-space step and Newton correction (§3), the crease pattern is
//! [`crate::geometry::unfold::sheet_of`], the x-ray is [`crate::fab::flat_folded`], the verdict is
//! [`crate::fab::verify()`], saving is [`crate::pipeline::finish_design`] as `deform` does.

mod analysis;
mod drag;
mod edits;
mod fit;
mod motion;
mod requests;

pub use requests::{
    Command, FabRequest, FitRequest, GenerateRequest, MotionRequest, Refusal, Reply, Settings,
    TargetPlacement,
};

use super::frame::{self, Frame, Meter};
use crate::constraints::{ConstraintSet, Family};
use crate::fab::Report;
use crate::generate::{self, Params, PatternKind};
use crate::mesh::{Mesh, Vec3};
use crate::solver::{Mode, Solver};
use analysis::{Analyst, Job, Stamp};
use drag::DragState;
use std::collections::BTreeSet;
use std::sync::Arc;
use std::time::{Duration, Instant};

pub use crate::limits::MAX_UPLOAD;

/// Minimum time between crease-pattern rebuilds during a drag (the page redraws two flat
/// views from them); at rest the pattern is always rebuilt.
const RELAY_EVERY: Duration = Duration::from_millis(300);
/// How long `/api/state` waits for the verdict of the design as it is now.
const STATE_WAIT: Duration = Duration::from_millis(300);

/// What undo restores: the design and every setting the user chose for it.
#[derive(Clone)]
struct Design {
    mesh: Mesh,
    pinned: BTreeSet<usize>,
    mode: Mode,
    /// Condition families held in design mode; `None` is the design's default set.
    conditions: Option<Vec<Family>>,
    alpha: f64,
    remesh: Option<f64>,
    /// Design mode changed lengths since the pattern was loaded: saving unfolds anew.
    relaid: bool,
}

/// The studio's design session.
pub struct Session {
    /// The design as of the last settled change (during a drag the solver holds the
    /// moving positions; see [`Session::current`]).
    design: Design,
    title: String,
    solver: Option<Solver>,
    anchor: Vec<usize>,
    drag: Option<DragState>,
    history: Vec<Design>,
    future: Vec<Design>,
    message: String,
    blocked: Option<String>,
    report: Option<Report>,
    /// The design the report describes.
    report_stamp: Option<Stamp>,
    /// The crease-pattern part of frames, and the design it describes.
    pattern_json: Arc<String>,
    pattern_stamp: Option<Stamp>,
    pattern_at: Option<Instant>,
    analyst: Analyst,
    versions: frame::Versions,
    meter: Meter,
    fab_files: Vec<(String, Vec<u8>)>,
    /// The folding motion of the design as it is, once asked for.
    motion: Option<crate::pipeline::Motion>,
    /// The conditions in force, computed once per design and settings (the default set
    /// needs the design's reference state).
    in_force: Option<ConstraintSet>,
    /// A request changed what the page shows since the last frame.
    unpublished: bool,
    /// The target surface a fit pulls toward, as the user placed it.
    target: Option<fit::StudioTarget>,
    /// The fit under way or finished.
    fit: Option<fit::FitRun>,
}

impl Session {
    /// A session around a design.
    pub fn new(mesh: Mesh, title: &str) -> Session {
        let mut s = Session {
            design: Design {
                mesh,
                pinned: BTreeSet::new(),
                mode: Mode::Design,
                conditions: None,
                alpha: 0.0,
                remesh: None,
                relaid: false,
            },
            title: title.to_string(),
            solver: None,
            anchor: Vec::new(),
            drag: None,
            history: Vec::new(),
            future: Vec::new(),
            message: "ready: drag a vertex; Shift-click pins it".into(),
            blocked: None,
            report: None,
            report_stamp: None,
            pattern_json: Arc::new(String::from("{}")),
            pattern_stamp: None,
            pattern_at: None,
            analyst: Analyst::start(),
            versions: frame::Versions::default(),
            meter: Meter::default(),
            fab_files: Vec::new(),
            motion: None,
            in_force: None,
            unpublished: false,
            target: None,
            fit: None,
        };
        s.design.alpha = s.mesh_alpha();
        s.design_changed(true);
        s
    }

    /// The starting design without a file: the bundled Miura-ori at half fold.
    pub fn default_design() -> Mesh {
        generate::generate(&Params::defaults(PatternKind::Miura))
            .expect("the default Miura-ori parameters are valid")
    }

    fn mesh_alpha(&self) -> f64 {
        self.design
            .mesh
            .edges()
            .iter()
            .filter(|e| e.target == 0.0)
            .map(|e| e.alpha)
            .fold(0.0, f64::max)
    }

    /// Whether the session has work to do without a request: a drag that can go on, or
    /// a fit (paused while a drag is under way).
    pub fn wants_to_step(&self) -> bool {
        match &self.drag {
            Some(d) => !d.stuck,
            None => self.fit_running(),
        }
    }

    /// One step of what is under way: the drag, else the fit.
    pub fn step(&mut self) {
        if self.drag.is_some() {
            self.drag_step();
        } else {
            self.fit_step();
        }
    }

    /// The design as it stands (the solver's positions during a drag).
    pub fn current(&self) -> Mesh {
        match &self.solver {
            Some(s) => {
                let mut m = s.mesh().clone();
                m.set_positions(s.positions().to_vec());
                m
            }
            None => self.design.mesh.clone(),
        }
    }

    /// The mesh whose topology is current: the solver's while it exists (remeshing changes
    /// it there), else the design's. Its positions may lag the solver's; see
    /// [`Session::positions`].
    fn topology_mesh(&self) -> &Mesh {
        self.solver.as_ref().map_or(&self.design.mesh, |s| s.mesh())
    }

    fn positions(&self) -> &[Vec3] {
        match &self.solver {
            Some(s) => s.positions(),
            None => self.design.mesh.positions(),
        }
    }

    /// Moves the solver's state into `mesh` and drops the solver (settings or anchor change).
    fn settle(&mut self) {
        if let Some(s) = self.solver.take() {
            self.design.mesh = s.into_mesh();
        }
    }

    /// The design as it stands, with the solver's positions.
    fn snapshot(&self) -> Design {
        match self.solver {
            None => self.design.clone(),
            Some(_) => Design {
                mesh: self.current(),
                ..self.design.clone()
            },
        }
    }

    fn restore(&mut self, design: Design) {
        self.stop_fit("undo");
        self.solver = None;
        self.drag = None;
        self.design = design;
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
        if topology {
            self.forget_pattern();
        }
        self.in_force = None;
        self.fab_files.clear();
        self.motion = None;
    }

    /// The conditions in force: simulation mode's, the user's choice, or what the design's
    /// own assignment calls for.
    fn condition_set(&mut self) -> ConstraintSet {
        if self.in_force.is_none() {
            let chosen = self.design.conditions.as_ref().map(|f| ConstraintSet {
                families: f.clone(),
            });
            self.in_force = Some(
                self.design
                    .mode
                    .conditions(chosen.as_ref(), &self.design.mesh),
            );
        }
        self.in_force.clone().expect("just computed")
    }

    /// Handles one request; the caller publishes [`Session::frame`] afterwards.
    pub fn handle(&mut self, command: Command) -> Result<Reply, Refusal> {
        self.unpublished |= !self.is_quiet(&command);
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
            Command::Open { name, imported } => Ok(self.open(&name, *imported)),
            Command::SaveFold => {
                let mesh = self.finished()?;
                Ok(Reply::File {
                    name: crate::pipeline::names::design_file(&self.title),
                    bytes: crate::io::fold::to_string(&mesh).into_bytes(),
                })
            }
            Command::Fabricate(r) => self.fabricate(r),
            Command::Motion(r) => self.motion(r),
            Command::MotionFile(format) => self.motion_file(&format),
            Command::LoadTarget { name, surface } => Ok(self.load_target(&name, *surface)),
            Command::PlaceTarget(p) => self.place_target(p),
            Command::ClearTarget => Ok(self.clear_target()),
            Command::TargetMesh => self.target_mesh(),
            Command::Fit(r) => self.start_fit(r),
            Command::StopFit => {
                self.stop_fit("Stop");
                Ok(ok())
            }
            #[cfg(test)]
            Command::Panic => panic!("a panic injected by a test"),
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

    /// Requests that change nothing on screen: reads, and a new pointer position for the
    /// drag under way (the next solver step shows it). At 10k vertices a frame costs
    /// milliseconds, and a mouse sends sixty positions a second.
    fn is_quiet(&self, command: &Command) -> bool {
        match command {
            Command::State | Command::FabFile(_) | Command::TargetMesh => true,
            Command::MotionFile(_) => true,
            Command::Drag { vertex, .. } => self.drag.as_ref().is_some_and(|d| d.vertex == *vertex),
            _ => false,
        }
    }

    /// After a request panicked (a bug): the solver and the drag are dropped, so the
    /// design is the last settled one, and the page is sent a fresh frame.
    pub fn recover(&mut self) {
        self.solver = None;
        self.drag = None;
        self.blocked = None;
        self.message = "an internal error stopped the last request; the design is kept".into();
        self.design_changed(true);
        self.unpublished = true;
    }

    /// Whether something changed since the last frame was built; clears the flag.
    pub fn take_unpublished(&mut self) -> bool {
        std::mem::take(&mut self.unpublished)
    }

    fn pin(&mut self, vertex: usize, pinned: bool) -> Result<Reply, Refusal> {
        self.check_vertex(vertex)?;
        if self.drag.as_ref().is_some_and(|d| d.vertex == vertex) {
            return Err(Refusal::conflict(format!(
                "vertex {vertex} is being dragged; release it first"
            )));
        }
        if self.design.pinned.contains(&vertex) != pinned {
            self.remember();
            if pinned {
                self.design.pinned.insert(vertex);
            } else {
                self.design.pinned.remove(&vertex);
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

    /// A new topology: the old crease pattern's indices no longer fit, so frames carry
    /// none until the analyst has laid out the new one.
    fn forget_pattern(&mut self) {
        self.versions.topology += 1;
        self.versions.pattern += 1;
        self.pattern_json = Arc::new(String::from("{}"));
        self.pattern_stamp = None;
    }

    fn stamp(&self) -> Stamp {
        Stamp {
            positions: self.versions.positions,
            topology: self.versions.topology,
        }
    }

    fn job(&mut self, with_pattern: bool) -> Job {
        Job {
            mesh: self.current(),
            set: self.condition_set(),
            relaid: self.design.relaid,
            with_pattern,
            stamp: self.stamp(),
        }
    }

    fn accept(&mut self, a: analysis::Analysis) -> bool {
        if a.stamp.topology != self.versions.topology {
            return false;
        }
        self.report = Some(a.report);
        self.report_stamp = Some(a.stamp);
        if let Some(json) = a.pattern_json {
            self.pattern_stamp = Some(a.stamp);
            self.pattern_at = Some(Instant::now());
            if *self.pattern_json != json {
                self.pattern_json = Arc::new(json);
                self.versions.pattern += 1;
            }
        }
        true
    }

    /// Takes in a finished analysis and starts the next one if the design has moved on.
    /// Returns whether anything new arrived.
    pub fn analyse(&mut self) -> bool {
        self.analyst.cancel_unless(self.versions.topology);
        let arrived = match self.analyst.collect(Duration::ZERO) {
            Some(a) => self.accept(a),
            None => false,
        };
        let now = self.stamp();
        if !self.analyst.busy() && self.report_stamp != Some(now) {
            let pattern_due = self
                .pattern_stamp
                .is_none_or(|s| s.topology != now.topology)
                || (self.pattern_stamp != Some(now)
                    && (!self.wants_to_step()
                        || self.pattern_at.is_none_or(|t| t.elapsed() >= RELAY_EVERY)));
            let job = self.job(pattern_due);
            self.analyst.send(job);
        }
        arrived
    }

    /// Work for an idle session: a finished analysis, or a step meter that fell to 0.
    pub fn idle(&mut self, shown_rate: f64) -> bool {
        let arrived = self.analyse();
        arrived || self.meter.rate() != shown_rate
    }

    /// The report of the design as it is now, waiting up to [`STATE_WAIT`] for the
    /// analyst (twice at most: for the analysis under way, then for this design's), so
    /// `/api/state` answers within a second whatever the design; `None` when the verdict
    /// is not in yet (the page's frames bring it when it is). While a drag or fit steps
    /// it does not wait: every step is a new design, so a wait would hold the solver for
    /// every poll and bring a verdict the next step makes stale (polled every 20 ms, two
    /// layer-order drags of the waterbomb took 82 s, and 31 s without the wait).
    fn fresh_report(&mut self) -> Option<&Report> {
        if self.wants_to_step() {
            // A finished analysis is still taken, and the next one started.
            self.unpublished |= self.analyse();
        } else {
            for _ in 0..2 {
                if self.report_stamp == Some(self.stamp()) {
                    break;
                }
                if !self.analyst.busy() {
                    self.analyse();
                }
                if let Some(a) = self.analyst.collect(STATE_WAIT) {
                    // The page has not seen it either: the next frame carries it.
                    self.unpublished |= self.accept(a);
                }
            }
        }
        let current = self.report_stamp == Some(self.stamp());
        current.then_some(self.report.as_ref()).flatten()
    }

    /// The frame the page draws, rebuilt from what changed.
    pub fn frame(&mut self, previous: Option<&Frame>) -> Frame {
        let conditions = self.condition_set();
        self.analyse();
        // Faces and creases need no positions: no copy of the mesh is made for them.
        let topology = match previous {
            Some(p) if p.topology_version == self.versions.topology => p.topology.clone(),
            _ => Arc::new(frame::topology_json(self.topology_mesh())),
        };
        let pattern = Arc::clone(&self.pattern_json);
        Frame {
            version: self.versions.next_frame(),
            topology_version: self.versions.topology,
            pattern_version: self.versions.pattern,
            topology,
            pattern,
            steps_per_second: self.meter.rate(),
            live: frame::live_json(&frame::Live {
                positions: self.positions(),
                pinned: &self.design.pinned,
                anchor: &self.anchor,
                mode: self.design.mode,
                report: self.report.as_ref(),
                dragging: self.drag.as_ref().map(|d| d.vertex),
                message: &self.message,
                blocked: self.blocked.as_deref(),
                steps_per_second: self.meter.rate(),
                undo: self.history.len(),
                redo: self.future.len(),
                conditions: &conditions.families,
                custom_conditions: self.design.conditions.is_some(),
                alpha: self.design.alpha,
                remesh: self.design.remesh,
                title: &self.title,
                target: self.target_json(),
                fit: self.fit_json(),
            }),
        }
    }

    /// `GET /api/state`: the documented object, positions at full precision.
    pub fn state_json(&mut self) -> serde_json::Value {
        let conditions = self.condition_set();
        let report = self.fresh_report().cloned();
        let residuals: serde_json::Map<String, serde_json::Value> = report
            .iter()
            .flat_map(|r| &r.families)
            .filter(|f| f.gating)
            .map(|f| (f.name.to_string(), f.max.into()))
            .collect();
        let positions: Vec<[f64; 3]> = self.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
        serde_json::json!({
            "vertices": positions.len(),
            "positions": positions,
            "pinned": self.design.pinned,
            "mode": self.design.mode.name(),
            "residuals": residuals,
            "pass": report.as_ref().map(Report::pass),
            "judged": report.is_some(),
            "title": self.title,
            "dragging": self.drag.as_ref().map(|d| d.vertex),
            "settled": !self.wants_to_step(),
            "blocked": self.blocked,
            "message": self.message,
            "anchor": self.anchor,
            "undo": self.history.len(),
            "redo": self.future.len(),
            "alpha": self.design.alpha,
            "remesh": self.design.remesh,
            "conditions": conditions.families.iter().map(|f| f.name()).collect::<Vec<_>>(),
            "stepsPerSecond": self.meter.rate(),
            "topologyVersion": self.versions.topology,
            "target": self.target_json(),
            "fit": self.fit_json(),
        })
    }
}

fn ok() -> Reply {
    Reply::Json(serde_json::json!({"ok": true}))
}
