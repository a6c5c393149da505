//! Dragging (§3, §5): the anchor, the solver built for it, and one Euler step of the
//! drag toward the pointer.

use super::requests::{Refusal, Reply};
use super::{ok, Session};
use crate::mesh::Vec3;
use crate::pipeline;
use crate::solver::{pointer_step, Mode, Options, PointerStep, Solver};
use std::collections::BTreeSet;

pub(super) struct DragState {
    pub(super) vertex: usize,
    pub(super) target: Vec3,
    /// The solver cannot go on toward this target (a step failed, or no progress).
    pub(super) stuck: bool,
    pub(super) moved: bool,
}

impl Session {
    /// The anchor for dragging `vertex`: the pins, plus the face farthest from the dragged
    /// vertex while fewer than three are pinned (fewer cannot hold the rigid motions).
    fn anchor_for(&self, vertex: usize) -> Vec<usize> {
        let mut anchor: BTreeSet<usize> = self.design.pinned.clone();
        if anchor.len() < 3 {
            let avoid: Vec<usize> = std::iter::once(vertex).collect();
            anchor.extend(Solver::default_fixed(&self.design.mesh, &avoid));
        }
        anchor.remove(&vertex);
        anchor.into_iter().collect()
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
        if (t - self.positions()[vertex]).norm() > 10.0 * size {
            return Err(Refusal::bad(format!(
                "the drag target is {:.0} mm away, more than ten times the design's size",
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

    pub(super) fn release(&mut self) {
        if let Some(d) = self.drag.take() {
            if !d.moved {
                self.history.pop();
            }
            if self.blocked.is_none() {
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
        match pointer_step(solver, v, target) {
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
