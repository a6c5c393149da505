//! Verification and the crease pattern, computed beside the solver on a thread of their
//! own: at 10k vertices they cost as much as a solver step, and the session thread should
//! spend its core on steps. The session hands over a copy of the design whenever the last
//! analysis is done and the design has moved on; during a drag the verdict therefore lags
//! the form by at most one analysis, and at rest it is exact.

use super::super::frame;
use crate::constraints::ConstraintSet;
use crate::fab::{self, Budget, Report, Tolerances};
use crate::geometry::unfold::{sheet_of, PatternFrom};
use crate::mesh::Mesh;
use crate::pipeline;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, Sender, TryRecvError};
use std::sync::Arc;
use std::time::Duration;

/// How long the analysis of one design may judge its layer order: past it, the pane
/// says the design is too large for live analysis instead of holding up the next one.
pub const LIVE_BUDGET: Duration = Duration::from_secs(2);

/// What the panes say when the budget runs out.
pub const LIVE_ADVICE: &str =
    "too large for live analysis: run `crease verify` on the saved design";

/// Which design an analysis describes: the positions and topology versions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stamp {
    /// Positions version.
    pub positions: u64,
    /// Topology version.
    pub topology: u64,
}

/// A design to analyse.
pub struct Job {
    /// The design, with the positions to analyse.
    pub mesh: Mesh,
    /// The conditions in force.
    pub set: ConstraintSet,
    /// Lay the crease pattern out anew (design mode changed lengths).
    pub relaid: bool,
    /// Build the crease pattern and x-ray too (they are heavy; a drag asks less often).
    pub with_pattern: bool,
    /// Which design this is.
    pub stamp: Stamp,
}

/// What an analysis found.
pub struct Analysis {
    /// The verification report.
    pub report: Report,
    /// The crease-pattern part of a frame, when asked for.
    pub pattern_json: Option<String>,
    /// Which design it describes.
    pub stamp: Stamp,
}

/// Verifies the design (as `verify` would the saved file: fold angles recorded first)
/// within the job's time and `cancel`, and, when asked, lays out its crease pattern and
/// flat-folded state.
fn analyse(job: Job, cancel: Arc<AtomicBool>) -> Analysis {
    let Job {
        mut mesh,
        set,
        relaid,
        with_pattern,
        stamp,
    } = job;
    pipeline::record_fold_angles(&mut mesh);
    let budget = Budget::live(LIVE_BUDGET, cancel, LIVE_ADVICE);
    let report = fab::verify_within(&mesh, Some(&set), Tolerances::default(), &budget);
    let pattern_json = with_pattern.then(|| {
        // Design mode changed lengths: the stored crease pattern no longer describes it.
        let from = if relaid {
            PatternFrom::Form
        } else {
            PatternFrom::Stored
        };
        match sheet_of(&mesh, from) {
            Ok(strip) if mesh.is_tube() => frame::strip_pattern_json(&strip),
            Ok(sheet) => frame::pattern_json(&mesh, sheet.crease_pattern()),
            Err(_) => frame::pattern_json(&mesh, None),
        }
    });
    Analysis {
        report,
        pattern_json,
        stamp,
    }
}

/// The analysis thread, and which design it is working on.
pub struct Analyst {
    jobs: Sender<(Job, Arc<AtomicBool>)>,
    results: Receiver<Analysis>,
    /// The design under analysis and the flag that cancels it.
    working: Option<(Stamp, Arc<AtomicBool>)>,
}

impl Analyst {
    /// Starts the thread; it ends when the analyst is dropped.
    pub fn start() -> Analyst {
        let (jobs, inbox) = mpsc::channel::<(Job, Arc<AtomicBool>)>();
        let (outbox, results) = mpsc::channel();
        std::thread::Builder::new()
            .name("studio-analysis".into())
            .spawn(move || {
                // The analysis's parallel parts (the layer order's triples) get every core
                // but one, which stays with the session thread: the page is answered while
                // a large design is judged.
                let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(cores.saturating_sub(1).max(1))
                    .thread_name(|i| format!("studio-analysis-{i}"))
                    .build()
                    .ok();
                for (job, cancel) in inbox {
                    let analysis = match &pool {
                        Some(pool) => pool.install(|| analyse(job, cancel)),
                        None => analyse(job, cancel),
                    };
                    if outbox.send(analysis).is_err() {
                        return;
                    }
                }
            })
            .expect("the analysis thread starts");
        Analyst {
            jobs,
            results,
            working: None,
        }
    }

    /// An analysis is under way.
    pub fn busy(&self) -> bool {
        self.working.is_some()
    }

    /// Starts analysing `job`.
    pub fn send(&mut self, job: Job) {
        let (stamp, cancel) = (job.stamp, Arc::new(AtomicBool::new(false)));
        self.working = self
            .jobs
            .send((job, Arc::clone(&cancel)))
            .is_ok()
            .then_some((stamp, cancel));
    }

    /// Cancels the analysis under way unless it is of topology `keep` (the design's
    /// positions may move on during a drag; a new design makes it worthless).
    pub fn cancel_unless(&self, keep: u64) {
        if let Some((stamp, cancel)) = &self.working {
            if stamp.topology != keep {
                cancel.store(true, Ordering::Relaxed);
            }
        }
    }

    /// The finished analysis, waiting up to `wait` for it.
    pub fn collect(&mut self, wait: Duration) -> Option<Analysis> {
        let got = if wait.is_zero() {
            self.results
                .try_recv()
                .map_err(|e| e == TryRecvError::Disconnected)
        } else {
            self.results
                .recv_timeout(wait)
                .map_err(|e| e == mpsc::RecvTimeoutError::Disconnected)
        };
        match got {
            Ok(a) => {
                self.working = None;
                Some(a)
            }
            Err(disconnected) => {
                if disconnected {
                    self.working = None;
                }
                None
            }
        }
    }
}
