//! `report.json`, the one type it is written and read through: `fab` writes it beside the
//! files, `crease plot` reads the machine and the two-sided steps back from it, and the
//! CLI and the tests read a run's figures from it. Written through `serde_json::Value`
//! (whose map is sorted), so its keys stay in alphabetical order as before the type.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The whole of `report.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FabReport {
    /// The verification report ([`crate::fab::Report::to_json`]).
    pub verification: serde_json::Value,
    /// The sheet and its jobs.
    pub sheet: SheetReport,
    /// How the preview pictures were drawn (scales, the design's view).
    pub previews: PreviewsReport,
    /// What the maker does in the machine's own software, if the profile says.
    pub next_steps: Option<super::NextSteps>,
    /// A print-and-cut sheet's marks and placement.
    pub print_and_cut: Option<crate::fab::print_and_cut::PrintReport>,
    /// The hinge gaps of a panels-on-membrane sheet.
    pub hinge: Option<HingeReport>,
    /// A tube's seam: which edge of the strip is glued to which.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seam: Option<SeamReport>,
}

/// `report.json`'s `previews`: how `sheet.png`, `design.png` and `design-side.png` were
/// drawn.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PreviewsReport {
    /// The toolpath's picture.
    #[serde(rename = "sheet.png")]
    pub sheet: SheetPreview,
    /// The 3D design's picture.
    #[serde(rename = "design.png")]
    pub design: DesignPreview,
    /// The 3D design seen from its side ([`crate::output::png::design_side_view`]).
    #[serde(rename = "design-side.png", default = "DesignPreview::absent")]
    pub design_side: DesignPreview,
    /// The folding motion from flat (`fab --motion`), as `crease animate` reports it,
    /// one line each: the path and the panels.
    #[serde(
        rename = "motion.png",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub motion: Option<String>,
    /// The folding guide at the end of sheet.pdf: drawn, or why not ([`super::Guide`]).
    #[serde(
        rename = "folding-guide",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub guide: Option<String>,
}

impl DesignPreview {
    /// What a report written before `design-side.png` existed reads as: no picture.
    fn absent() -> DesignPreview {
        DesignPreview {
            size_px: [0, 0],
            view: [0.0; 3],
            px_per_mm: 0.0,
        }
    }
}

/// How `sheet.png` was drawn ([`crate::output::png::sheet`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SheetPreview {
    /// Pixels per sheet millimetre.
    pub px_per_mm: f64,
    /// The strokes' width, pixels.
    pub stroke_px: f64,
}

/// How `design.png` was drawn ([`crate::output::png::design`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignPreview {
    /// Width and height, pixels.
    pub size_px: [u32; 2],
    /// The direction the design is seen from.
    pub view: [f64; 3],
    /// Pixels per design millimetre.
    pub px_per_mm: f64,
}

/// A tube's seam on the sheet (issue 31): the strip's side with the glue tab and the side
/// glued onto it, edge by edge, in sheet millimetres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeamReport {
    /// The glue tab's width (mm, before scaling to the sheet).
    pub tab_mm: f64,
    /// Each seam edge, rim to rim.
    pub pairs: Vec<SeamPair>,
}

/// One seam edge: its two copies on the sheet, ends matching in order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeamPair {
    /// Number of the pair, from 1, as marked on the sheet.
    pub number: usize,
    /// The edge the tab hangs from (its hinge), start and end.
    pub tab_side: [[f64; 2]; 2],
    /// The edge glued onto the tab, start and end (the copies of `tab_side`'s ends).
    pub glued_side: [[f64; 2]; 2],
}

impl FabReport {
    /// The JSON text written as `report.json` (pretty, keys sorted, a final newline).
    pub fn to_text(&self) -> String {
        let value = serde_json::to_value(self).expect("a report is plain data");
        serde_json::to_string_pretty(&value).expect("json") + "\n"
    }

    /// Reads `report.json` text.
    pub fn from_text(text: &str) -> Result<FabReport, serde_json::Error> {
        serde_json::from_str(text)
    }
}

/// `report.json`'s `sheet`: where the pattern went and what the jobs cost.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SheetReport {
    /// The machine's name.
    pub machine: String,
    /// The material laid over the machine, if any.
    pub material: Option<String>,
    /// What `crease plot` needs to stream the job to the machine it was made for (none
    /// when no cutter job was written, or the machine is not on a line).
    #[serde(default)]
    pub plotter: Option<PlotterReport>,
    /// The media.
    pub media: MediaReport,
    /// The pattern's size on the media (mm).
    pub size_mm: [f64; 2],
    /// Scale applied to the design.
    pub scale: f64,
    /// Rotation applied (degrees).
    pub rotation_deg: f64,
    /// Length of the sheet's lines per kind (mm).
    pub line_length_mm: BTreeMap<String, f64>,
    /// Length cut or scored per kind (mm).
    pub cut_length_mm: BTreeMap<String, f64>,
    /// Strokes in the jobs.
    pub strokes: usize,
    /// Pen-up travel (mm).
    pub pen_up_travel_mm: f64,
    /// The cutter job files written (none for a laser, a Design Space sheet or a tiled
    /// sheet). Missing in reports made before they were named.
    #[serde(default)]
    pub job_files: Option<Vec<String>>,
    /// Their size in bytes.
    pub job_bytes: usize,
    /// What plotting takes (s): the motion, or the transfer if slower.
    pub estimated_plot_time_s: f64,
    /// The machine's motion (s).
    pub motion_time_s: f64,
    /// The transfer over the serial line (s).
    pub transfer_time_s: f64,
    /// Largest relative edge-length difference between the sheet and the 3D design.
    pub isometry_max_relative_error: f64,
    /// Mountains scored from the back in a second job.
    pub mountains_from_back: bool,
    /// How the two sides of a two-sided job register.
    #[serde(default)]
    pub two_sided: Option<TwoSidedReport>,
    /// The sheet is tiled over pages (no cutter job).
    pub tiled: bool,
    /// Folds with no room for a dash, and what the profile gave them.
    pub unscored_creases: Vec<UnscoredCrease>,
}

/// A machine's line, as `crease plot` needs it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlotterReport {
    /// hpgl or gpgl.
    pub protocol: crate::machine::Protocol,
    /// serial or usb.
    pub connection: crate::machine::Connection,
    /// Baud rate.
    pub baud: u32,
    /// Flow control by name.
    pub flow_control: crate::machine::FlowMode,
    /// The machine's input buffer (bytes).
    pub buffer_bytes: usize,
}

/// The media by name and size.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MediaReport {
    /// Its name.
    pub name: String,
    /// Width (mm).
    pub width_mm: f64,
    /// Height (mm).
    pub height_mm: f64,
}

/// The registration of a two-sided job: the crosses each job cuts first, and the steps.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TwoSidedReport {
    /// The front job's cross centres (mm).
    pub front_marks_mm: [[f64; 2]; 3],
    /// The back job's (mm, mirrored).
    pub back_marks_mm: [[f64; 2]; 3],
    /// What the maker does, in order.
    pub steps: Vec<String>,
}

/// A fold with no room for a dash.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UnscoredCrease {
    /// What the profile's `short_folds` gave it.
    pub given: String,
    /// mountain or valley.
    pub kind: String,
    /// Its length (mm).
    pub length_mm: f64,
    /// One end on the media (mm).
    pub from_mm: [f64; 2],
    /// The other end.
    pub to_mm: [f64; 2],
}

/// The hinge gaps of a panels-on-membrane sheet.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HingeReport {
    /// How each gap is found.
    pub formula: String,
    /// The sheet's thickness (mm).
    pub thickness_mm: f64,
    /// The largest fold a gap is laid out for (degrees).
    pub largest_gap_fold_deg: f64,
    /// Panels cut.
    pub panels: usize,
    /// Every fold's gap.
    pub folds: Vec<HingeFold>,
    /// Valleys folded past the largest fold (edge indices).
    pub too_far: Vec<usize>,
}

/// One fold's hinge gap.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HingeFold {
    /// The edge.
    pub edge: usize,
    /// Its two vertices.
    pub vertices: [usize; 2],
    /// Its fold (degrees).
    pub fold_deg: f64,
    /// The gap between its panels (mm).
    pub gap_mm: f64,
}
