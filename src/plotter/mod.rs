//! Plotters and cutters on the line: streaming a job over a serial port or a USB device
//! node with flow control, progress and resume, and an emulated plotter on a pty. The
//! machines' profiles are data, in [`crate::machine`].

pub mod emulator;
mod journal;
mod line;
mod link;
mod session;
pub mod stream;

pub use emulator::{Emulator, EmulatorConfig, EmulatorState, Flow};
pub use stream::{stream, FlowMode, Journal, Progress, StreamError, StreamOptions, StreamReport};

/// The language a plotter speaks, which decides how the sender asks it anything.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Language {
    /// HP-GL/1: commands end with `;`, replies with CR; `ESC.B` and `OA;` queries.
    Hpgl,
    /// GP-GL: commands and replies end with ETX; `ESC ENQ` status.
    Gpgl,
}

impl Language {
    /// From a machine profile's `protocol`: HP-GL and GP-GL are streamed, the others are
    /// files for the machine's own software.
    pub fn from_protocol(protocol: crate::machine::Protocol) -> Option<Language> {
        use crate::machine::Protocol;
        match protocol {
            Protocol::Hpgl => Some(Language::Hpgl),
            Protocol::Gpgl => Some(Language::Gpgl),
            Protocol::Dxf | Protocol::Svg => None,
        }
    }

    /// From a name (`emulate --language`): hpgl or gpgl.
    pub fn parse(name: &str) -> Option<Language> {
        match name {
            "hpgl" => Some(Language::Hpgl),
            "gpgl" => Some(Language::Gpgl),
            _ => None,
        }
    }

    /// The byte that ends every command.
    pub fn terminator(self) -> u8 {
        match self {
            Language::Hpgl => b';',
            Language::Gpgl => 0x03,
        }
    }
}
