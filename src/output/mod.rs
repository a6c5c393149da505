//! Writers for a laid-out sheet: SVG (Inkscape layers per fold type), PDF (a 1:1 printable
//! template), HPGL (for plotters and cutters). They format bytes; geometry is decided
//! upstream in [`crate::fab`].

pub mod hpgl;
pub mod pdf;
pub mod svg;

pub use hpgl::{HpglSettings, PenPath, ToolSetting};
