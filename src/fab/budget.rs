//! How much work an analysis may do: a deadline, a flag that cancels it when its answer
//! is no longer wanted (the studio's design moved on), and a cap on what the layer-order
//! problem may allocate. The command line's searches (`verify`, `convert --assign`,
//! `fold --flat`) take both from `--budget` and `--memory`; the studio's live analysis
//! has both and the cancel flag, so a hostile or merely huge file never blocks it.

use std::fmt;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Layer-order constraints a problem may hold by default: [`CONSTRAINTS_PER_MB`] times
/// [`DEFAULT_LAYER_MEMORY_MB`]. A flat 16 × 16 waterbomb (79 million triples) fits.
pub const MAX_LAYER_CONSTRAINTS: usize = CONSTRAINTS_PER_MB * DEFAULT_LAYER_MEMORY_MB;

/// The memory, in MB, the layer-order problem may take by default (`--memory`'s
/// default): the process stays under about 2 GB on the largest designs.
pub const DEFAULT_LAYER_MEMORY_MB: usize = 2_000;

/// Constraints (counted as the cap counts them) that one MB of the process's peak
/// memory holds. A constraint takes about 72 bytes plus its watch lists, and a
/// transitivity triple twelve bytes in three lists that grow by doubling; with the
/// overlapping pairs, their index and the mesh, the peak was measured at about 168 bytes
/// a constraint: `verify` of the Japanese Spiny Lobster v2 (Flat-Folder's community set)
/// stops at the cap of 12 million with 1.97 GB resident (19.3 s on one core).
pub const CONSTRAINTS_PER_MB: usize = 6_000;

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
    /// What to tell the user when the problem outgrows [`Budget::max_constraints`], when
    /// that differs from [`Budget::advice`] (the command line's `--memory`).
    pub memory_advice: &'static str,
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
            memory_advice: "",
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
            Exceeded::Size { limit } => {
                let count = if *limit >= 1_000_000 {
                    format!("{} million", (*limit as f64 / 1e5).round() / 10.0)
                } else {
                    limit.to_string()
                };
                write!(
                    f,
                    "too large: more than {count} layer constraints, about {} MB (faces stacked too deep)",
                    limit.div_ceil(CONSTRAINTS_PER_MB)
                )?
            }
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
    /// The command line's budget: `time` from now for the layer search and `memory_mb`
    /// for its problem ([`CONSTRAINTS_PER_MB`] constraints a MB), with the advice to
    /// raise whichever runs out (`--budget`, `--memory`).
    pub fn search(time: Duration, memory_mb: f64) -> Budget {
        Budget {
            deadline: Some((Instant::now() + time, time)),
            max_constraints: (memory_mb * CONSTRAINTS_PER_MB as f64) as usize,
            advice: "raise --budget to search longer",
            memory_advice: "raise --memory (MB) if the machine has it to give",
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
            memory_advice: "",
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
        let advice = match exceeded {
            Exceeded::Size { .. } if !self.memory_advice.is_empty() => self.memory_advice,
            _ => self.advice,
        };
        OverBudget { exceeded, advice }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The command line's budget caps the problem at its MB times
    /// [`CONSTRAINTS_PER_MB`], and each way of running out names the option that
    /// raises it.
    #[test]
    fn each_way_a_search_runs_out_names_the_option_that_raises_it() {
        let budget = Budget::search(Duration::from_secs(60), 10.0);
        assert_eq!(budget.max_constraints, 60_000);
        assert!(budget.check_size(60_000).is_ok());
        let size = budget.check_size(60_001).unwrap_err().to_string();
        assert!(
            size.contains("more than 60000 layer constraints, about 10 MB")
                && size.ends_with("raise --memory (MB) if the machine has it to give"),
            "{size}"
        );
        let late = Budget::search(Duration::ZERO, 10.0);
        std::thread::sleep(Duration::from_millis(2));
        let time = late.check().unwrap_err().to_string();
        assert!(time.ends_with("raise --budget to search longer"), "{time}");
        // The default cap is the default memory's, read as millions past one.
        assert_eq!(
            Budget::search(Duration::from_secs(1), DEFAULT_LAYER_MEMORY_MB as f64).max_constraints,
            MAX_LAYER_CONSTRAINTS
        );
        let default = Budget::default().check_size(MAX_LAYER_CONSTRAINTS + 1);
        assert!(default
            .unwrap_err()
            .to_string()
            .starts_with("too large: more than 12 million layer constraints, about 2000 MB"),);
    }
}
