//! The job as the sender sees it: its commands with where the pen ends after each, the
//! tool state in force at any offset, and the journal of what the plotter confirmed.

use super::Language;
use crate::output::gpgl;
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

/// The job's commands, run through an interpreter of its language.
pub(crate) fn commands(job: &[u8], language: Language) -> Vec<Command> {
    let mut out = Vec::new();
    let mut hpgl = Interpreter::new();
    let mut gpgl = gpgl::Interpreter::new();
    let mut start = 0;
    let end = language.terminator();
    for (i, &b) in job.iter().enumerate() {
        if b != end {
            continue;
        }
        let raw = String::from_utf8_lossy(&job[start..i]);
        let text = raw.trim_start_matches(gpgl::RESET).trim();
        let (before, after) = match language {
            Language::Hpgl => {
                let before = hpgl.state().0;
                let _ = hpgl.execute(text);
                (before, hpgl.state().0)
            }
            Language::Gpgl => {
                let before = gpgl.state().0;
                let _ = gpgl.execute(text);
                (before, gpgl.state().0)
            }
        };
        let moving = matches!(
            command_name(text, language).as_str(),
            "PU" | "PD" | "PA" | "PR" | "M" | "D" | "H"
        );
        out.push(Command {
            end: i + 1,
            position: after,
            moves: moving && after != before,
        });
        start = i + 1;
    }
    out
}

/// The commands that set the plotter up and pick its tool, last of each kind, in force
/// after byte `upto` of the job: HP-GL's SP, VS and FS; GP-GL's orientation, origin,
/// limits, tool holder, speed, pressure and blade offset.
pub(crate) fn tool_state(job: &[u8], upto: usize, language: Language) -> String {
    let text = String::from_utf8_lossy(&job[..upto]);
    let end = language.terminator() as char;
    let mut state: Vec<(String, String)> = Vec::new();
    for cmd in text.split(end) {
        let c = cmd.trim_start_matches(gpgl::RESET).trim();
        let name = command_name(c, language);
        let keep = match language {
            Language::Hpgl => ["SP", "VS", "FS"].contains(&name.as_str()),
            Language::Gpgl => {
                ["FN", "\\", "Z", "TB", "FE", "J", "!", "FX", "FC"].contains(&name.as_str())
            }
        };
        if keep {
            // Each TB setting (mark mode, mark type, size, the search) is its own: a
            // registered job resumes by finding its marks again.
            let name = if name == "TB" {
                c.split(',').next().unwrap_or(c).to_string()
            } else {
                name
            };
            state.retain(|(n, _)| *n != name);
            state.push((name, c.to_string()));
        }
    }
    state
        .into_iter()
        .map(|(_, c)| format!("{c}{end}"))
        .collect()
}

/// A command's name: HP-GL's two letters (upper case), GP-GL's one or two characters.
fn command_name(cmd: &str, language: Language) -> String {
    match language {
        Language::Hpgl => cmd.get(..2).unwrap_or("").to_ascii_uppercase(),
        Language::Gpgl => gpgl::command_name(cmd).to_string(),
    }
}

/// Saves the journal through a temporary file, so a crash never leaves half of one.
pub(crate) fn save_journal(path: &Path, journal: &Journal) {
    let text = serde_json::to_string(journal).expect("journal serialises");
    let _ = crate::io::write_atomic(path, text.as_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_registered_gpgl_job_resumes_by_searching_for_its_marks_again() {
        // Every TB setting is kept, in order, and the last of each other setting: a
        // cutter reset for the resume finds the marks before it cuts on.
        let job = "\u{1b}\u{4}FN0\u{3}TB50,0\u{3}TB99\u{3}TB52,2\u{3}TB123,4600,3600,200,100\u{3}\\0,0\u{3}Z4600,3600\u{3}J1\u{3}FX20\u{3}M10,10\u{3}D20,20\u{3}FX8\u{3}";
        let state = tool_state(job.as_bytes(), job.len(), Language::Gpgl);
        assert_eq!(
            state,
            "FN0\u{3}TB50,0\u{3}TB99\u{3}TB52,2\u{3}TB123,4600,3600,200,100\u{3}\\0,0\u{3}Z4600,3600\u{3}J1\u{3}FX8\u{3}"
        );
    }
}
