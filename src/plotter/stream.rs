//! Streaming an HP-GL job to a plotter over a serial port without losing a byte.
//!
//! Progress counts what the plotter has confirmed, never what was handed to the kernel: a
//! reply to a query confirms every byte sent before the query. ESC.B (answered on receipt)
//! confirms bytes received; OA; (answered when executed) confirms bytes drawn. Both are
//! kept in a journal beside the job, which `--resume` uses to continue after a pulled cable
//! or a power cut without drawing a segment twice or skipping one.

use super::journal::{commands, hash, save_journal, tool_state};
pub use super::journal::{journal_path, unfinished, Journal};
use serialport::{FlowControl, TTYPort};
use std::io::{ErrorKind, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How the sender respects the plotter's buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlowMode {
    /// The port's XON/XOFF.
    XonXoff,
    /// The port's RTS/CTS.
    RtsCts,
    /// Ask ESC.B for free space, send at most that minus a margin.
    Query,
    /// No line flow control: send half a buffer, wait for OA; to come back, repeat.
    None,
}

impl FlowMode {
    /// Parses xonxoff, rtscts, query, none.
    pub fn parse(s: &str) -> Result<FlowMode, String> {
        match s {
            "xonxoff" => Ok(FlowMode::XonXoff),
            "rtscts" => Ok(FlowMode::RtsCts),
            "query" => Ok(FlowMode::Query),
            "none" => Ok(FlowMode::None),
            _ => Err(format!(
                "unknown flow control \"{s}\" (xonxoff, rtscts, query, none)"
            )),
        }
    }
}

/// Streaming settings.
#[derive(Clone, Debug)]
pub struct StreamOptions {
    /// Serial port path.
    pub port: PathBuf,
    /// Line speed.
    pub baud: u32,
    /// Flow control.
    pub flow: FlowMode,
    /// The plotter's buffer size (bytes), from the machine profile.
    pub buffer: usize,
    /// Continue a job from its journal.
    pub resume: bool,
    /// How long a silent plotter is given before it counts as not answering (on top of
    /// the time the bytes in flight need on the line).
    pub answer_timeout: Duration,
}

/// What went wrong while plotting. The journal is kept in every case.
#[derive(Debug, thiserror::Error)]
pub enum StreamError {
    /// The port could not be opened (exit 2).
    #[error("cannot open {port}: {cause}")]
    Open {
        /// The port.
        port: String,
        /// Why.
        cause: String,
    },
    /// A bad option (exit 2).
    #[error("{0}")]
    Input(String),
    /// The port went away mid-job.
    #[error("the port {port} disappeared after {confirmed} confirmed bytes ({cause}); run again with --resume when it is back")]
    Vanished {
        /// The port.
        port: String,
        /// Bytes confirmed received.
        confirmed: usize,
        /// The system's words.
        cause: String,
    },
    /// The plotter stopped answering.
    #[error("the plotter stopped answering (no reply to {query} within {seconds:.0} s) after {confirmed} confirmed bytes; check paper and power, then --resume")]
    Silent {
        /// Which query.
        query: String,
        /// How long we waited.
        seconds: f64,
        /// Bytes confirmed.
        confirmed: usize,
    },
    /// The plotter reported an error.
    #[error("the plotter reports error {code} ({meaning}); the journal is kept for --resume")]
    Plotter {
        /// ESC.E code.
        code: u32,
        /// What it means.
        meaning: &'static str,
    },
    /// Ctrl-C.
    #[error(
        "stopped by the user after {confirmed} confirmed bytes; the pen is up; --resume continues"
    )]
    Interrupted {
        /// Bytes confirmed.
        confirmed: usize,
    },
}

impl StreamError {
    /// Bad input rather than a failure on the way (exit 2 vs 1).
    pub fn is_input_error(&self) -> bool {
        matches!(self, StreamError::Open { .. } | StreamError::Input(_))
    }
}

/// Standard baud rates; anything else is refused before opening the port.
pub const BAUD_RATES: [u32; 13] = [
    300, 600, 1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600,
];

/// Progress as the plotter confirms it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Progress {
    /// Bytes of the job the plotter confirmed receiving.
    pub confirmed: usize,
    /// Bytes of the job the plotter confirmed drawing.
    pub drawn: usize,
    /// Job length.
    pub total: usize,
    /// Commands confirmed received.
    pub commands: usize,
}

struct Link {
    port: TTYPort,
    name: String,
}

impl Link {
    fn vanished(&self, confirmed: usize, e: impl std::fmt::Display) -> StreamError {
        StreamError::Vanished {
            port: self.name.clone(),
            confirmed,
            cause: e.to_string(),
        }
    }

    /// Writes everything, waiting out flow-control stops (a stopped port times out).
    fn send(
        &mut self,
        bytes: &[u8],
        confirmed: usize,
        interrupted: &AtomicBool,
    ) -> Result<(), StreamError> {
        let mut rest = bytes;
        while !rest.is_empty() {
            if interrupted.load(Ordering::SeqCst) {
                return Err(StreamError::Interrupted { confirmed });
            }
            match self.port.write(rest) {
                Ok(0) => std::thread::sleep(Duration::from_millis(2)),
                Ok(n) => rest = &rest[n..],
                Err(e)
                    if e.kind() == ErrorKind::TimedOut
                        || e.kind() == ErrorKind::WouldBlock
                        || e.kind() == ErrorKind::Interrupted => {}
                Err(e) => return Err(self.vanished(confirmed, e)),
            }
        }
        Ok(())
    }

    /// Reads one reply (up to CR), skipping flow-control bytes.
    fn reply(
        &mut self,
        query: &str,
        wait: Duration,
        confirmed: usize,
    ) -> Result<String, StreamError> {
        let start = Instant::now();
        let mut text = Vec::new();
        let mut byte = [0u8; 1];
        loop {
            if start.elapsed() > wait {
                return Err(StreamError::Silent {
                    query: query.to_string(),
                    seconds: wait.as_secs_f64(),
                    confirmed,
                });
            }
            match self.port.read(&mut byte) {
                Ok(0) => {}
                Ok(_) => match byte[0] {
                    b'\r' => return Ok(String::from_utf8_lossy(&text).trim().to_string()),
                    0x11 | 0x13 | b'\n' => {}
                    b => text.push(b),
                },
                Err(e)
                    if e.kind() == ErrorKind::TimedOut
                        || e.kind() == ErrorKind::WouldBlock
                        || e.kind() == ErrorKind::Interrupted => {}
                Err(e) => return Err(self.vanished(confirmed, e)),
            }
        }
    }
}

/// Opens the port with the flow control asked for. Errors name the port and say why.
fn open(options: &StreamOptions) -> Result<Link, StreamError> {
    let name = options.port.display().to_string();
    if !BAUD_RATES.contains(&options.baud) {
        return Err(StreamError::Input(format!(
            "{} is not a serial speed (use one of {})",
            options.baud,
            BAUD_RATES.map(|b| b.to_string()).join(", ")
        )));
    }
    let flow = match options.flow {
        FlowMode::XonXoff => FlowControl::Software,
        FlowMode::RtsCts => FlowControl::Hardware,
        FlowMode::Query | FlowMode::None => FlowControl::None,
    };
    let port = serialport::new(name.clone(), options.baud)
        .flow_control(flow)
        .timeout(Duration::from_millis(50))
        .open_native()
        .map_err(|e| StreamError::Open {
            port: name.clone(),
            cause: {
                let text = e.to_string();
                let lower = text.to_lowercase();
                // serialport reports an exclusively held port as "no device" with the
                // system's words; tell the two apart by what the system said.
                if lower.contains("busy")
                    || lower.contains("lock")
                    || lower.contains("resource temporarily")
                {
                    format!("the port is busy: another program has it open ({text})")
                } else if !Path::new(&name).exists()
                    || matches!(e.kind(), serialport::ErrorKind::Io(ErrorKind::NotFound))
                {
                    "no such port (is the plotter plugged in?)".to_string()
                } else {
                    text
                }
            },
        })?;
    Ok(Link { port, name })
}

/// What a finished job did.
#[derive(Clone, Debug, PartialEq)]
pub struct StreamReport {
    /// Bytes sent in this run.
    pub sent: usize,
    /// Where this run started in the job (0 unless resumed).
    pub resumed_from: usize,
    /// A note on how the resume point was found.
    pub resume_note: Option<String>,
    /// Wall time.
    pub elapsed: Duration,
}

/// Streams `job` (HP-GL bytes of the file at `job_path`) to the plotter.
pub fn stream(
    job: &[u8],
    job_path: &Path,
    options: &StreamOptions,
    progress: &mut dyn FnMut(Progress),
    interrupted: &AtomicBool,
) -> Result<StreamReport, StreamError> {
    let started = Instant::now();
    let journal_file = journal_path(job_path);
    let mut journal = Journal {
        job_hash: hash(job),
        job_len: job.len(),
        ..Default::default()
    };
    let cmds = commands(job);
    let mut link = open(options)?;
    let line_rate = options.baud as f64 / 10.0;
    let wait =
        |bytes: usize| options.answer_timeout + Duration::from_secs_f64(bytes as f64 / line_rate);
    let mut start = 0usize;
    let mut resume_note = None;
    let mut preamble = Vec::new();
    if options.resume {
        let old: Journal = std::fs::read_to_string(&journal_file)
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok())
            .ok_or_else(|| {
                StreamError::Input(format!(
                    "no journal for this job at {}; nothing to resume",
                    journal_file.display()
                ))
            })?;
        if old.job_hash != journal.job_hash {
            return Err(StreamError::Input(format!(
                "{} belongs to another job; nothing to resume",
                journal_file.display()
            )));
        }
        journal = old.clone();
        // Drop any half-received command, then ask where the pen is.
        link.send(b"\x1b.K", journal.received, interrupted)?;
        link.send(b"OA;", journal.received, interrupted)?;
        let at = link.reply("OA;", wait(64), journal.received)?;
        let xy: Vec<i64> = at
            .split(',')
            .filter_map(|v| v.trim().parse().ok())
            .collect();
        // A powered plotter executes every complete command it received, and it received
        // at least what it confirmed and at most what was sent; its buffer can hold back no
        // more than `buffer` bytes of that.
        let low = old.received.max(old.drawn).saturating_sub(options.buffer);
        let high = old.sent.max(old.received);
        let found = if xy.len() >= 2 {
            cmds.iter()
                .enumerate()
                .filter(|(_, c)| c.end > low && c.end <= high)
                .find(|(_, c)| c.moves && c.position == [xy[0], xy[1]])
                .map(|(i, _)| i)
        } else {
            None
        };
        match found {
            Some(i) => {
                start = cmds[i].end;
                preamble = tool_state(job, start).into_bytes();
                resume_note = Some(format!(
                    "the plotter is at {},{}: the end of command {} of {}; continuing with the next",
                    xy[0],
                    xy[1],
                    i + 1,
                    cmds.len()
                ));
            }
            None => {
                // A plotter that was reset cannot say: start again after the last command it
                // confirmed drawing, from a known state, with a pen-up move there.
                let k = cmds.iter().rposition(|c| c.end <= old.drawn);
                start = k.map(|k| cmds[k].end).unwrap_or(0);
                let pos = k.map(|k| cmds[k].position).unwrap_or([0, 0]);
                preamble = format!(
                    "IN;{}PA;PU{},{};PR;",
                    tool_state(job, start),
                    pos[0],
                    pos[1]
                )
                .into_bytes();
                resume_note = Some(format!(
                    "the plotter does not know where it was (reset?); resuming after the last command it confirmed drawing ({} of {} bytes)",
                    start,
                    job.len()
                ));
            }
        }
    }
    journal.done = false;
    save_journal(&journal_file, &journal);
    if !preamble.is_empty() {
        link.send(&preamble, journal.received, interrupted)?;
    }
    let mut sent = start;
    let total = job.len();
    let count_commands = |upto: usize| cmds.iter().filter(|c| c.end <= upto).count();
    let mut report = |journal: &Journal| {
        progress(Progress {
            confirmed: journal.received,
            drawn: journal.drawn,
            total,
            commands: count_commands(journal.received),
        })
    };
    let query_margin = 32usize.min(options.buffer / 4);
    let mut since_query = 0usize;
    while sent < total {
        if interrupted.load(Ordering::SeqCst) {
            let _ = link.send(b"\x1b.KPU;", journal.received, &AtomicBool::new(false));
            save_journal(&journal_file, &journal);
            return Err(StreamError::Interrupted {
                confirmed: journal.received,
            });
        }
        let result = (|| -> Result<(), StreamError> {
            match options.flow {
                FlowMode::Query => {
                    link.send(b"\x1b.B", journal.received, interrupted)?;
                    let free: usize = link
                        .reply("ESC.B", wait(0), journal.received)?
                        .parse()
                        .unwrap_or(0);
                    journal.received = sent;
                    let room = free.saturating_sub(query_margin);
                    if room == 0 {
                        std::thread::sleep(Duration::from_millis(20));
                        return Ok(());
                    }
                    let n = room.min(total - sent);
                    journal.sent = sent + n;
                    link.send(&job[sent..sent + n], journal.received, interrupted)?;
                    sent += n;
                }
                FlowMode::None => {
                    // Whole commands only: the OA; that follows must not join a half one.
                    let limit = (options.buffer / 2).min(total - sent);
                    let n = job[sent..sent + limit]
                        .iter()
                        .rposition(|&b| b == b';')
                        .map(|i| i + 1)
                        .or_else(|| job[sent..].iter().position(|&b| b == b';').map(|i| i + 1))
                        .unwrap_or(total - sent);
                    journal.sent = sent + n;
                    link.send(&job[sent..sent + n], journal.received, interrupted)?;
                    sent += n;
                    // OA; is answered when executed: the half buffer has been drawn.
                    link.send(b"OA;", journal.received, interrupted)?;
                    link.reply(
                        "OA;",
                        wait(options.buffer) + Duration::from_secs(60),
                        journal.received,
                    )?;
                    journal.received = sent;
                    journal.drawn = sent;
                }
                FlowMode::XonXoff | FlowMode::RtsCts => {
                    // Small writes, so a stop takes effect within a few bytes of ours.
                    let n = 64.min(total - sent);
                    journal.sent = sent + n;
                    link.send(&job[sent..sent + n], journal.received, interrupted)?;
                    sent += n;
                    since_query += n;
                    if since_query >= options.buffer / 2 || sent == total {
                        since_query = 0;
                        link.send(b"\x1b.B", journal.received, interrupted)?;
                        link.reply("ESC.B", wait(options.buffer * 4), journal.received)?;
                        journal.received = sent;
                    }
                }
            }
            Ok(())
        })();
        if let Err(e) = result {
            save_journal(&journal_file, &journal);
            return Err(e);
        }
        save_journal(&journal_file, &journal);
        report(&journal);
    }
    // Everything is sent: wait until it is drawn, then ask for errors.
    let finish = (|| -> Result<(), StreamError> {
        link.send(b"OA;", journal.received, interrupted)?;
        link.reply(
            "OA;",
            wait(options.buffer * 2) + Duration::from_secs(120),
            journal.received,
        )?;
        journal.received = total;
        journal.drawn = total;
        link.send(b"\x1b.E", journal.received, interrupted)?;
        let code: u32 = link
            .reply("ESC.E", wait(0), journal.received)?
            .parse()
            .unwrap_or(0);
        if code != 0 {
            return Err(StreamError::Plotter {
                code,
                meaning: match code {
                    10 => "overlapping output instructions",
                    11 => "invalid byte after ESC",
                    12 => "invalid byte in a device-control instruction",
                    13 => "parameter out of range",
                    14 => "too many parameters",
                    15 => "framing, parity or overrun error",
                    16 => "input buffer overflow: bytes were lost",
                    _ => "see the plotter's manual",
                },
            });
        }
        Ok(())
    })();
    if let Err(e) = finish {
        save_journal(&journal_file, &journal);
        return Err(e);
    }
    journal.done = true;
    save_journal(&journal_file, &journal);
    report(&journal);
    Ok(StreamReport {
        sent: total - start,
        resumed_from: start,
        resume_note,
        elapsed: started.elapsed(),
    })
}
