//! Streaming an HP-GL or GP-GL job to a plotter over a serial port without losing a byte.
//!
//! Progress counts what the plotter has confirmed, never what was handed to the kernel: a
//! reply to a query confirms every byte sent before the query. In HP-GL, ESC.B (answered
//! on receipt) confirms bytes received, and an `OA;` left in the stream every quarter
//! buffer (answered when executed) confirms bytes drawn without stopping the flow. In
//! GP-GL, which has no position query, the job goes in chunks of whole commands and the
//! next chunk follows when `ESC ENQ` says the cutter is ready, so every chunk boundary is
//! confirmed drawn. Both are kept in a journal beside the job, which `--resume` uses to
//! continue after a pulled cable or a power cut.

use super::journal::{commands, hash, save_journal};
pub use super::journal::{journal_path, unfinished, Journal};
pub use super::line::{FlowMode, Progress, StreamError, StreamOptions, StreamReport, BAUD_RATES};
use super::link::open;
use super::session::Session;
use super::Language;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// The journal of the job at `journal_file`, for `--resume`.
fn journal_to_resume(journal_file: &Path, job_hash: u64) -> Result<Journal, StreamError> {
    let old: Journal = std::fs::read_to_string(journal_file)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .ok_or_else(|| {
            StreamError::Input(format!(
                "no journal for this job at {}; nothing to resume",
                journal_file.display()
            ))
        })?;
    if old.job_hash != job_hash {
        return Err(StreamError::Input(format!(
            "{} belongs to another job; nothing to resume",
            journal_file.display()
        )));
    }
    // A finished job has no last command to resend: resending it would cut it twice.
    if old.done {
        return Err(StreamError::Input(format!(
            "the job was already complete ({} of {} bytes drawn, says {}); nothing to resume (plot it without --resume to cut another sheet)",
            old.drawn.max(old.received),
            old.job_len,
            journal_file.display()
        )));
    }
    Ok(old)
}

/// Streams `job` (the bytes of the file at `job_path`) to the plotter.
pub fn stream(
    job: &[u8],
    job_path: &Path,
    options: &StreamOptions,
    progress: &mut dyn FnMut(Progress),
    interrupted: &AtomicBool,
) -> Result<StreamReport, StreamError> {
    let started = Instant::now();
    if options.language == Language::Gpgl && options.flow == FlowMode::Query {
        return Err(StreamError::Input(
            "flow control \"query\" is HP-GL's ESC.B handshake; a GP-GL cutter uses rtscts, xonxoff or none".into(),
        ));
    }
    let journal_file = journal_path(job_path);
    let journal = Journal {
        job_hash: hash(job),
        job_len: job.len(),
        ..Default::default()
    };
    let old = if options.resume {
        Some(journal_to_resume(&journal_file, journal.job_hash)?)
    } else {
        None
    };
    let mut session = Session {
        job,
        cmds: commands(job, options.language),
        options,
        link: open(options)?,
        journal,
        journal_file,
        sent: 0,
        since_mark: 0,
        since_check: 0,
        interrupted,
    };
    let run = |session: &mut Session, progress: &mut dyn FnMut(Progress)| {
        let note = match &old {
            Some(old) => Some(session.resume_from(old)?),
            None => None,
        };
        session.send_rest(progress)?;
        Ok(note)
    };
    match run(&mut session, progress) {
        Ok(note) => Ok(StreamReport {
            sent: job.len() - note.as_ref().map_or(0, |n| n.0),
            resumed_from: note.as_ref().map_or(0, |n| n.0),
            resume_note: note.map(|n| n.1),
            elapsed: started.elapsed(),
        }),
        Err(e) => {
            session.journal.drawn = session.journal.drawn.max(session.link.drawn);
            save_journal(&session.journal_file, &session.journal);
            Err(e)
        }
    }
}
