//! How much work an analysis may do: a deadline, a flag that cancels it when its answer
//! is no longer wanted (the studio's design moved on), and a cap on what the layer-order
//! problem may allocate. The command line's searches (`verify`, `convert --assign`,
//! `fold --flat`) take both from `--budget` and `--memory`; the studio's live analysis
//! has both and the cancel flag, so a hostile or merely huge file never blocks it.

use std::fmt;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The memory, in MB, the layer-order problem may take by default (`--memory`'s
/// default): the process stays under about 2 GB on the largest designs.
pub const DEFAULT_LAYER_MEMORY_MB: usize = 2_000;

/// Bytes the layer-order problem may take by default ([`DEFAULT_LAYER_MEMORY_MB`]). A
/// flat 16 × 16 waterbomb (79 million triples) fits.
pub const MAX_LAYER_BYTES: usize = DEFAULT_LAYER_MEMORY_MB * 1_000_000;

/// Memory of each overlapping pair of pieces (a variable): its faces' overlap records,
/// its place in the pair index, its watch lists and the search's state for it.
pub const BYTES_PER_PAIR: usize = 300;

/// Memory of each taco–tortilla or taco–taco constraint: four literals of 8 bytes and
/// its watch entries, in a list that grows by doubling.
pub const BYTES_PER_CONSTRAINT: usize = 64;

/// Memory of each transitivity triple beside its three entries (its third piece under
/// each of its pairs, `layers::thirds`, allocated to size): what finding it leaves behind.
pub const BYTES_PER_TRIPLE_FOUND: usize = 1;

/// The memory a layer problem of `pairs` variables, `constraints` constraints and
/// `triples` triples takes, as the cap counts it ([`Budget::check_size`]), where a
/// triple's entry takes `entry_bytes` (2 or 4, by how many pieces it numbers). Fitted to
/// the peak resident memory of `verify` on Flat-Folder's largest community designs (after
/// the mesh, about 80 MB, is read), with entries of 2 bytes: the Japanese Spiny Lobster v2
/// (1.01 million pairs, 1.36 million constraints, 134 million triples) peaks at 1.25 GB
/// against an estimate of 1.33 GB, the new Flying Mantis at 576 MB against 578 MB and
/// Kamiya's Ryujin 2.1 at 433 MB against 402 MB.
pub fn layer_bytes(pairs: usize, constraints: usize, triples: usize, entry_bytes: usize) -> usize {
    pairs
        .saturating_mul(BYTES_PER_PAIR)
        .saturating_add(constraints.saturating_mul(BYTES_PER_CONSTRAINT))
        .saturating_add(triples.saturating_mul(3 * entry_bytes + BYTES_PER_TRIPLE_FOUND))
}

/// A bound on an analysis's time and memory.
#[derive(Clone, Debug)]
pub struct Budget {
    /// Give up after this instant; the duration it was given, for messages.
    pub deadline: Option<(Instant, Duration)>,
    /// Give up once this is set.
    pub cancel: Option<Arc<AtomicBool>>,
    /// Bytes the layer-order problem may take, as [`layer_bytes`] counts them.
    pub max_layer_bytes: usize,
    /// Units of search work left (a unit is a constraint or triple the layer search
    /// visits), shared by every search under this budget. Unlike a deadline it ends at
    /// the same point on any machine and under any load, so what it bounds (naming fewer
    /// faces of a proved conflict) gives the same answer everywhere.
    pub work: Option<Arc<AtomicU64>>,
    /// What to tell the user when the budget runs out (e.g. "run `crease verify`").
    pub advice: &'static str,
    /// What to tell the user when the problem outgrows [`Budget::max_layer_bytes`], when
    /// that differs from [`Budget::advice`] (the command line's `--memory`).
    pub memory_advice: &'static str,
}

impl Default for Budget {
    /// No deadline, no cancel flag, [`MAX_LAYER_BYTES`].
    fn default() -> Self {
        Budget {
            deadline: None,
            cancel: None,
            max_layer_bytes: MAX_LAYER_BYTES,
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
    /// A layer problem larger than the cap.
    Size {
        /// The cap, in bytes.
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
                "too large: its layer constraints would take more than {} MB (faces stacked too deep)",
                limit.div_ceil(1_000_000)
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
    /// The command line's budget: `time` from now for the layer search and `memory_mb`
    /// for its problem ([`layer_bytes`]), with the advice to raise whichever runs out
    /// (`--budget`, `--memory`).
    pub fn search(time: Duration, memory_mb: f64) -> Budget {
        Budget {
            deadline: Some((Instant::now() + time, time)),
            max_layer_bytes: (memory_mb * 1e6) as usize,
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
            max_layer_bytes: MAX_LAYER_BYTES / 3,
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

    /// Fails when a layer problem of `bytes` ([`layer_bytes`]) is past the cap.
    pub fn check_size(&self, bytes: usize) -> Result<(), OverBudget> {
        if bytes > self.max_layer_bytes {
            return Err(self.over(Exceeded::Size {
                limit: self.max_layer_bytes,
            }));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The command line's budget caps the problem at its MB, and each way of running
    /// out names the option that raises it.
    #[test]
    fn each_way_a_search_runs_out_names_the_option_that_raises_it() {
        let budget = Budget::search(Duration::from_secs(60), 10.0);
        assert_eq!(budget.max_layer_bytes, 10_000_000);
        assert!(budget.check_size(10_000_000).is_ok());
        let size = budget.check_size(10_000_001).unwrap_err().to_string();
        assert!(
            size.contains("would take more than 10 MB")
                && size.ends_with("raise --memory (MB) if the machine has it to give"),
            "{size}"
        );
        let late = Budget::search(Duration::ZERO, 10.0);
        std::thread::sleep(Duration::from_millis(2));
        let time = late.check().unwrap_err().to_string();
        assert!(time.ends_with("raise --budget to search longer"), "{time}");
        // The default cap is the default memory's.
        assert_eq!(
            Budget::search(Duration::from_secs(1), DEFAULT_LAYER_MEMORY_MB as f64).max_layer_bytes,
            MAX_LAYER_BYTES
        );
        let default = Budget::default().check_size(MAX_LAYER_BYTES + 1);
        assert!(default
            .unwrap_err()
            .to_string()
            .starts_with("too large: its layer constraints would take more than 2000 MB"),);
        // The estimate adds each part's memory, and saturates rather than wraps.
        assert_eq!(
            layer_bytes(2, 3, 5, 2),
            2 * BYTES_PER_PAIR + 3 * BYTES_PER_CONSTRAINT + 5 * (6 + BYTES_PER_TRIPLE_FOUND)
        );
        assert_eq!(layer_bytes(usize::MAX, 1, 1, 4), usize::MAX);
    }
}
