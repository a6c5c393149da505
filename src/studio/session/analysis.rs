//! Verification and the crease pattern, computed beside the solver on a thread of their
//! own: at 10k vertices they cost as much as a solver step, and the session thread should
//! spend its core on steps. The session hands over a copy of the design whenever the last
//! analysis is done and the design has moved on; during a drag the verdict therefore lags
//! the form by at most one analysis, and at rest it is exact.

use super::super::frame;
use crate::constraints::ConstraintSet;
use crate::fab::{self, Report, Tolerances};
use crate::mesh::Mesh;
use crate::pipeline;
use std::sync::mpsc::{self, Receiver, Sender, TryRecvError};

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

/// Verifies the design (as `verify` would the saved file: fold angles recorded first) and,
/// when asked, lays out its crease pattern and flat-folded state.
pub fn analyse(job: Job) -> Analysis {
    let Job {
        mut mesh,
        set,
        relaid,
        with_pattern,
        stamp,
    } = job;
    pipeline::record_fold_angles(&mut mesh);
    let report = fab::verify(&mesh, Some(&set), Tolerances::default());
    let pattern_json = with_pattern.then(|| {
        let pattern = match (relaid, mesh.flat()) {
            (false, Some(f)) => Some(f.to_vec()),
            _ => fab::unfold(&mesh).ok(),
        };
        frame::pattern_json(&mesh, pattern.as_deref())
    });
    Analysis {
        report,
        pattern_json,
        stamp,
    }
}

/// The analysis thread, and whether it is working.
pub struct Analyst {
    jobs: Sender<Job>,
    results: Receiver<Analysis>,
    busy: bool,
}

impl Analyst {
    /// Starts the thread; it ends when the analyst is dropped.
    pub fn start() -> Analyst {
        let (jobs, inbox) = mpsc::channel::<Job>();
        let (outbox, results) = mpsc::channel();
        std::thread::Builder::new()
            .name("studio-analysis".into())
            .spawn(move || {
                for job in inbox {
                    if outbox.send(analyse(job)).is_err() {
                        return;
                    }
                }
            })
            .expect("the analysis thread starts");
        Analyst {
            jobs,
            results,
            busy: false,
        }
    }

    /// An analysis is under way.
    pub fn busy(&self) -> bool {
        self.busy
    }

    /// Starts analysing `job`.
    pub fn send(&mut self, job: Job) {
        self.busy = self.jobs.send(job).is_ok();
    }

    /// The finished analysis, if there is one.
    pub fn collect(&mut self) -> Option<Analysis> {
        match self.results.try_recv() {
            Ok(a) => {
                self.busy = false;
                Some(a)
            }
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => {
                self.busy = false;
                None
            }
        }
    }
}
