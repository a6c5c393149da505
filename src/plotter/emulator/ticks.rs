//! The emulator's thread: every millisecond it draws from the buffer, moves bytes over
//! the modelled wire, raises or drops flow control, and pulls or replugs the cable.

use super::{host_flags, open_line, EmulatorConfig, EmulatorState, Flow, Line, Plotter, XOFF, XON};
use std::collections::VecDeque;
use std::io::{Read, Write};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The emulator thread's world between ticks: the line (absent while the cable is
/// pulled), the plotter, the bytes the host's driver still holds, and the credits that
/// pace the wire at its baud rate and the pen at its drawing rate.
struct Session {
    line: Option<Line>,
    link: PathBuf,
    config: EmulatorConfig,
    plotter: Plotter,
    host_queue: VecDeque<u8>,
    wire_credit: f64,
    draw_credit: f64,
    unplugged_at: Option<Instant>,
    started: Option<Instant>,
    last_work: Instant,
    pending_idle: Duration,
}

pub(super) fn run(
    first: Line,
    link: PathBuf,
    config: EmulatorConfig,
    state: Arc<Mutex<EmulatorState>>,
    stop: Arc<AtomicBool>,
) {
    let mut session = Session {
        line: Some(first),
        link,
        plotter: Plotter::new(config.clone()),
        config,
        host_queue: VecDeque::new(),
        wire_credit: 0.0,
        draw_credit: 0.0,
        unplugged_at: None,
        started: None,
        last_work: Instant::now(),
        pending_idle: Duration::ZERO,
    };
    let mut last = Instant::now();
    while !stop.load(Ordering::SeqCst) {
        std::thread::sleep(Duration::from_millis(1));
        let now = Instant::now();
        let dt = now.duration_since(last).as_secs_f64();
        last = now;
        let mut st = state.lock().expect("emulator state");
        session.reconnect_if_due();
        let replies = session.draw(dt, now, &mut st);
        if session.line.is_none() {
            continue;
        }
        session.exchange(dt, now, replies, &mut st);
        session.pull_cable_if_due(&mut st);
    }
}

impl Session {
    /// Cable pulled: wait, then plug a new pty in behind the same link.
    fn reconnect_if_due(&mut self) {
        let (Some(t), Some(after)) = (self.unplugged_at, self.config.reconnect_after) else {
            return;
        };
        if t.elapsed() >= after {
            if let Ok(l) = open_line(&self.link) {
                self.line = Some(l);
                self.unplugged_at = None;
                self.host_queue.clear();
            }
        }
    }

    /// Draws for `dt` seconds; returns the replies drawing produced (answers to queries
    /// that waited for the pen).
    fn draw(&mut self, dt: f64, now: Instant, st: &mut EmulatorState) -> Vec<String> {
        let rate = self.config.rate;
        // Drawing continues while the plotter has power, cable or not. A plotter cannot
        // make up time it stood idle: credit never outlasts a short scheduling hiccup, and
        // an empty buffer forfeits it (see below).
        self.draw_credit = (self.draw_credit + dt * rate).min(rate * 0.02 + 1.0);
        let budget = self.draw_credit.floor() as usize;
        let had = self.plotter.buffer.len();
        // Idle time counts only when more work follows it: the wait after the job's last
        // command is not the sender's fault.
        if had == 0 {
            if self.started.is_some() && self.unplugged_at.is_none() {
                self.pending_idle += Duration::from_secs_f64(dt);
            }
        } else {
            st.idle += self.pending_idle;
            self.pending_idle = Duration::ZERO;
            self.last_work = now;
        }
        let replies = self.plotter.draw(budget, st);
        self.draw_credit -= (had - self.plotter.buffer.len()) as f64;
        if self.plotter.buffer.is_empty() {
            self.draw_credit = self.draw_credit.min(1.0);
        }
        if let Some(s) = self.started {
            if had > 0 {
                st.busy_span = self.last_work.duration_since(s);
            }
        }
        replies
    }

    /// One tick on the line: replies out, the host's bytes in at the wire's pace (unless
    /// flow control holds the host), and the flow signals the buffer's level calls for.
    fn exchange(&mut self, dt: f64, now: Instant, replies: Vec<String>, st: &mut EmulatorState) {
        let Some(l) = self.line.as_mut() else {
            return;
        };
        let (config, plotter) = (&self.config, &mut self.plotter);
        for r in replies {
            let _ = l.master.write_all(r.as_bytes());
        }
        // Take what the host wrote into its (modelled) driver queue.
        let mut buf = [0u8; 4096];
        match l.master.read(&mut buf) {
            Ok(n) => self.host_queue.extend(&buf[..n]),
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
        let wire_rate = config.baud as f64 / 10.0;
        self.wire_credit = (self.wire_credit + dt * wire_rate).min(wire_rate * 0.05 + 1.0);
        if stopped {
            self.wire_credit = self.wire_credit.min(1.0);
        }
        while self.wire_credit >= 1.0 && !stopped {
            let Some(b) = self.host_queue.pop_front() else {
                break;
            };
            self.wire_credit -= 1.0;
            st.received += 1;
            self.started.get_or_insert(now);
            if let Some(r) = plotter.receive(b, st) {
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
    }

    /// Pulls the cable once `fail_after` bytes have arrived: the host's port vanishes
    /// with everything still in its queue (and with `power_cycle` the plotter's buffer
    /// and pen state go too; the paper keeps what was drawn).
    fn pull_cable_if_due(&mut self, st: &mut EmulatorState) {
        let due = self.config.fail_after.is_some_and(|n| st.received >= n);
        if !due || self.unplugged_at.is_some() || st.disconnects > 0 {
            return;
        }
        st.disconnects += 1;
        // The link goes before the line: a host that sees its port hang up must not
        // find the old link still there and open the pty it named, whose number another
        // emulator's replugged port may already hold (a power-cut test hung waiting on
        // a plotter that was not its own, with eight emulators running at once).
        super::remove_emulator_link(&self.link);
        self.line = None;
        if self.config.power_cycle {
            let drawn = std::mem::take(&mut st.path.segments);
            st.earlier.extend(drawn);
            self.plotter = Plotter::new(self.config.clone());
            self.host_queue.clear();
        }
        self.unplugged_at = Some(Instant::now());
    }
}
