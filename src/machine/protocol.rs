//! The closed sets a machine profile chooses from — the job's language, how it reaches the
//! machine, the line's flow control, a GP-GL cutter's axis order — as types, so a profile
//! naming anything else is refused by the reader with its line and key, and the code
//! matches on variants instead of comparing strings.

use serde::{Deserialize, Serialize};

/// The job a machine takes (`protocol` in a profile).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Protocol {
    /// HP-GL: `sheet.hpgl`, streamed by `crease plot`.
    Hpgl,
    /// GP-GL (Graphtec and Silhouette): `sheet.gpgl`, streamed by `crease plot`.
    Gpgl,
    /// Laser cutters: `sheet.dxf` and `sheet.svg`, no cutter job.
    Dxf,
    /// Cutters driven by their own design software (Cricut Design Space): `sheet.svg`
    /// with one layer per operation.
    Svg,
}

impl Protocol {
    /// The name a profile writes.
    pub fn name(self) -> &'static str {
        match self {
            Protocol::Hpgl => "hpgl",
            Protocol::Gpgl => "gpgl",
            Protocol::Dxf => "dxf",
            Protocol::Svg => "svg",
        }
    }

    /// Whether the machine takes a cutter job (HP-GL or GP-GL) that crease writes on its
    /// step grid and can stream, rather than a drawing for its own software.
    pub fn is_cutter_job(self) -> bool {
        matches!(self, Protocol::Hpgl | Protocol::Gpgl)
    }
}

impl std::fmt::Display for Protocol {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// How the job reaches the machine (`connection` in a profile).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Connection {
    /// A serial port `crease plot` streams to (needs `baud`, `flow_control`, `buffer_bytes`).
    #[default]
    Serial,
    /// A USB printer-class device node (`/dev/usb/lpN`) written as a file (needs
    /// `buffer_bytes`).
    Usb,
    /// The maker's own software sends it.
    File,
}

impl Connection {
    /// The name a profile writes.
    pub fn name(self) -> &'static str {
        match self {
            Connection::Serial => "serial",
            Connection::Usb => "usb",
            Connection::File => "file",
        }
    }
}

impl std::fmt::Display for Connection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// How the sender respects the plotter's buffer (`flow_control` in a profile, `--flow`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
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
    /// Every mode, in the order messages list them.
    pub const ALL: [FlowMode; 4] = [
        FlowMode::XonXoff,
        FlowMode::RtsCts,
        FlowMode::Query,
        FlowMode::None,
    ];

    /// Parses a mode by its [`FlowMode::name`] (`--flow`), naming them all if it is none.
    pub fn parse(s: &str) -> Result<FlowMode, String> {
        FlowMode::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = FlowMode::ALL.iter().map(|f| f.name()).collect();
                format!("unknown flow control \"{s}\" ({})", names.join(", "))
            })
    }

    /// The name a profile writes.
    pub fn name(self) -> &'static str {
        match self {
            FlowMode::XonXoff => "xonxoff",
            FlowMode::RtsCts => "rtscts",
            FlowMode::Query => "query",
            FlowMode::None => "none",
        }
    }
}

/// The order of a GP-GL cutter's `M`/`D` coordinates (`gpgl.axis_order`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AxisOrder {
    /// Media feed, then carriage: Silhouette and Graphtec in portrait (`FN0`).
    #[default]
    FeedFirst,
    /// Carriage, then feed, as inkcut and robocut send.
    CarriageFirst,
}

/// The serial line of a machine that is streamed to.
#[derive(Clone, Debug, PartialEq)]
pub struct SerialLine {
    /// A device node written as a file (connection "usb"), not a serial port.
    pub device: bool,
    /// Speed (0 for a device node, which has none).
    pub baud: u32,
    /// The line's flow control ([`FlowMode::None`] for a device node).
    pub flow_control: FlowMode,
    /// The machine's input buffer, bytes.
    pub buffer_bytes: usize,
}

impl SerialLine {
    /// Bytes the line carries per second: a serial byte is 10 bits on the wire.
    pub fn bytes_per_second(&self) -> f64 {
        line_bytes_per_second(self.device, self.baud)
    }
}

/// Bytes per second a USB device node takes: far more than a cutter cuts, so the cutter
/// sets the pace (a USB 1.1 printer-class link moves about 1 MB/s).
pub const DEVICE_BYTES_PER_S: f64 = 100_000.0;

/// Bytes per second a line carries: a tenth of the baud rate on a serial port (8N1: a
/// byte is 10 bits on the wire), and for a USB device node a conservative
/// [`DEVICE_BYTES_PER_S`] (full-speed USB bulk transfers run several times faster).
pub fn line_bytes_per_second(device: bool, baud: u32) -> f64 {
    if device {
        DEVICE_BYTES_PER_S
    } else {
        f64::from(baud.max(1)) / 10.0
    }
}
