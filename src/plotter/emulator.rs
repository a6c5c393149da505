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

use super::Language;
use crate::output::gpgl;
use crate::output::hpgl::{Interpreter, PenPath};
use serialport::{SerialPort, TTYPort};
use std::collections::VecDeque;
use std::io::{Read, Write};
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
    // Point the link at the new pty atomically.
    let tmp = link.with_extension("linking");
    let _ = std::fs::remove_file(&tmp);
    std::os::unix::fs::symlink(&target, &tmp)?;
    std::fs::rename(&tmp, link)?;
    Ok(Line { master, slave })
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
            Machine::Gpgl(i) => i.execute(cmd).map(|_| None),
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
                0x05 => Some(format!("{}\u{3}", self.gpgl_status())),
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
        let line = open_line(link)?;
        let (st, sp, lk) = (state.clone(), stop.clone(), link.to_path_buf());
        let thread = std::thread::spawn(move || run(line, lk, config, st, sp));
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
        let _ = std::fs::remove_file(&self.link);
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

fn run(
    first: Line,
    link: PathBuf,
    config: EmulatorConfig,
    state: Arc<Mutex<EmulatorState>>,
    stop: Arc<AtomicBool>,
) {
    let mut line = Some(first);
    let mut plotter = Plotter::new(config.clone());
    let mut host_queue: VecDeque<u8> = VecDeque::new();
    let wire_rate = config.baud as f64 / 10.0;
    let (mut wire_credit, mut draw_credit) = (0.0f64, 0.0f64);
    let mut last = Instant::now();
    let mut unplugged_at: Option<Instant> = None;
    let mut started: Option<Instant> = None;
    let mut last_work = Instant::now();
    let mut pending_idle = Duration::ZERO;
    let mut buf = [0u8; 4096];
    while !stop.load(Ordering::SeqCst) {
        std::thread::sleep(Duration::from_millis(1));
        let now = Instant::now();
        let dt = now.duration_since(last).as_secs_f64();
        last = now;
        let mut st = state.lock().expect("emulator state");
        // Cable pulled: wait, then plug a new pty in behind the same link.
        if let Some(t) = unplugged_at {
            if let Some(after) = config.reconnect_after {
                if t.elapsed() >= after {
                    if let Ok(l) = open_line(&link) {
                        line = Some(l);
                        unplugged_at = None;
                        host_queue.clear();
                    }
                }
            }
        }
        // Drawing continues while the plotter has power, cable or not. A plotter cannot
        // make up time it stood idle: credit never outlasts a short scheduling hiccup, and
        // an empty buffer forfeits it (see below).
        draw_credit = (draw_credit + dt * config.rate).min(config.rate * 0.02 + 1.0);
        let budget = draw_credit.floor() as usize;
        let had = plotter.buffer.len();
        // Idle time counts only when more work follows it: the wait after the job's last
        // command is not the sender's fault.
        if had == 0 {
            if started.is_some() && unplugged_at.is_none() {
                pending_idle += Duration::from_secs_f64(dt);
            }
        } else {
            st.idle += pending_idle;
            pending_idle = Duration::ZERO;
            last_work = now;
        }
        let replies = plotter.draw(budget, &mut st);
        draw_credit -= (had - plotter.buffer.len()) as f64;
        if plotter.buffer.is_empty() {
            draw_credit = draw_credit.min(1.0);
        }
        if let Some(s) = started {
            if had > 0 {
                st.busy_span = last_work.duration_since(s);
            }
        }
        let Some(l) = line.as_mut() else {
            continue;
        };
        for r in replies {
            let _ = l.master.write_all(r.as_bytes());
        }
        // Take what the host wrote into its (modelled) driver queue.
        match l.master.read(&mut buf) {
            Ok(n) => host_queue.extend(&buf[..n]),
            Err(e)
                if e.kind() == std::io::ErrorKind::TimedOut
                    || e.kind() == std::io::ErrorKind::WouldBlock => {}
            Err(_) => {}
        }
        // The host is stopped only if its port honours our stop signal.
        let (ixon, crtscts) = host_flags(&l.slave);
        let stopped = match config.flow {
            Flow::XonXoff => plotter.xoff_sent && ixon,
            Flow::RtsCts => plotter.cts_low && crtscts,
            Flow::None => false,
        };
        wire_credit = (wire_credit + dt * wire_rate).min(wire_rate * 0.05 + 1.0);
        if stopped {
            wire_credit = wire_credit.min(1.0);
        }
        while wire_credit >= 1.0 && !stopped {
            let Some(b) = host_queue.pop_front() else {
                break;
            };
            wire_credit -= 1.0;
            st.received += 1;
            started.get_or_insert(now);
            if let Some(r) = plotter.receive(b, &mut st) {
                let _ = l.master.write_all(r.as_bytes());
            }
            if config.fail_after == Some(st.received) {
                break;
            }
        }
        // Ask the host to pause with a margin for bytes already on their way.
        let margin = (config.buffer / 4).max(16);
        match config.flow {
            Flow::XonXoff => {
                if !plotter.xoff_sent && plotter.free() < margin {
                    let _ = l.master.write_all(&[XOFF]);
                    plotter.xoff_sent = true;
                } else if plotter.xoff_sent && plotter.free() > config.buffer / 2 {
                    let _ = l.master.write_all(&[XON]);
                    plotter.xoff_sent = false;
                }
            }
            Flow::RtsCts => plotter.cts_low = plotter.free() < margin,
            Flow::None => {}
        }
        if config.fail_after.is_some_and(|n| st.received >= n)
            && unplugged_at.is_none()
            && st.disconnects == 0
        {
            // Pull the cable: the host's port vanishes with everything still in its queue.
            st.disconnects += 1;
            line = None;
            if config.power_cycle {
                // Switched off: the buffer and the pen state are gone; the paper keeps
                // what was drawn.
                let drawn = std::mem::take(&mut st.path.segments);
                st.earlier.extend(drawn);
                plotter = Plotter::new(config.clone());
                host_queue.clear();
            }
            let _ = std::fs::remove_file(&link);
            unplugged_at = Some(Instant::now());
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
