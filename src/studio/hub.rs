//! One thread owns the session; request handlers only forward (bevy_remote's habit).
//! Handlers post a [`Command`] with a reply channel to the mailbox; the session thread
//! answers each in turn, publishes a `Frame` after every change and, while a drag can
//! go on, takes solver steps between messages. Long-polls wait on the published frame and
//! never touch the mesh.

use super::frame::Frame;
use super::session::{Command, Refusal, Reply, Session};
use crate::mesh::Mesh;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError, Sender, TryRecvError};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

type Answer = Result<Reply, Refusal>;

struct Envelope {
    command: Command,
    reply: Sender<Answer>,
}

/// Runs `work` on the session, catching a panic (a bug) so that it cannot end the
/// session: the drag under way is dropped, the design and history stay as they were
/// before it, and the request gets a 500 naming the bug.
fn guarded<T>(session: &mut Session, work: impl FnOnce(&mut Session) -> T) -> Result<T, Refusal> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work(session))) {
        Ok(t) => Ok(t),
        Err(cause) => {
            let what = cause
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| cause.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "no message".into());
            session.recover();
            let what: String = what.chars().take(120).collect();
            Err(Refusal {
                status: 500,
                message: format!(
                    "internal error, the design is kept (please report this bug): {what}"
                ),
            })
        }
    }
}

/// The shared side of the session thread.
pub struct Hub {
    mailbox: Mutex<Sender<Envelope>>,
    published: Mutex<Arc<Frame>>,
    changed: Condvar,
    stop: AtomicBool,
    thread: Mutex<Option<JoinHandle<()>>>,
    /// Names this session among every studio that ever served on the port: frame
    /// versions start again at 1 with each session, so a tab kept open across a restart
    /// must see that it talks to another one (see [`Hub::instance`]).
    instance: u64,
}

/// How long a request may wait for the session (a fold or fabrication of a large design
/// takes seconds; longer means something is wrong).
const ANSWER_WITHIN: Duration = Duration::from_secs(120);

impl Hub {
    /// Starts the session thread around a design.
    pub fn start(mesh: Mesh, title: &str) -> Arc<Hub> {
        let mut session = Session::new(mesh, title);
        let first = Arc::new(session.frame(None));
        let (tx, rx) = mpsc::channel::<Envelope>();
        let hub = Arc::new(Hub {
            mailbox: Mutex::new(tx),
            published: Mutex::new(first),
            changed: Condvar::new(),
            stop: AtomicBool::new(false),
            thread: Mutex::new(None),
            instance: new_instance(),
        });
        let shared = Arc::clone(&hub);
        let handle = std::thread::Builder::new()
            .name("studio-session".into())
            .spawn(move || shared.run(session, rx))
            .expect("the session thread starts");
        *hub.thread.lock().expect("hub lock") = Some(handle);
        hub
    }

    fn run(&self, mut session: Session, rx: mpsc::Receiver<Envelope>) {
        while !self.stop.load(Ordering::Relaxed) {
            let next = if session.wants_to_step() {
                match rx.try_recv() {
                    Ok(e) => Some(e),
                    Err(TryRecvError::Empty) => None,
                    Err(TryRecvError::Disconnected) => return,
                }
            } else {
                match rx.recv_timeout(Duration::from_millis(40)) {
                    Ok(e) => Some(e),
                    Err(RecvTimeoutError::Timeout) => {
                        // An analysis may have finished, or the step meter fallen to 0.
                        if session.idle(self.latest_rate()) {
                            self.publish(&mut session);
                        }
                        continue;
                    }
                    Err(RecvTimeoutError::Disconnected) => return,
                }
            };
            match next {
                Some(envelope) => {
                    let answer =
                        guarded(&mut session, |s| s.handle(envelope.command)).unwrap_or_else(Err);
                    if session.take_unpublished() {
                        let _ = guarded(&mut session, |s| self.publish(s));
                    }
                    // The asker may have gone (a closed tab): nothing to do then.
                    let _ = envelope.reply.send(answer);
                }
                None => {
                    let _ = guarded(&mut session, |s| {
                        s.step();
                        self.publish(s);
                    });
                }
            }
        }
    }

    fn publish(&self, session: &mut Session) {
        let previous = self.latest();
        let frame = Arc::new(session.frame(Some(&previous)));
        *self.published.lock().expect("hub lock") = frame;
        self.changed.notify_all();
    }

    fn latest_rate(&self) -> f64 {
        self.latest().steps_per_second
    }

    /// The newest frame.
    pub fn latest(&self) -> Arc<Frame> {
        self.published.lock().expect("hub lock").clone()
    }

    /// This session's instance number (see the field's doc).
    pub fn instance(&self) -> u64 {
        self.instance
    }

    /// Waits up to `timeout` for a frame newer than `after`, then returns the newest.
    pub fn frame_after(&self, after: u64, timeout: Duration) -> Arc<Frame> {
        let guard = self.published.lock().expect("hub lock");
        let (guard, _) = self
            .changed
            .wait_timeout_while(guard, timeout, |f| {
                f.version <= after && !self.stop.load(Ordering::Relaxed)
            })
            .expect("hub lock");
        guard.clone()
    }

    /// Sends a command to the session and waits for its answer.
    pub fn ask(&self, command: Command) -> Answer {
        let (tx, rx) = mpsc::channel();
        let sent = self
            .mailbox
            .lock()
            .expect("hub lock")
            .send(Envelope { command, reply: tx });
        if sent.is_err() {
            return Err(Refusal {
                status: 503,
                message: "the studio is shutting down".into(),
            });
        }
        rx.recv_timeout(ANSWER_WITHIN).unwrap_or_else(|_| {
            Err(Refusal {
                status: 503,
                message: "the session did not answer in time".into(),
            })
        })
    }

    /// Stops the session thread and wakes every waiting long-poll.
    pub fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
        self.changed.notify_all();
        if let Some(t) = self.thread.lock().expect("hub lock").take() {
            let _ = t.join();
        }
    }
}

/// A number no other studio session is likely to have had: the clock's nanoseconds mixed
/// with the process id and a counter (two hubs in one process, as in the tests), kept
/// within JavaScript's exact integers.
fn new_instance() -> u64 {
    use std::sync::atomic::AtomicU64;
    static COUNT: AtomicU64 = AtomicU64::new(0);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as u64);
    let mixed = nanos
        ^ (u64::from(std::process::id()) << 20)
        ^ COUNT
            .fetch_add(1, Ordering::Relaxed)
            .wrapping_mul(0x9e37_79b9_7f4a_7c15);
    (mixed & ((1 << 53) - 1)).max(1)
}
