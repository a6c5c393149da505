//! A plotter on a pseudo-terminal, for trying crease without hardware and for tests.
//!
//! A pty moves bytes at once and has no modem lines, so the emulator models the wire
//! itself (REFERENCE.md): bytes the host writes are first held in a queue that stands for
//! the host's serial driver; they cross the wire at baud/10 bytes per second, and only
//! while the host is not stopped. The host is stopped when the emulator has sent XOFF and
//! the host's termios has IXON, or when the emulator holds CTS low and the host's termios
//! has CRTSCTS; the emulator reads those flags from its own handle on the slave. A sender
//! that ignores flow control therefore overruns the finite input buffer, and the emulator
//! counts every byte lost. The buffer drains at a drawing rate into an interpreter of the
//! plotter's language that records the pen path. In HP-GL it answers OA, OI and OS when it
//! reaches them, so an `OA;` reply confirms that everything before it is drawn; the escape
//! queries ESC.B, ESC.L, ESC.O, ESC.E and ESC.K act at once, as on HP plotters. In GP-GL
//! `ESC ENQ` answers at once (`0` ready: nothing left to cut, `1` moving, `2` no media)
//! and `ESC EOT` resets the cutter. The drawing rate is a ceiling the plotter cannot
//! exceed to make up for time it stood idle: idle time is lost, as on a real machine.

mod ticks;

use super::Language;
use crate::output::gpgl;
use crate::output::hpgl::{Interpreter, PenPath};
use serialport::{SerialPort, TTYPort};
use std::collections::VecDeque;
use std::os::fd::AsRawFd;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

const XON: u8 = 0x11;
const XOFF: u8 = 0x13;
const ESC: u8 = 0x1b;

/// How the emulated plotter asks the host to pause.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// XON/XOFF bytes.
    XonXoff,
    /// CTS low (modelled; the host must have CRTSCTS set).
    RtsCts,
    /// None: the host must ask with ESC.B or pace itself.
    None,
}

impl Flow {
    /// Parses xonxoff, rtscts, query or none (query uses no line flow control).
    pub fn parse(s: &str) -> Result<Flow, String> {
        match s {
            "xonxoff" => Ok(Flow::XonXoff),
            "rtscts" => Ok(Flow::RtsCts),
            "query" | "none" => Ok(Flow::None),
            _ => Err(format!(
                "unknown flow control \"{s}\" (xonxoff, rtscts, query, none)"
            )),
        }
    }
}

/// Emulator settings.
#[derive(Clone, Debug)]
pub struct EmulatorConfig {
    /// Input buffer (bytes).
    pub buffer: usize,
    /// Drawing rate: bytes of HP-GL executed per second.
    pub rate: f64,
    /// Line speed.
    pub baud: u32,
    /// Flow control the plotter uses.
    pub flow: Flow,
    /// Pull the cable after this many bytes have crossed the wire.
    pub fail_after: Option<usize>,
    /// Plug it back in after this long (a new pty behind the same link).
    pub reconnect_after: Option<Duration>,
    /// Switch the plotter off (lose all state) when the cable is pulled.
    pub power_cycle: bool,
    /// The language it speaks.
    pub language: Language,
    /// Whether media is loaded (GP-GL's status says `2` when not).
    pub media_loaded: bool,
    /// Whether a registration mark search (GP-GL `TB123`) finds the marks: it answers
    /// `0` when it does, `1` when not.
    pub marks_found: bool,
}

impl Default for EmulatorConfig {
    fn default() -> Self {
        EmulatorConfig {
            buffer: 1024,
            rate: 600.0,
            baud: 9600,
            flow: Flow::XonXoff,
            fail_after: None,
            reconnect_after: None,
            power_cycle: false,
            language: Language::Hpgl,
            media_loaded: true,
            marks_found: true,
        }
    }
}

/// What the emulated plotter has seen and done, shared with the caller.
#[derive(Clone, Debug, Default)]
pub struct EmulatorState {
    /// The pen path drawn so far.
    pub path: PenPath,
    /// Bytes lost to input-buffer overflow.
    pub lost: usize,
    /// Bytes that crossed the wire.
    pub received: usize,
    /// Time with an empty buffer while the job was under way (after the first byte and
    /// before the last command executed).
    pub idle: Duration,
    /// Time from the first byte to the last executed command.
    pub busy_span: Duration,
    /// Times the cable was pulled.
    pub disconnects: usize,
    /// HP-GL errors met (bad commands).
    pub errors: Vec<String>,
    /// Segments drawn before a power cycle (the paper keeps them).
    pub earlier: Vec<(u32, [i64; 2], [i64; 2])>,
    /// Status queries answered (GP-GL `ESC ENQ`).
    pub status_queries: usize,
}

impl EmulatorState {
    /// Every segment drawn, those before a reset or power cycle included, and how many
    /// of them are distinct: a resumed GP-GL job cuts up to a chunk again (it cannot
    /// report the knife's position), so the distinct count is what says whether the
    /// whole job arrived.
    pub fn drawn(&self) -> (usize, usize) {
        let all = || self.earlier.iter().chain(&self.path.segments);
        let distinct: std::collections::HashSet<_> = all().collect();
        (all().count(), distinct.len())
    }
}

/// A running emulator.
pub struct Emulator {
    /// The link path the host opens.
    pub link: PathBuf,
    state: Arc<Mutex<EmulatorState>>,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

struct Line {
    master: TTYPort,
    slave: TTYPort,
}

fn open_line(link: &Path) -> std::io::Result<Line> {
    let (mut master, slave) = TTYPort::pair().map_err(std::io::Error::other)?;
    master
        .set_timeout(Duration::from_millis(1))
        .map_err(std::io::Error::other)?;
    let target = slave
        .name()
        .ok_or_else(|| std::io::Error::other("pty has no name"))?;
    // Point the link at the new pty atomically; what is made is removed if that fails.
    let tmp = link.with_extension("linking");
    if is_emulator_link(&tmp) {
        let _ = std::fs::remove_file(&tmp);
    }
    std::os::unix::fs::symlink(&target, &tmp)?;
    if let Err(e) = std::fs::rename(&tmp, link) {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    Ok(Line { master, slave })
}

/// Whether `path` is a symlink to a pseudo-terminal, as the emulator makes: the only
/// thing at a `--link` path it may replace or remove.
fn is_emulator_link(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink())
        && std::fs::read_link(path).is_ok_and(|t| t.starts_with("/dev/pts/"))
}

/// Removes the emulator's link at `path`, and nothing else that may be there.
pub(super) fn remove_emulator_link(path: &Path) {
    if is_emulator_link(path) {
        let _ = std::fs::remove_file(path);
    }
}

/// Refuses a `--link` path (or its `.linking` neighbour) that holds anything but an
/// emulator's own link: a user's file there must survive.
pub fn check_link_path(link: &Path) -> std::io::Result<()> {
    for p in [link.to_path_buf(), link.with_extension("linking")] {
        if std::fs::symlink_metadata(&p).is_ok() && !is_emulator_link(&p) {
            return Err(std::io::Error::new(
                std::io::ErrorKind::AlreadyExists,
                format!(
                    "{} exists and is not an emulator's link: choose another --link path (nothing was changed)",
                    p.display()
                ),
            ));
        }
    }
    Ok(())
}

/// Host-side flow-control flags from the slave's termios: (IXON, CRTSCTS).
fn host_flags(slave: &TTYPort) -> (bool, bool) {
    use nix::sys::termios::{tcgetattr, ControlFlags, InputFlags};
    let fd = unsafe { std::os::fd::BorrowedFd::borrow_raw(slave.as_raw_fd()) };
    match tcgetattr(fd) {
        Ok(t) => (
            t.input_flags.contains(InputFlags::IXON),
            t.control_flags.contains(ControlFlags::CRTSCTS),
        ),
        Err(_) => (false, false),
    }
}

/// The command interpreter of either language.
enum Machine {
    Hpgl(Interpreter),
    Gpgl(gpgl::Interpreter),
}

impl Machine {
    fn new(language: Language) -> Machine {
        match language {
            Language::Hpgl => Machine::Hpgl(Interpreter::new()),
            Language::Gpgl => Machine::Gpgl(gpgl::Interpreter::new()),
        }
    }

    fn execute(&mut self, cmd: &str) -> Result<Option<String>, String> {
        match self {
            Machine::Hpgl(i) => i.execute(cmd),
            // A found mark search is answered; the rest of GP-GL is silent.
            Machine::Gpgl(i) => i.execute(cmd).map(|_| gpgl::reply_to(cmd)),
        }
    }

    fn path(&self) -> &PenPath {
        match self {
            Machine::Hpgl(i) => &i.path,
            Machine::Gpgl(i) => &i.path,
        }
    }
}

struct Plotter {
    config: EmulatorConfig,
    buffer: VecDeque<u8>,
    interpreter: Machine,
    command: Vec<u8>,
    escape: Vec<u8>,
    error: u8,
    xoff_sent: bool,
    cts_low: bool,
}

impl Plotter {
    fn new(config: EmulatorConfig) -> Plotter {
        Plotter {
            interpreter: Machine::new(config.language),
            config,
            buffer: VecDeque::new(),
            command: Vec::new(),
            escape: Vec::new(),
            error: 0,
            xoff_sent: false,
            cts_low: false,
        }
    }

    fn free(&self) -> usize {
        self.config.buffer.saturating_sub(self.buffer.len())
    }

    /// A byte arriving off the wire. Returns a reply to send at once, if any.
    fn receive(&mut self, b: u8, state: &mut EmulatorState) -> Option<String> {
        if b == ESC {
            // An escape always starts afresh, even after half of one lost on the wire.
            self.escape = vec![ESC];
            return None;
        }
        if !self.escape.is_empty() && self.config.language == Language::Gpgl {
            self.escape.clear();
            return match b {
                0x05 => {
                    state.status_queries += 1;
                    Some(format!("{}\u{3}", self.gpgl_status()))
                }
                0x04 => {
                    // Reset: the buffer, a half-read command and the position are gone;
                    // what was cut stays cut.
                    self.buffer.clear();
                    self.command.clear();
                    let cut = std::mem::take(&mut state.path.segments);
                    state.earlier.extend(cut);
                    self.interpreter = Machine::new(Language::Gpgl);
                    None
                }
                _ => None,
            };
        }
        if !self.escape.is_empty() {
            self.escape.push(b);
            if self.escape.len() < 3 {
                return None;
            }
            let code = self.escape[2];
            self.escape.clear();
            return match code {
                b'B' => Some(format!("{}\r", self.free())),
                b'L' => Some(format!("{}\r", self.config.buffer)),
                b'O' => Some(format!("{}\r", if self.buffer.is_empty() { 8 } else { 0 })),
                b'E' => {
                    let e = self.error;
                    self.error = 0;
                    Some(format!("{e}\r"))
                }
                b'K' => {
                    // Abort: drop what is buffered and any half-read command.
                    self.buffer.clear();
                    self.command.clear();
                    None
                }
                _ => None, // ESC.@, ESC.P and others: configuration, accepted
            };
        }
        if self.buffer.len() >= self.config.buffer {
            state.lost += 1;
            self.error = 16;
            return None;
        }
        self.buffer.push_back(b);
        None
    }

    /// GP-GL status: `2` no media, `1` still cutting, `0` ready.
    fn gpgl_status(&self) -> char {
        if !self.config.media_loaded {
            '2'
        } else if self.buffer.is_empty() {
            // Nothing left to execute (a half-received command waits for its end).
            '0'
        } else {
            '1'
        }
    }

    /// Executes up to `budget` buffered bytes; returns replies of output commands.
    fn draw(&mut self, budget: usize, state: &mut EmulatorState) -> Vec<String> {
        let mut replies = Vec::new();
        for _ in 0..budget {
            let Some(b) = self.buffer.pop_front() else {
                break;
            };
            if b == self.config.language.terminator() {
                let cmd = String::from_utf8_lossy(&self.command).into_owned();
                self.command.clear();
                match self.interpreter.execute(&cmd) {
                    Ok(Some(_)) if !self.config.marks_found && gpgl::reply_to(&cmd).is_some() => {
                        replies.push(format!("    1{}", gpgl::ETX));
                        // Nothing is cut after a failed search: the job is dropped.
                        self.buffer.clear();
                    }
                    Ok(Some(r)) => replies.push(r),
                    Ok(None) => {}
                    Err(e) => {
                        state.errors.push(e);
                        self.error = 1;
                    }
                }
            } else if !b.is_ascii_whitespace() {
                self.command.push(b);
            }
        }
        state.path = self.interpreter.path().clone();
        replies
    }
}

impl Emulator {
    /// Starts an emulator whose pty is reachable at `link` (a symlink, replaced on
    /// reconnection so the host can open the same path again).
    pub fn start(link: &Path, config: EmulatorConfig) -> std::io::Result<Emulator> {
        let state = Arc::new(Mutex::new(EmulatorState::default()));
        let stop = Arc::new(AtomicBool::new(false));
        check_link_path(link)?;
        let line = open_line(link)?;
        let (st, sp, lk) = (state.clone(), stop.clone(), link.to_path_buf());
        let thread = std::thread::spawn(move || ticks::run(line, lk, config, st, sp));
        Ok(Emulator {
            link: link.to_path_buf(),
            state,
            stop,
            thread: Some(thread),
        })
    }

    /// A snapshot of what the plotter has done.
    pub fn state(&self) -> EmulatorState {
        self.state.lock().expect("emulator state").clone()
    }

    /// Waits until the plotter has executed everything it received and has been quiet for
    /// `quiet`, or `timeout` passes.
    pub fn wait_idle(&self, quiet: Duration, timeout: Duration) {
        let start = Instant::now();
        let mut last = (0, 0);
        let mut since = Instant::now();
        while start.elapsed() < timeout {
            let s = self.state();
            let now = (s.received, s.path.segments.len());
            if now != last {
                last = now;
                since = Instant::now();
            } else if since.elapsed() >= quiet {
                return;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Stops the emulator and removes its link.
    pub fn stop(mut self) -> EmulatorState {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
        remove_emulator_link(&self.link);
        self.state()
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// Runs an emulator in the foreground until interrupted (the `crease emulate` command),
/// printing what it records when it stops.
pub fn run_foreground(
    link: &Path,
    config: EmulatorConfig,
    interrupted: Arc<AtomicBool>,
) -> std::io::Result<EmulatorState> {
    let emulator = Emulator::start(link, config)?;
    while !interrupted.load(Ordering::SeqCst) {
        std::thread::sleep(Duration::from_millis(50));
    }
    Ok(emulator.stop())
}
