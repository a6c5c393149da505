//! The job as the sender sees it: its commands with where the pen ends after each, the
//! tool state in force at any offset, and the journal of what the plotter confirmed.

use crate::output::hpgl::Interpreter;
use std::path::{Path, PathBuf};

/// The journal kept beside a job.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Journal {
    /// FNV-1a hash of the job, so a journal is only used for its own job.
    pub job_hash: u64,
    /// Job length.
    pub job_len: usize,
    /// Bytes confirmed received.
    pub received: usize,
    /// Bytes confirmed drawn.
    pub drawn: usize,
    /// Bytes handed to the port (some may not have arrived).
    pub sent: usize,
    /// Whether the job finished.
    pub done: bool,
}

/// The journal's path for a job file.
pub fn journal_path(job: &Path) -> PathBuf {
    let mut name = job.file_name().unwrap_or_default().to_os_string();
    name.push(".journal");
    job.with_file_name(name)
}

/// The journal of an unfinished plot of this very job, if one lies beside it: a plain
/// `plot` must not start it again from byte 0 (everything drawn would be cut twice).
pub fn unfinished(job: &[u8], job_path: &Path) -> Option<Journal> {
    let text = std::fs::read_to_string(journal_path(job_path)).ok()?;
    let journal: Journal = serde_json::from_str(&text).ok()?;
    (journal.job_hash == hash(job) && journal.job_len == job.len() && !journal.done)
        .then_some(journal)
}

pub(crate) fn hash(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf29ce484222325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x100000001b3)
    })
}

/// One command of the job: where it ends in the file and where the pen is afterwards.
pub(crate) struct Command {
    pub(crate) end: usize,
    pub(crate) position: [i64; 2],
    pub(crate) moves: bool,
}

pub(crate) fn commands(job: &[u8]) -> Vec<Command> {
    let mut out = Vec::new();
    let mut plotter = Interpreter::new();
    let mut start = 0;
    for (i, &b) in job.iter().enumerate() {
        if b == b';' {
            let text = String::from_utf8_lossy(&job[start..i]);
            let before = plotter.state().0;
            let _ = plotter.execute(&text);
            let name = text.trim().get(..2).unwrap_or("").to_ascii_uppercase();
            out.push(Command {
                end: i + 1,
                position: plotter.state().0,
                moves: matches!(name.as_str(), "PU" | "PD" | "PA" | "PR")
                    && plotter.state().0 != before,
            });
            start = i + 1;
        }
    }
    out
}

/// Tool-state commands (SP, VS, FS) in force after byte `upto` of the job.
pub(crate) fn tool_state(job: &[u8], upto: usize) -> String {
    let text = String::from_utf8_lossy(&job[..upto]);
    let mut state: Vec<(String, String)> = Vec::new();
    for cmd in text.split(';') {
        let c = cmd.trim();
        let name = c.get(..2).unwrap_or("").to_ascii_uppercase();
        if matches!(name.as_str(), "SP" | "VS" | "FS") {
            state.retain(|(n, _)| *n != name);
            state.push((name, c.to_string()));
        }
    }
    state.into_iter().map(|(_, c)| c + ";").collect()
}

/// Saves the journal through a temporary file, so a crash never leaves half of one.
pub(crate) fn save_journal(path: &Path, journal: &Journal) {
    let text = serde_json::to_string(journal).expect("journal serialises");
    let _ = crate::io::write_atomic(path, text.as_bytes());
}
