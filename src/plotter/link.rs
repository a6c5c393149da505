//! The line to the plotter: a serial port opened with the flow control asked for, or a
//! device node (a USB printer-class cutter) opened as a file; writing through
//! flow-control stops, and reading replies.
//!
//! Replies to the queries a plotter answers on receipt (ESC.B, ESC.E, ESC ENQ) come back
//! at once. An HP-GL `OA;` is answered only when the plotter has executed everything before
//! it, so the sender leaves such marks in the stream without waiting for them; each reply
//! is matched to the oldest mark still out and moves `drawn` on. That is how the journal
//! learns what is on paper while the buffer stays full.

use super::line::{FlowMode, StreamError, StreamOptions, BAUD_RATES};
use super::Language;
use serialport::{FlowControl, SerialPort, TTYPort};
use std::collections::VecDeque;
use std::io::{ErrorKind, Read, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// What the job goes through.
enum Port {
    /// A serial port (or the emulator's pseudo-terminal).
    Serial(TTYPort),
    /// A device node written and read as a file, non-blocking, waited on with `poll`.
    Device(std::fs::File),
}

/// A device node that went away.
fn hung_up() -> std::io::Error {
    std::io::Error::new(
        ErrorKind::BrokenPipe,
        "the device hung up (unplugged or switched off)",
    )
}

/// How long a read waits for a byte, as the serial port's timeout.
const READ_WAIT: Duration = Duration::from_millis(50);

impl Port {
    /// Whether a byte can be read within `wait` (a device node only). A device that hung
    /// up (unplugged, switched off) is an error, not silence.
    fn readable(file: &std::fs::File, wait: Duration) -> std::io::Result<bool> {
        use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
        use std::os::fd::AsFd;
        let mut fds = [PollFd::new(file.as_fd(), PollFlags::POLLIN)];
        let ms = PollTimeout::try_from(wait).unwrap_or(PollTimeout::MAX);
        let n = poll(&mut fds, ms).map_err(std::io::Error::from)?;
        let gone = PollFlags::POLLHUP | PollFlags::POLLERR | PollFlags::POLLNVAL;
        if fds[0].revents().is_some_and(|r| r.intersects(gone)) {
            return Err(hung_up());
        }
        Ok(n > 0)
    }

    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        match self {
            Port::Serial(p) => p.write(bytes),
            Port::Device(f) => f.write(bytes),
        }
    }

    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        match self {
            Port::Serial(p) => p.read(buf),
            Port::Device(f) => {
                if !Port::readable(f, READ_WAIT)? {
                    return Err(ErrorKind::TimedOut.into());
                }
                // Readable with nothing to read is the end of the device.
                match f.read(buf)? {
                    0 => Err(hung_up()),
                    n => Ok(n),
                }
            }
        }
    }

    /// Bytes waiting to be read (for a device node: some, if any are).
    fn bytes_to_read(&self) -> std::io::Result<u32> {
        match self {
            Port::Serial(p) => p.bytes_to_read().map_err(std::io::Error::other),
            Port::Device(f) => Ok(if Port::readable(f, Duration::ZERO)? {
                256
            } else {
                0
            }),
        }
    }
}

pub(crate) struct Link {
    port: Port,
    pub(crate) name: String,
    language: Language,
    partial: Vec<u8>,
    /// Job offsets of `OA;` marks sent and not yet answered, oldest first.
    marks: VecDeque<usize>,
    /// Job bytes the plotter confirmed drawing (through marks).
    pub(crate) drawn: usize,
}

fn transient(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        ErrorKind::TimedOut | ErrorKind::WouldBlock | ErrorKind::Interrupted
    )
}

impl Link {
    pub(crate) fn vanished(&self, confirmed: usize, e: impl std::fmt::Display) -> StreamError {
        StreamError::Vanished {
            port: self.name.clone(),
            confirmed,
            cause: e.to_string(),
        }
    }

    /// Writes everything, waiting out flow-control stops (a stopped port times out).
    pub(crate) fn send(
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
                // A device node that cannot take more says so at once: wait a little.
                Err(e) if transient(&e) => std::thread::sleep(Duration::from_millis(1)),
                Err(e) => return Err(self.vanished(confirmed, e)),
            }
        }
        Ok(())
    }

    /// Sends an HP-GL `OA;` that confirms, when answered, the job up to offset `at`.
    pub(crate) fn mark(
        &mut self,
        at: usize,
        confirmed: usize,
        interrupted: &AtomicBool,
    ) -> Result<(), StreamError> {
        self.send(b"OA;", confirmed, interrupted)?;
        self.marks.push_back(at);
        Ok(())
    }

    /// A finished reply line, or a mark's answer taken in (then `None`).
    fn line_done(&mut self) -> Option<String> {
        let text = String::from_utf8_lossy(&self.partial).trim().to_string();
        self.partial.clear();
        if self.language == Language::Hpgl && text.contains(',') {
            if let Some(at) = self.marks.pop_front() {
                self.drawn = self.drawn.max(at);
                return None;
            }
        }
        Some(text)
    }

    /// Takes one byte off the line; a complete reply that is not a mark's comes back.
    fn take(&mut self, b: u8) -> Option<String> {
        let end = match self.language {
            Language::Hpgl => b'\r',
            Language::Gpgl => 0x03,
        };
        match b {
            0x11 | 0x13 | b'\n' => None,
            b'\r' if self.language == Language::Gpgl => None,
            b if b == end => self.line_done(),
            b => {
                self.partial.push(b);
                None
            }
        }
    }

    /// Reads whatever has arrived without waiting, taking in mark answers. A reply that is
    /// not a mark's, arriving unasked, is dropped.
    pub(crate) fn poll(&mut self, confirmed: usize) -> Result<(), StreamError> {
        loop {
            let waiting = self
                .port
                .bytes_to_read()
                .map_err(|e| self.vanished(confirmed, e))?;
            if waiting == 0 {
                return Ok(());
            }
            let mut buf = vec![0u8; waiting as usize];
            match self.port.read(&mut buf) {
                Ok(n) => {
                    for &b in &buf[..n] {
                        let _ = self.take(b);
                    }
                }
                Err(e) if transient(&e) => return Ok(()),
                Err(e) => return Err(self.vanished(confirmed, e)),
            }
        }
    }

    /// One byte off the line, `None` if none came in the port's short timeout; an error
    /// once `wait` has passed since `start` or the port is gone.
    fn next_byte(
        &mut self,
        query: &str,
        (start, wait): (Instant, Duration),
        confirmed: usize,
    ) -> Result<Option<u8>, StreamError> {
        if start.elapsed() > wait {
            return Err(StreamError::Silent {
                query: query.to_string(),
                seconds: wait.as_secs_f64(),
                confirmed,
            });
        }
        let mut byte = [0u8; 1];
        match self.port.read(&mut byte) {
            Ok(0) => Ok(None),
            Ok(_) => Ok(Some(byte[0])),
            Err(e) if transient(&e) => Ok(None),
            Err(e) => Err(self.vanished(confirmed, e)),
        }
    }

    /// Waits for the next reply that is not a mark's.
    pub(crate) fn reply(
        &mut self,
        query: &str,
        wait: Duration,
        confirmed: usize,
    ) -> Result<String, StreamError> {
        let start = Instant::now();
        loop {
            if let Some(b) = self.next_byte(query, (start, wait), confirmed)? {
                if let Some(text) = self.take(b) {
                    return Ok(text);
                }
            }
        }
    }

    /// Waits until every mark sent is answered: everything up to the last is drawn.
    pub(crate) fn await_marks(
        &mut self,
        wait: Duration,
        confirmed: usize,
    ) -> Result<(), StreamError> {
        let start = Instant::now();
        while !self.marks.is_empty() {
            if let Some(b) = self.next_byte("OA;", (start, wait), confirmed)? {
                let _ = self.take(b);
            }
        }
        Ok(())
    }
}

/// Opens a device node for reading and writing, non-blocking. Errors name it and say why.
fn open_device(name: &str) -> Result<Port, StreamError> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .custom_flags(nix::fcntl::OFlag::O_NONBLOCK.bits())
        .open(name)
        .map(Port::Device)
        .map_err(|e| StreamError::Open {
            port: name.to_string(),
            cause: match e.kind() {
                ErrorKind::NotFound => {
                    "no such device (is the cutter plugged in and switched on? on Linux it appears as /dev/usb/lp0 when the usblp driver is loaded)".to_string()
                }
                ErrorKind::PermissionDenied => format!(
                    "{e}: add yourself to the device's group (usually lp) and log in again"
                ),
                _ => e.to_string(),
            },
        })
}

/// Opens the port with the flow control asked for. Errors name the port and say why.
pub(crate) fn open(options: &StreamOptions) -> Result<Link, StreamError> {
    let name = options.port.display().to_string();
    if options.device {
        return Ok(Link {
            port: open_device(&name)?,
            name,
            language: options.language,
            partial: Vec::new(),
            marks: VecDeque::new(),
            drawn: 0,
        });
    }
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
    Ok(Link {
        port: Port::Serial(port),
        name,
        language: options.language,
        partial: Vec::new(),
        marks: VecDeque::new(),
        drawn: 0,
    })
}
