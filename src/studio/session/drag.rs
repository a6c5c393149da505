//! Dragging (§3, §5): the anchor, the solver built for it, and one Euler step of the
//! drag toward the pointer.

use super::requests::{Refusal, Reply};
use super::{ok, Session};
use crate::constraints::Family;
use crate::mesh::Vec3;
use crate::pipeline;
use crate::pipeline::StepOrder;
use crate::solver::{pointer_release, pointer_step, Mode, Options, PointerStep, Solver};

/// Time a pointer drag's step may spend confirming the layer order (`layer-order` among
/// the conditions) before it is let through and left to the analysis: long enough for a
/// few hundred faces, short enough to keep the drag live.
pub(super) const LIVE_ORDER_TIME: std::time::Duration = std::time::Duration::from_millis(250);
use std::time::Instant;

pub(super) struct DragState {
    pub(super) vertex: usize,
    pub(super) target: Vec3,
    /// The solver cannot go on toward this target (a step failed, or no progress).
    pub(super) stuck: bool,
    pub(super) moved: bool,
    /// With `layer-order` among the conditions: the positions of the last step whose
    /// layer order was confirmed, and whether a step since went unconfirmed (its check
    /// ran out of time). A lost order goes back to them; so does a release whose full
    /// check does not confirm the unconfirmed steps.
    pub(super) confirmed: Option<(Vec<Vec3>, bool)>,
    /// When the next step's layer order is checked live: a check waits twice as long as
    /// the last one took, so checking costs at most a third of the drag's time (on the
    /// 8 × 8 waterbomb a check takes about 0.25 s and a step 0.02–0.07 s). `None` once a
    /// check ran out of time: the design is too large to judge live, and the release
    /// checks the unconfirmed steps in full.
    pub(super) order_check_due: Option<Instant>,
}

impl Session {
    /// The anchor for dragging `vertex` ([`Solver::anchor_with_pins`]).
    fn anchor_for(&self, vertex: usize) -> Vec<usize> {
        Solver::anchor_with_pins(&self.design.mesh, &self.design.pinned, vertex)
    }

    pub(super) fn ensure_solver(&mut self, vertex: usize) -> Result<(), String> {
        if self.solver.is_some() && self.anchor_for(vertex) == self.anchor {
            return Ok(());
        }
        self.settle();
        if pipeline::is_flat_start(&self.design.mesh) {
            // The flat sheet is a singular point no drag leaves (see `pipeline`).
            self.fold_design(pipeline::LEAVE_FLAT_AMOUNT)
                .map_err(|r| r.message)?;
            self.message = format!(
                "the sheet was flat, a singular point no drag leaves: folded to {:.0}% of its targets first (undo to go back)",
                100.0 * pipeline::LEAVE_FLAT_AMOUNT
            );
        }
        let anchor = self.anchor_for(vertex);
        let set = self.condition_set();
        let mut solver = Solver::new(self.design.mesh.clone(), set, &anchor, Options::default())
            .map_err(|e| e.to_string())?;
        solver.correct().map_err(|e| {
            format!("the design does not hold the chosen conditions, so it cannot be dragged: {e}")
        })?;
        self.anchor = anchor;
        self.solver = Some(solver);
        Ok(())
    }

    pub(super) fn check_vertex(&self, vertex: usize) -> Result<(), Refusal> {
        let n = self.positions().len();
        if vertex >= n {
            return Err(Refusal {
                status: 404,
                message: format!("vertex {vertex} does not exist (the design has {n} vertices)"),
            });
        }
        Ok(())
    }

    pub(super) fn drag(&mut self, vertex: usize, target: [f64; 3]) -> Result<Reply, Refusal> {
        self.check_vertex(vertex)?;
        let t = Vec3::new(target[0], target[1], target[2]);
        if !t.iter().all(|c| c.is_finite()) {
            return Err(Refusal::bad("the drag target is not a finite point"));
        }
        let (lo, hi) = self.design.mesh.bounding_box();
        let size = (hi - lo).norm().max(1.0);
        let reach = crate::limits::DRAG_REACH_IN_SIZES;
        if (t - self.positions()[vertex]).norm() > reach * size {
            return Err(Refusal::bad(format!(
                "the drag target is {:.0} mm away, more than {reach} times the design's size",
                (t - self.positions()[vertex]).norm()
            )));
        }
        if self.design.pinned.contains(&vertex) {
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
                let confirmed = self
                    .keeps_order()
                    .then(|| (self.positions().to_vec(), false));
                self.drag = Some(DragState {
                    vertex,
                    target: t,
                    stuck: false,
                    moved: false,
                    confirmed,
                    order_check_due: Some(Instant::now()),
                });
                self.message = format!("dragging vertex {vertex}");
            }
        }
        Ok(ok())
    }

    /// Whether drags hold the layer order (`layer-order` among design mode's conditions).
    fn keeps_order(&self) -> bool {
        self.design.mode == Mode::Design
            && self
                .solver
                .as_ref()
                .is_some_and(|s| s.conditions().families.contains(&Family::LayerOrder))
    }

    /// Undoes the drag's steps back to its last confirmed layer order, saying why.
    fn back_to_confirmed(&mut self, why: String) {
        let (Some(drag), Some(solver)) = (self.drag.as_mut(), self.solver.as_mut()) else {
            return;
        };
        drag.stuck = true;
        if let Some((confirmed, unconfirmed)) = drag.confirmed.as_mut() {
            // A remesh renumbers the vertices: then the last step is all there is to undo.
            if confirmed.len() == solver.positions().len() {
                solver.restore(confirmed.clone());
                *unconfirmed = false;
            }
        }
        let m = format!("vertex {} is held: {why}", drag.vertex);
        self.message = m.clone();
        self.blocked = Some(m);
        self.versions.positions += 1;
    }

    /// After a step: its layer order checked within [`LIVE_ORDER_TIME`] when a check is
    /// due ([`DragState::order_check_due`]), else the step is left unconfirmed. Kept
    /// moves the confirmed state on; lost goes back to it (over the unchecked steps too);
    /// undecided (too slow to check live) lets the steps stand until the release checks
    /// them in full.
    fn hold_order_after_step(&mut self, before: Vec<Vec3>) {
        let (Some(solver), Some(drag)) = (self.solver.as_ref(), self.drag.as_mut()) else {
            return;
        };
        let started = Instant::now();
        if drag.order_check_due.is_none_or(|due| started < due) {
            if let Some((_, unconfirmed)) = drag.confirmed.as_mut() {
                *unconfirmed = true;
            }
            return;
        }
        let verdict = pipeline::layer_order_of_step(solver, LIVE_ORDER_TIME);
        drag.order_check_due = Some(Instant::now() + 2 * started.elapsed());
        match verdict {
            StepOrder::Kept => {
                let now = solver.positions().to_vec();
                drag.confirmed = Some((now, false));
            }
            StepOrder::Lost(why) => {
                if let Some((confirmed, _)) = drag.confirmed.as_mut() {
                    if confirmed.len() != before.len() {
                        *confirmed = before;
                    }
                }
                self.back_to_confirmed(why);
            }
            StepOrder::Undecided(why) => {
                drag.order_check_due = None;
                if let Some((_, unconfirmed)) = drag.confirmed.as_mut() {
                    *unconfirmed = true;
                }
                self.message = format!(
                    "the layer order is too slow to check while dragging ({why}); it is checked when the drag is released"
                );
            }
        }
    }

    pub(super) fn release(&mut self) {
        let unconfirmed = self
            .drag
            .as_ref()
            .and_then(|d| d.confirmed.as_ref())
            .is_some_and(|c| c.1);
        if unconfirmed {
            let solver = self.solver.as_ref().expect("a drag has a solver");
            match pipeline::layer_order_of_step(solver, pipeline::STEP_ORDER_TIME) {
                StepOrder::Kept => {}
                StepOrder::Lost(why) | StepOrder::Undecided(why) => {
                    // The same words as a live check's, so the page (and a person) reads
                    // one message whether the machine was quick enough to check mid-drag.
                    self.back_to_confirmed(format!("{why} (checked on release)"));
                }
            }
        }
        if let Some(d) = self.drag.take() {
            if !d.moved {
                self.history.pop();
            }
            let settled = match (d.moved, self.solver.as_mut()) {
                (true, Some(solver)) => pointer_release(solver),
                _ => true,
            };
            if !settled {
                self.message = format!(
                    "released vertex {}: the design holds its conditions to {:.0e} (a drag's live precision), not the usual {:.0e}; undo the drag if it must be exact",
                    d.vertex,
                    crate::tolerance::LIVE_RESIDUAL,
                    crate::tolerance::SOLVER_RESIDUAL
                );
            }
            if self.blocked.is_none() && settled {
                self.message = format!("released vertex {}", d.vertex);
            }
            self.versions.positions += 1;
        }
    }

    /// One Euler step of the drag toward the pointer: the library's
    /// [`crate::solver::pointer_step`]; the session keeps only what the page shows.
    pub(super) fn drag_step(&mut self) {
        let Some(drag) = &self.drag else { return };
        let (v, target) = (drag.vertex, drag.target);
        let Some(solver) = self.solver.as_mut() else {
            return;
        };
        // With `layer-order` among the conditions a step that would lose the order is
        // undone, as a scripted drag's is; the positions before it are kept for that.
        let keeps_order = self.drag.as_ref().is_some_and(|d| d.confirmed.is_some());
        let before = keeps_order.then(|| solver.positions().to_vec());
        let outcome = pointer_step(solver, v, target);
        if let (Ok(PointerStep::Moved | PointerStep::Held), Some(before)) = (&outcome, before) {
            self.hold_order_after_step(before);
            if self.drag.as_ref().is_some_and(|d| d.stuck) {
                return;
            }
        }
        match outcome {
            Ok(PointerStep::Arrived) => self.drag.as_mut().expect("dragging").stuck = true,
            Ok(step) => {
                self.meter.tick();
                let drag = self.drag.as_mut().expect("dragging");
                drag.moved = true;
                self.design.relaid |= self.design.mode == Mode::Design;
                self.versions.positions += 1;
                if step == PointerStep::Held {
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
            (self.design.remesh, self.solver.as_mut(), self.drag.as_mut())
        else {
            return;
        };
        let outcome = solver.remesh(&[drag.vertex], threshold);
        if let Some(map) = outcome.renumbered {
            drag.vertex = map[drag.vertex];
            self.design.pinned = self.design.pinned.iter().map(|&p| map[p]).collect();
            self.anchor = self.anchor.iter().map(|&p| map[p]).collect();
        }
        if outcome.collapses + outcome.flips > 0 {
            self.message = format!(
                "remeshed: {} edge collapse(s), {} flip(s)",
                outcome.collapses, outcome.flips
            );
            self.forget_pattern();
            self.in_force = None;
        }
    }
}
