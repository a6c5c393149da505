//! Why a solve failed, and which condition stopped it.

use crate::constraints::Family;

/// Why a linear solve failed (the factorisation in `linear`, or the ordering before it).
#[derive(Debug, thiserror::Error)]
#[error("the normal equations J Jᵀ could not be factorised: {0}")]
pub struct LinearError(pub(super) String);

/// Why a solve failed.
#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    /// A named vertex does not exist.
    #[error("vertex {vertex} does not exist (the mesh has {count} vertices)")]
    UnknownVertex {
        /// The vertex.
        vertex: usize,
        /// Vertex count.
        count: usize,
    },
    /// The solver needs a disk or a tube.
    #[error("the solver needs a single sheet without holes (a disk) or a tube closed along a seam; this mesh has {components} piece(s) and {holes} hole(s)")]
    NotADisk {
        /// Pieces of paper.
        components: usize,
        /// Holes.
        holes: usize,
    },
    /// Newton's method did not bring the residual under tolerance.
    #[error("the solve did not converge at step {step}: residual {residual:.2e} after {iterations} Newton iterations (tolerance {tolerance:.0e}){}", blocker_text(blocker))]
    NotConverged {
        /// Step number.
        step: usize,
        /// Remaining max |residual|.
        residual: f64,
        /// Iterations spent.
        iterations: usize,
        /// The tolerance.
        tolerance: f64,
        /// The condition and element with the largest residual where the solve gave up:
        /// what blocked the step.
        blocker: Option<Blocker>,
    },
    /// The normal equations could not be factorised.
    #[error(transparent)]
    Linear(#[from] LinearError),
}

/// The condition that stopped a step, and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blocker {
    /// The condition family.
    pub family: Family,
    /// The element whose residual was largest.
    pub element: crate::constraints::Element,
    /// That residual.
    pub residual: f64,
}

impl std::fmt::Display for Blocker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} at {} (residual {:.1e})",
            self.family.name(),
            self.element,
            self.residual
        )
    }
}

fn blocker_text(b: &Option<Blocker>) -> String {
    match b {
        Some(b) => format!("; blocked by {b}"),
        None => String::new(),
    }
}
