//! Writers for a laid-out sheet: SVG (Inkscape layers per fold type), PDF (a 1:1 printable
//! template), HPGL (for plotters and cutters), DXF (for laser cutters and CAD). They format
//! bytes; geometry is decided upstream in [`crate::fab`].

pub mod colour;
pub mod dxf;
pub mod gltf;
pub mod gpgl;
pub mod hpgl;
pub mod pdf;
pub mod png;
pub mod svg;

pub use gpgl::GpglSettings;
pub use hpgl::{HpglSettings, PenPath, ToolSetting};
