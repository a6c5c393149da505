//! How much work an analysis may do: a deadline, a flag that cancels it when its answer
//! is no longer wanted (the studio's design moved on), and a cap on what the layer-order
//! problem may allocate. `verify` on the command line has no deadline but keeps the cap;
//! the studio's live analysis has both, so a hostile or merely huge file never blocks it.

use std::fmt;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Layer-order constraints a problem may hold. Each takes about 72 bytes plus its
/// watch lists (about 100 bytes in all), and a transitivity triple, stored in twelve,
/// counts as [`TRIPLES_PER_CONSTRAINT`]th of one, so the cap bounds the solver near
/// 1.2 GB: a flat 16 × 16 waterbomb (79 million triples) fits.
pub const MAX_LAYER_CONSTRAINTS: usize = 12_000_000;

/// Transitivity triples that count as one constraint against the cap (by memory: twelve
/// bytes against about a hundred).
pub const TRIPLES_PER_CONSTRAINT: usize = 8;

/// A bound on an analysis's time and memory.
#[derive(Clone, Debug)]
pub struct Budget {
    /// Give up after this instant; the duration it was given, for messages.
    pub deadline: Option<(Instant, Duration)>,
    /// Give up once this is set.
    pub cancel: Option<Arc<AtomicBool>>,
    /// Layer-order constraints the problem may hold.
    pub max_constraints: usize,
    /// Units of search work left (a unit is a constraint or triple the layer search
    /// visits), shared by every search under this budget. Unlike a deadline it ends at
    /// the same point on any machine and under any load, so what it bounds (naming fewer
    /// faces of a proved conflict) gives the same answer everywhere.
    pub work: Option<Arc<AtomicU64>>,
    /// What to tell the user when the budget runs out (e.g. "run `crease verify`").
    pub advice: &'static str,
}

impl Default for Budget {
    /// No deadline, no cancel flag, [`MAX_LAYER_CONSTRAINTS`].
    fn default() -> Self {
        Budget {
            deadline: None,
            cancel: None,
            max_constraints: MAX_LAYER_CONSTRAINTS,
            work: None,
            advice: "",
        }
    }
}

/// Why an analysis stopped before deciding.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Exceeded {
    /// Past the deadline.
    Time(Duration),
    /// More constraints than the cap.
    Size {
        /// The cap.
        limit: usize,
    },
    /// The answer is no longer wanted.
    Cancelled,
    /// The units of search work it was given are spent.
    Work,
}

/// An analysis stopped by its [`Budget`], with the advice to show.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OverBudget {
    /// What ran out.
    pub exceeded: Exceeded,
    /// What to do instead.
    pub advice: &'static str,
}

impl fmt::Display for OverBudget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.exceeded {
            Exceeded::Time(d) => write!(f, "over its time budget of {:.1} s", d.as_secs_f64())?,
            Exceeded::Size { limit } => write!(
                f,
                "too large: more than {:.0e} layer constraints (faces stacked too deep)",
                *limit as f64
            )?,
            Exceeded::Cancelled => write!(f, "cancelled: the design changed")?,
            Exceeded::Work => write!(f, "over its budget of search work")?,
        }
        if !self.advice.is_empty() {
            write!(f, " — {}", self.advice)?;
        }
        Ok(())
    }
}

impl std::error::Error for OverBudget {}

impl Budget {
    /// The command line's budget: `time` from now for the layer search, with the advice
    /// to raise it.
    pub fn search(time: Duration) -> Budget {
        Budget {
            deadline: Some((Instant::now() + time, time)),
            advice: "raise --budget to search longer",
            ..Budget::default()
        }
    }

    /// A budget of `time` from now, cancelled by `cancel`, with `advice` for the user.
    pub fn live(time: Duration, cancel: Arc<AtomicBool>, advice: &'static str) -> Budget {
        Budget {
            deadline: Some((Instant::now() + time, time)),
            cancel: Some(cancel),
            max_constraints: MAX_LAYER_CONSTRAINTS / 3,
            work: None,
            advice,
        }
    }

    /// This budget with `units` of search work to share ([`Budget::work`]).
    pub fn with_work(&self, units: u64) -> Budget {
        Budget {
            work: Some(Arc::new(AtomicU64::new(units))),
            ..self.clone()
        }
    }

    /// Takes `units` of search work; fails once the work given is spent (and from then
    /// on), and on whatever [`Budget::check`] fails on.
    pub fn spend(&self, units: u64) -> Result<(), OverBudget> {
        if let Some(left) = &self.work {
            let taken = left.fetch_update(Ordering::Relaxed, Ordering::Relaxed, |l| {
                Some(l.saturating_sub(units))
            });
            if taken.is_ok_and(|before| before < units) {
                return Err(self.over(Exceeded::Work));
            }
        }
        self.check()
    }

    fn over(&self, exceeded: Exceeded) -> OverBudget {
        OverBudget {
            exceeded,
            advice: self.advice,
        }
    }

    /// Fails once the deadline has passed or the analysis was cancelled.
    pub fn check(&self) -> Result<(), OverBudget> {
        if self
            .cancel
            .as_ref()
            .is_some_and(|c| c.load(Ordering::Relaxed))
        {
            return Err(self.over(Exceeded::Cancelled));
        }
        match self.deadline {
            Some((at, given)) if Instant::now() > at => Err(self.over(Exceeded::Time(given))),
            _ => Ok(()),
        }
    }

    /// Fails when `constraints` is past the cap.
    pub fn check_size(&self, constraints: usize) -> Result<(), OverBudget> {
        if constraints > self.max_constraints {
            return Err(self.over(Exceeded::Size {
                limit: self.max_constraints,
            }));
        }
        Ok(())
    }
}
