//! The studio's fit to a target surface: a target loaded from the page and placed by the
//! user, and [`crate::fit::Fitter`] stepped on the session thread like a drag, so the
//! page sees the distance fall and the design stays draggable and pinnable (a drag
//! pauses the fit, which resumes from wherever the drag left the design). Pins are held
//! still; nothing else is anchored, so the design slides onto the target as it bends.
//! Undo returns to before the fit.

use super::requests::{FitRequest, Refusal, Reply, TargetPlacement};
use super::{ok, Session};
use crate::constraints::Family;
use crate::fit::{FitOptions, Fitter, SurfaceChoice};
use crate::limits;
use crate::mesh::Vec3;
use crate::pipeline;
use crate::solver::{Options, Solver};
use crate::surface::TriSurface;
use std::sync::Arc;

/// A target surface as loaded and as placed.
pub(super) struct StudioTarget {
    name: String,
    loaded: Arc<TriSurface>,
    pub(super) placed: Arc<TriSurface>,
    placement: TargetPlacement,
    /// Changes whenever the placed surface does (the page fetches it then).
    pub(super) version: u64,
}

/// A fit under way, paused or finished.
pub(super) struct FitRun {
    fitter: Fitter,
    /// Steps taken.
    steps: usize,
    /// (RMS, largest) after the last step (mm).
    last: (f64, f64),
    /// The goal (mm).
    goal: f64,
}

impl Session {
    /// Takes a target already read (`crate::io::read_target_bytes`, on the connection's
    /// thread) and brings it near the design.
    pub(super) fn load_target(&mut self, name: &str, surface: TriSurface) -> Reply {
        self.stop_fit("a new target was loaded");
        let surface = Arc::new(surface);
        let version = self.target.as_ref().map_or(1, |t| t.version + 1);
        self.target = Some(StudioTarget {
            name: name.to_string(),
            loaded: surface.clone(),
            placed: surface,
            placement: TargetPlacement::default(),
            version,
        });
        let triangles = self
            .target
            .as_ref()
            .map_or(0, |t| t.placed.triangles().len());
        self.message = match self.bring_target_to_design() {
            Some((shift, apart)) => format!(
                "target {name} loaded ({triangles} triangles) {apart:.0} mm from the design and moved onto it by ({:.1}, {:.1}, {:.1}) mm: adjust it, then press Fit",
                shift.x, shift.y, shift.z
            ),
            None => format!("target {name} loaded ({triangles} triangles): place it, then press Fit"),
        };
        self.target_summary()
    }

    /// A target whose box does not meet the design's is shifted so the boxes' centres
    /// meet (a dome file drawn about the origin and a pattern laid out from it started
    /// far apart, and nothing said so): the shift and how far apart they were, or `None`
    /// when they already meet (the file's own placement is kept) or the shift is out of
    /// range.
    fn bring_target_to_design(&mut self) -> Option<(Vec3, f64)> {
        let (dlo, dhi) = self.current().bounding_box();
        let (tlo, thi) = self.target.as_ref()?.loaded.bounding_box();
        let meet = (0..3).all(|k| tlo[k] <= dhi[k] && dlo[k] <= thi[k]);
        if meet {
            return None;
        }
        let shift = (dlo + dhi) / 2.0 - (tlo + thi) / 2.0;
        let gap = Vec3::from_fn(|k, _| (tlo[k] - dhi[k]).max(dlo[k] - thi[k]).max(0.0)).norm();
        let placement = TargetPlacement {
            shift: Some([shift.x, shift.y, shift.z]),
            ..TargetPlacement::default()
        };
        self.place_target(placement).ok()?;
        Some((shift, gap))
    }

    pub(super) fn place_target(&mut self, p: TargetPlacement) -> Result<Reply, Refusal> {
        let bad = |e: limits::OutOfRange| Refusal::bad(e.to_string());
        let shift = p.shift.unwrap_or_default();
        let turn = p.turn.unwrap_or_default();
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            limits::TARGET_SHIFT
                .check(format!("shift {axis}"), shift[k])
                .map_err(bad)?;
            limits::TURN
                .check(format!("turn {axis}"), turn[k])
                .map_err(bad)?;
        }
        let offset = p.offset.unwrap_or(0.0);
        let Some(target) = &mut self.target else {
            return Err(Refusal::conflict(
                "no target loaded: load an .obj or .stl first",
            ));
        };
        let (lo, hi) = target.loaded.bounding_box();
        let most = limits::TARGET_OFFSET_OF_EXTENT * (hi - lo).norm();
        if !(offset.is_finite() && offset.abs() <= most) {
            return Err(Refusal::bad(format!(
                "offset = {}: an offset must be within half the target's extent ({} mm)",
                limits::short(offset),
                limits::short(most)
            )));
        }
        target.placed = Arc::new(target.loaded.placed(
            offset,
            turn,
            Vec3::new(shift[0], shift[1], shift[2]),
        ));
        target.placement = p;
        target.version += 1;
        self.stop_fit("the target moved");
        Ok(self.target_summary())
    }

    pub(super) fn clear_target(&mut self) -> Reply {
        self.stop_fit("the target was removed");
        self.target = None;
        ok()
    }

    /// `GET /api/target`: the placed target's triangles, for drawing.
    pub(super) fn target_mesh(&self) -> Result<Reply, Refusal> {
        let Some(t) = &self.target else {
            return Err(Refusal {
                status: 404,
                message: "no target loaded".into(),
            });
        };
        let vertices: Vec<[f64; 3]> = t
            .placed
            .vertices()
            .iter()
            .map(|p| [p.x, p.y, p.z])
            .collect();
        Ok(Reply::Json(serde_json::json!({
            "name": t.name,
            "version": t.version,
            "vertices": vertices,
            "triangles": t.placed.triangles(),
        })))
    }

    fn target_summary(&self) -> Reply {
        Reply::Json(serde_json::json!({
            "ok": true,
            "target": self.target_json(),
        }))
    }

    /// The target's name, version and placement for the state and frames (no triangles).
    pub(super) fn target_json(&self) -> serde_json::Value {
        match &self.target {
            Some(t) => serde_json::json!({
                "name": t.name,
                "version": t.version,
                "triangles": t.placed.triangles().len(),
                "shift": t.placement.shift.unwrap_or_default(),
                "turn": t.placement.turn.unwrap_or_default(),
                "offset": t.placement.offset.unwrap_or(0.0),
            }),
            None => serde_json::Value::Null,
        }
    }

    /// The fit's progress for the state and frames.
    pub(super) fn fit_json(&self) -> serde_json::Value {
        match &self.fit {
            Some(run) => serde_json::json!({
                "running": run.fitter.stopped().is_none(),
                "steps": run.steps,
                "rms": run.last.0,
                "largest": run.last.1,
                "goal": run.goal,
                "stopped": run.fitter.stopped().map(|s| s.name()),
            }),
            None => serde_json::Value::Null,
        }
    }

    pub(super) fn start_fit(&mut self, r: FitRequest) -> Result<Reply, Refusal> {
        let Some(target) = &self.target else {
            return Err(Refusal::conflict(
                "no target to fit to: load an .obj or .stl first",
            ));
        };
        let target = target.placed.clone();
        let mut options = FitOptions::default();
        if let Some(n) = r.steps {
            options.max_steps = limits::STEPS
                .check_count("steps", n as u64)
                .map_err(|e| Refusal::bad(e.to_string()))? as usize;
        }
        if let Some(g) = r.within {
            options.goal = Some(
                limits::FIT_GOAL
                    .check("within", g)
                    .map_err(|e| Refusal::bad(e.to_string()))?,
            );
        }
        if let Some(s) = &r.surface {
            options.surface = SurfaceChoice::parse(s).map_err(Refusal::bad)?;
        }
        self.stop_fit("Fit was pressed again");
        self.release();
        self.remember();
        if let Err(m) = self.ensure_fit_solver() {
            self.history.pop();
            self.blocked = Some(m.clone());
            return Err(Refusal::failed(m));
        }
        let solver = self.solver.as_ref().expect("just built");
        let fitter = Fitter::new(solver, target, options);
        let (rms, largest) = fitter.history[0];
        let goal = fitter.goal(solver);
        self.fit = Some(FitRun {
            fitter,
            steps: 0,
            last: (rms, largest),
            goal,
        });
        self.blocked = None;
        self.message = format!("fitting: largest distance {largest:.2} mm, goal {goal:.2} mm");
        Ok(ok())
    }

    /// Stops a fit under way (Stop, a new target, undo); the design stays where it is.
    pub(super) fn stop_fit(&mut self, why: &str) {
        if let Some(run) = self.fit.take() {
            if run.fitter.stopped().is_none() {
                self.message = format!(
                    "fit stopped ({why}) after {} steps: largest distance {:.3} mm",
                    run.steps, run.last.1
                );
            }
        }
    }

    /// Whether a fit wants steps.
    pub(super) fn fit_running(&self) -> bool {
        self.fit
            .as_ref()
            .is_some_and(|f| f.fitter.stopped().is_none())
    }

    /// A solver for the fit: the pins held, nothing else (see the module's doc).
    fn ensure_fit_solver(&mut self) -> Result<(), String> {
        let pins: Vec<usize> = self.design.pinned.iter().copied().collect();
        if self.solver.is_some() && self.anchor == pins {
            return Ok(());
        }
        self.settle();
        if pipeline::is_flat_start(&self.design.mesh) {
            self.fold_design(pipeline::LEAVE_FLAT_AMOUNT)
                .map_err(|r| r.message)?;
        }
        let set = self.condition_set();
        let options = crate::fit::solver_options(&Options::default());
        let mut solver = Solver::new(self.design.mesh.clone(), set, &pins, options)
            .map_err(|e| e.to_string())?;
        solver.correct().map_err(|e| {
            format!("the design does not hold the chosen conditions, so it cannot be fitted: {e}")
        })?;
        self.anchor = pins;
        if let Some(run) = &mut self.fit {
            run.fitter.regroup(&solver);
        }
        self.solver = Some(solver);
        Ok(())
    }

    /// One step of the fit (when no drag is under way).
    pub(super) fn fit_step(&mut self) {
        if !self.fit_running() {
            return;
        }
        if let Err(m) = self.ensure_fit_solver() {
            self.stop_fit("the solver could not be prepared");
            self.blocked = Some(m.clone());
            self.message = m;
            return;
        }
        let (Some(run), Some(solver)) = (self.fit.as_mut(), self.solver.as_mut()) else {
            return;
        };
        // With `layer-order` among the conditions a step that loses the order is undone,
        // as a pointer drag's is (a step too slow to confirm live stands).
        let keep_order = solver.conditions().families.contains(&Family::LayerOrder);
        let mut check =
            |s: &Solver| match pipeline::layer_order_of_step(s, super::drag::LIVE_ORDER_TIME) {
                pipeline::StepOrder::Lost(why) => Some(why),
                _ => None,
            };
        let check = keep_order.then_some(&mut check);
        match run.fitter.step_checked(solver, check) {
            Ok(m) => {
                run.steps += 1;
                run.last = (m.rms, m.largest);
                self.meter.tick();
                self.versions.positions += 1;
                self.design.relaid |= self.design.mode == crate::solver::Mode::Design;
                self.message = format!(
                    "fitting: step {}, largest distance {:.3} mm (goal {:.3}), RMS {:.3} mm",
                    run.steps, m.largest, run.goal, m.rms
                );
                if let Some(stop) = run.fitter.stopped() {
                    run.fitter.settle_on_best(solver);
                    let after = run.fitter.measure(solver);
                    run.last = (after.rms, after.largest);
                    self.message = format!(
                        "fit {} after {} steps: largest distance {:.3} mm (goal {:.3} mm {}), RMS {:.3} mm",
                        stop.name(),
                        run.steps,
                        after.largest,
                        run.goal,
                        if after.largest <= run.goal { "met" } else { "not met" },
                        after.rms
                    );
                }
            }
            Err(e) => {
                let m = format!("the fit was blocked: {e}");
                self.fit = None;
                self.message = m.clone();
                self.blocked = Some(m);
            }
        }
    }
}
