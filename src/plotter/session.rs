//! One run of the sender over one job: what it sends when, the queries that confirm it,
//! and where a resumed job continues (see [`super::stream`] for the protocol).

use super::journal::{save_journal, tool_state, Command, Journal};
use super::line::{FlowMode, Progress, StreamError, StreamOptions};
use super::link::Link;
use super::Language;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How long a cutter may search for registration marks: inkscape-silhouette allows 40 s.
const MARK_SEARCH_PATIENCE: Duration = Duration::from_secs(40);

/// Where a resumed job continues and what must be sent first to get there.
pub(super) struct ResumePoint {
    pub(super) start: usize,
    pub(super) preamble: Vec<u8>,
    pub(super) note: String,
}

/// One run of the sender over one job.
pub(super) struct Session<'a> {
    pub(super) job: &'a [u8],
    pub(super) cmds: Vec<Command>,
    pub(super) options: &'a StreamOptions,
    pub(super) link: Link,
    pub(super) journal: Journal,
    pub(super) journal_file: PathBuf,
    pub(super) sent: usize,
    /// Job bytes sent since the last drawing mark (HP-GL) or receipt check.
    pub(super) since_mark: usize,
    pub(super) since_check: usize,
    pub(super) interrupted: &'a AtomicBool,
}

impl Session<'_> {
    /// How long a reply may take when `bytes` are ahead of it on the line.
    fn wait(&self, bytes: usize) -> Duration {
        self.options.answer_timeout
            + Duration::from_secs_f64(bytes as f64 / self.options.line_rate())
    }

    /// How long to wait for the plotter to work through `bytes` and answer: the line
    /// time plus two minutes of drawing.
    fn patience(&self, bytes: usize) -> Duration {
        self.wait(bytes) + Duration::from_secs(120)
    }

    /// The last command wholly within the first `drawn` bytes, and where the job goes on
    /// after it.
    fn after_drawn(&self, drawn: usize) -> (Option<usize>, usize) {
        let k = self.cmds.iter().rposition(|c| c.end <= drawn);
        (k, k.map_or(0, |k| self.cmds[k].end))
    }

    /// The end of the last whole command within `max` bytes of `from` (at least one
    /// command, however long), so no query ever lands inside a command.
    fn chunk_end(&self, from: usize, max: usize) -> usize {
        let limit = from + max;
        let i = self.cmds.partition_point(|c| c.end <= limit);
        match i.checked_sub(1).map(|k| self.cmds[k].end) {
            Some(end) if end > from => end,
            _ => self.cmds.get(i).map_or(self.job.len(), |c| c.end),
        }
    }

    /// Job bytes between drawing marks (HP-GL): a sixteenth of the buffer, so a power cut
    /// costs a few segments redrawn, while the marks take under a tenth of the line.
    fn mark_every(&self) -> usize {
        (self.options.buffer / 16).max(32)
    }

    /// Sends the job up to `to` (a command end), with an HP-GL `OA;` after every
    /// `mark_every` bytes whose answer will say that much is drawn.
    fn send_job(&mut self, to: usize) -> Result<(), StreamError> {
        let marking =
            self.options.language == Language::Hpgl && self.options.flow != FlowMode::None;
        let every = self.mark_every();
        while self.sent < to {
            let piece = if marking {
                self.chunk_end(self.sent, every.saturating_sub(self.since_mark).max(1))
                    .min(to)
            } else {
                to
            };
            self.journal.sent = piece;
            let bytes = &self.job[self.sent..piece];
            self.link
                .send(bytes, self.journal.received, self.interrupted)?;
            self.since_mark += piece - self.sent;
            self.since_check += piece - self.sent;
            self.sent = piece;
            if marking && self.since_mark >= every {
                self.since_mark = 0;
                self.link
                    .mark(self.sent, self.journal.received, self.interrupted)?;
            }
        }
        Ok(())
    }

    /// ESC.B: free bytes in the plotter's buffer; its answer confirms all sent before it.
    fn free_space(&mut self) -> Result<usize, StreamError> {
        let before = self.sent;
        self.link
            .send(b"\x1b.B", self.journal.received, self.interrupted)?;
        let wait = self.wait(self.options.buffer * 4);
        let free = self
            .link
            .reply("ESC.B", wait, self.journal.received)?
            .parse()
            .unwrap_or(0);
        self.journal.received = before;
        Ok(free)
    }

    /// ESC ENQ: the cutter's status; its answer confirms all sent before it. Ready (`0`)
    /// means everything received is cut.
    pub(super) fn cutter_status(&mut self) -> Result<char, StreamError> {
        let before = self.sent;
        self.link
            .send(b"\x1b\x05", self.journal.received, self.interrupted)?;
        let wait = self.wait(self.options.buffer * 4);
        let status = self.link.reply("ESC ENQ", wait, self.journal.received)?;
        self.journal.received = before;
        let confirmed = self.journal.received;
        match status.chars().next().unwrap_or('1') {
            '0' => {
                self.journal.drawn = before;
                Ok('0')
            }
            '2' => Err(StreamError::NoMedia { confirmed }),
            '4' => Err(StreamError::Cancelled { confirmed }),
            c => Ok(c),
        }
    }

    /// The end of a registration mark search (`TB123…`) in `job[from..to]`, if there is one.
    fn mark_search_end(&self, from: usize, to: usize) -> Option<usize> {
        let at = mark_search_at(&self.job[from..to])? + from;
        let etx = self.job[at..].iter().position(|&b| b == 0x03)? + at;
        Some(etx + 1)
    }

    /// Waits for the cutter's answer to a mark search: `0` when it found the marks;
    /// anything else stops the job before it cuts.
    fn await_marks_found(&mut self) -> Result<(), StreamError> {
        let confirmed = self.journal.received;
        let answer = self.link.reply(
            "TB123 (the registration mark search)",
            MARK_SEARCH_PATIENCE,
            confirmed,
        )?;
        if answer.trim() != "0" {
            return Err(StreamError::MarksNotFound { answer, confirmed });
        }
        Ok(())
    }

    /// Polls the cutter every 20 ms until it is ready (paused and moving both wait).
    fn until_ready(&mut self, patience: Duration) -> Result<(), StreamError> {
        let start = Instant::now();
        loop {
            if self.interrupted.load(Ordering::SeqCst) {
                return Err(StreamError::Interrupted {
                    confirmed: self.journal.received,
                });
            }
            if self.cutter_status()? == '0' {
                return Ok(());
            }
            if start.elapsed() > patience {
                return Err(StreamError::Silent {
                    query: "ESC ENQ (still not ready)".into(),
                    seconds: patience.as_secs_f64(),
                    confirmed: self.journal.received,
                });
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Sends the next piece of the job the way the flow mode and language allow.
    pub(super) fn step(&mut self) -> Result<(), StreamError> {
        let buffer = self.options.buffer;
        let patience = self.patience(buffer);
        if self.options.language == Language::Gpgl {
            // Chunks of whole commands, each cut before the next goes: a quarter buffer
            // (at most 1 KiB), so a resume cuts little again and the wait is short.
            let end = self.chunk_end(self.sent, (buffer / 4).clamp(16, 1024));
            // The mark search ends its chunk, and its answer is awaited before more goes.
            let search = self.mark_search_end(self.sent, end);
            self.send_job(search.unwrap_or(end))?;
            if search.is_some() {
                self.await_marks_found()?;
            }
            return self.until_ready(patience);
        }
        match self.options.flow {
            FlowMode::Query => {
                let free = self.free_space()?;
                // A margin for the reply's own lag, and room for the drawing marks.
                let every = self.mark_every();
                let room = free.saturating_sub(32.min(buffer / 4) + 3) * every / (every + 3);
                let end = self.chunk_end(self.sent, room.max(1));
                let worth = (buffer / 8).max(16).min(self.job.len() - self.sent);
                if end - self.sent > room || room < worth {
                    // Too little room to be worth a round trip: let the plotter draw.
                    std::thread::sleep(Duration::from_millis(10));
                    return Ok(());
                }
                self.send_job(end)
            }
            FlowMode::None => {
                // No flow control: half a buffer, then wait for an OA; to come back.
                let end = self.chunk_end(self.sent, buffer / 2);
                self.send_job(end)?;
                self.link
                    .mark(self.sent, self.journal.received, self.interrupted)?;
                self.link.await_marks(patience, self.journal.received)?;
                self.journal.received = self.sent;
                Ok(())
            }
            FlowMode::XonXoff | FlowMode::RtsCts => {
                // Small writes, so a stop takes effect within a few bytes of ours.
                let end = self.chunk_end(self.sent, 64);
                self.send_job(end)?;
                if self.since_check >= buffer / 2 || self.sent == self.job.len() {
                    self.since_check = 0;
                    self.free_space()?;
                }
                Ok(())
            }
        }
    }

    /// Takes in drawing marks answered so far, saves the journal and reports.
    pub(super) fn settle(&mut self, progress: &mut dyn FnMut(Progress)) -> Result<(), StreamError> {
        self.link.poll(self.journal.received)?;
        self.journal.drawn = self.journal.drawn.max(self.link.drawn);
        save_journal(&self.journal_file, &self.journal);
        let received = self.journal.received;
        progress(Progress {
            confirmed: received,
            drawn: self.journal.drawn,
            total: self.job.len(),
            commands: self.cmds.partition_point(|c| c.end <= received),
        });
        Ok(())
    }

    /// Everything is sent: wait until it is drawn, then ask for errors.
    pub(super) fn finish(&mut self) -> Result<(), StreamError> {
        let total = self.job.len();
        let patience = self.patience(self.options.buffer * 2);
        if self.options.language == Language::Gpgl {
            return self.until_ready(patience);
        }
        self.link
            .mark(total, self.journal.received, self.interrupted)?;
        self.link.await_marks(patience, self.journal.received)?;
        self.journal.received = total;
        self.journal.drawn = total;
        self.link
            .send(b"\x1b.E", self.journal.received, self.interrupted)?;
        let code: u32 = self
            .link
            .reply("ESC.E", self.wait(0), self.journal.received)?
            .parse()
            .unwrap_or(0);
        if code != 0 {
            return Err(StreamError::Plotter {
                code,
                meaning: hpgl_error_meaning(code),
            });
        }
        Ok(())
    }

    /// Takes up the journal of an interrupted run: sends what puts the plotter where the
    /// job goes on, and returns that place with a note saying how it was chosen.
    pub(super) fn resume_from(&mut self, old: &Journal) -> Result<(usize, String), StreamError> {
        self.journal = old.clone();
        let point = self.resume_point(old)?;
        self.sent = point.start;
        self.link.drawn = old.drawn;
        let received = self.journal.received;
        self.link
            .send(&point.preamble, received, self.interrupted)?;
        if mark_search_at(&point.preamble).is_some() {
            self.await_marks_found()?;
        }
        Ok((point.start, point.note))
    }

    /// Sends the job from where the session stands to its end and waits until the
    /// plotter confirms it; an interruption lifts the pen first, so nothing is cut twice
    /// when the job is resumed.
    pub(super) fn send_rest(
        &mut self,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<(), StreamError> {
        self.journal.done = false;
        save_journal(&self.journal_file, &self.journal);
        if self.options.language == Language::Gpgl && self.sent == 0 {
            // No media, or a job cancelled on the panel, is said before the first cut.
            self.cutter_status()?;
        }
        while self.sent < self.job.len() {
            if self.interrupted.load(Ordering::SeqCst) {
                let lift: &[u8] = match self.options.language {
                    Language::Hpgl => b"\x1b.KPU;",
                    Language::Gpgl => b"\x1b\x04",
                };
                let _ = self.link.send(lift, 0, &AtomicBool::new(false));
                return Err(StreamError::Interrupted {
                    confirmed: self.journal.received,
                });
            }
            self.step()?;
            self.settle(progress)?;
        }
        self.finish()?;
        self.journal.done = true;
        self.settle(progress)
    }

    /// Where to continue an interrupted job, from its journal and what the plotter says.
    pub(super) fn resume_point(&mut self, old: &Journal) -> Result<ResumePoint, StreamError> {
        match self.options.language {
            Language::Hpgl => self.hpgl_resume_point(old),
            Language::Gpgl => {
                // GP-GL cannot say where the knife is. Let the cutter finish what it holds,
                // then go on after the last chunk it reported cut, from a reset and the
                // job's own set-up: at most one chunk is cut again, nothing is skipped.
                self.until_ready(self.patience(self.options.buffer))?;
                let (k, start) = self.after_drawn(old.drawn);
                let mut preamble = crate::output::gpgl::RESET.as_bytes().to_vec();
                preamble.extend(tool_state(self.job, start, Language::Gpgl).bytes());
                if let Some(k) = k {
                    let [a, b] = self.cmds[k].position;
                    preamble.extend(format!("M{a},{b}\u{3}").bytes());
                }
                Ok(ResumePoint {
                    start,
                    preamble,
                    note: format!(
                        "GP-GL cannot report the knife's position: continuing after the last chunk the cutter reported cut ({start} of {} bytes)",
                        self.job.len()
                    ),
                })
            }
        }
    }

    fn hpgl_resume_point(&mut self, old: &Journal) -> Result<ResumePoint, StreamError> {
        let received = old.received;
        // Drop any half-received command, then ask where the pen is.
        self.link.send(b"\x1b.K", received, self.interrupted)?;
        self.link.send(b"OA;", received, self.interrupted)?;
        let at = self.link.reply("OA;", self.wait(64), received)?;
        let xy: Vec<i64> = at
            .split(',')
            .filter_map(|v| v.trim().parse().ok())
            .collect();
        // A powered plotter executes every complete command it received, and it received
        // at least what it confirmed and at most what was sent; its buffer can hold back no
        // more than `buffer` bytes of that.
        let low = old
            .received
            .max(old.drawn)
            .saturating_sub(self.options.buffer);
        let high = old.sent.max(old.received);
        let found = (xy.len() >= 2)
            .then(|| {
                self.cmds
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| c.end > low && c.end <= high)
                    .find(|(_, c)| c.moves && c.position == [xy[0], xy[1]])
                    .map(|(i, _)| i)
            })
            .flatten();
        let total = self.cmds.len();
        if let Some(i) = found {
            let start = self.cmds[i].end;
            return Ok(ResumePoint {
                start,
                preamble: tool_state(self.job, start, Language::Hpgl).into_bytes(),
                note: format!(
                    "the plotter is at {},{}: the end of command {} of {total}; continuing with the next",
                    xy[0],
                    xy[1],
                    i + 1,
                ),
            });
        }
        // A plotter that was reset cannot say: start again after the last command it
        // confirmed drawing, from a known state, with a pen-up move there.
        let (k, start) = self.after_drawn(old.drawn);
        let pos = k.map_or([0, 0], |k| self.cmds[k].position);
        let state = tool_state(self.job, start, Language::Hpgl);
        Ok(ResumePoint {
            start,
            preamble: format!("IN;{state}PA;PU{},{};PR;", pos[0], pos[1]).into_bytes(),
            note: format!(
                "the plotter does not know where it was (reset?); resuming after the last command it confirmed drawing ({start} of {} bytes)",
                self.job.len()
            ),
        })
    }
}

/// What an HP-GL ESC.E error code means.
fn hpgl_error_meaning(code: u32) -> &'static str {
    match code {
        10 => "overlapping output instructions",
        11 => "invalid byte after ESC",
        12 => "invalid byte in a device-control instruction",
        13 => "parameter out of range",
        14 => "too many parameters",
        15 => "framing, parity or overrun error",
        16 => "input buffer overflow: bytes were lost",
        _ => "see the plotter's manual",
    }
}

/// Where a registration mark search (GP-GL `TB123`) starts in `bytes`, if it does.
fn mark_search_at(bytes: &[u8]) -> Option<usize> {
    let search = crate::output::gpgl::SEARCH_MARKS.as_bytes();
    bytes.windows(search.len()).position(|w| w == search)
}
