//! What a serial line to a plotter is set up with and how it fails: the flow-control
//! mode, the stream options, the errors, the baud rates, progress and the report of a
//! job. Shared by the port (`link`), the conversation (`session`) and the job
//! (`stream`), which import this rather than each other.

use super::Language;
use std::path::PathBuf;
use std::time::Duration;

/// How the sender respects the plotter's buffer: the profile's `flow_control`, one type.
pub use crate::machine::FlowMode;

/// Streaming settings.
#[derive(Clone, Debug)]
pub struct StreamOptions {
    /// Serial port path.
    pub port: PathBuf,
    /// Line speed.
    pub baud: u32,
    /// The job's language.
    pub language: Language,
    /// Flow control.
    pub flow: FlowMode,
    /// The plotter's buffer size (bytes), from the machine profile.
    pub buffer: usize,
    /// The port is a device node read and written as a file (a USB printer-class cutter
    /// such as the Silhouette Cameo on Linux, `/dev/usb/lpN`): no line speed and no
    /// line flow control (USB paces the writes); `baud` is then not used.
    pub device: bool,
    /// Continue a job from its journal.
    pub resume: bool,
    /// How long a silent plotter is given before it counts as not answering (on top of
    /// the time the bytes in flight need on the line).
    pub answer_timeout: Duration,
}

impl StreamOptions {
    /// Bytes per second the line carries ([`crate::machine::line_bytes_per_second`]).
    pub fn line_rate(&self) -> f64 {
        crate::machine::line_bytes_per_second(self.device, self.baud)
    }
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
    /// The cutter says no media is loaded (GP-GL status 2).
    #[error("the cutter reports no media loaded after {confirmed} confirmed bytes; load the sheet, then --resume")]
    NoMedia {
        /// Bytes confirmed.
        confirmed: usize,
    },
    /// The cutter did not find the print-and-cut registration marks.
    #[error("the cutter did not find the registration marks (it answered \"{answer}\") after {confirmed} confirmed bytes, before cutting anything: check the print lies square with the black square at the top left, the marks are solid black and the sensor is clean, then --restart")]
    MarksNotFound {
        /// What it answered to the search.
        answer: String,
        /// Bytes confirmed.
        confirmed: usize,
    },
    /// The job was cancelled on the cutter's panel (GP-GL status 4).
    #[error("the job was cancelled on the cutter's panel after {confirmed} confirmed bytes; --resume continues, --restart starts again")]
    Cancelled {
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
