//! What a fabrication run is asked (media, size, sides, tiling) and the sheet constants it
//! keeps: read by the run (`fabricate`) and by its report (`fab_report`), which therefore
//! import this and not each other.

/// Options of a fabrication run.
#[derive(Clone, Debug, Default)]
pub struct FabOptions {
    /// Media; default the machine's.
    pub media: Option<crate::fab::Media>,
    /// Scale the pattern so the laid-out sheet is this wide (mm).
    pub width: Option<f64>,
    /// Scale the pattern to the largest size the media takes within its margins.
    pub fit: bool,
    /// Margin kept free on every side (mm); default the machine's.
    pub margin: Option<f64>,
    /// Fabricate even if verification fails.
    pub force: bool,
    /// Score mountains from the back: a second, mirrored job.
    pub mountains_from_back: bool,
    /// When the pattern does not fit the media, split the PDF over pages instead of
    /// refusing (no cutter job is written then).
    pub tile: bool,
    /// Print-then-cut: lay the sheet out on a printed page with the machine's
    /// registration marks and cut in their frame ([`crate::fab::print_and_cut`]).
    pub print_and_cut: bool,
    /// Leave flat (triangulation) lines off the printed template.
    pub hide_flat: bool,
    /// Print-then-cut: the colour the paper's face is printed, RGB.
    pub print_fill: Option<[u8; 3]>,
    /// A tube's glue tab width (mm); default [`GLUE_TAB_MM`].
    pub tab: Option<f64>,
    /// How hard the cutting order is searched (a draft route for checking a layout).
    pub route: crate::fab::RouteSearch,
    /// Also write `motion.png`, the folding motion from flat ([`MOTION_PREVIEW_FRAMES`]
    /// steps of the path `verify --path` checks), beside the other previews.
    pub motion: bool,
    /// Whether `sheet.pdf` ends with the folding guide ([`Guide`]).
    pub guide: Guide,
}

/// Whether `sheet.pdf` ends with the folding guide: pictures of the folding motion from
/// the flat sheet to the design ([`GUIDE_PICTURES`] of them), drawn only where that path
/// is clear.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Guide {
    /// For a design with a 3D form of at most [`GUIDE_MAX_VERTICES`] vertices, whose
    /// path is found in about a second; a larger design's takes minutes, so it is asked
    /// for.
    #[default]
    Auto,
    /// For any design with a 3D form (`fab --guide`).
    Always,
    /// Never (`fab --no-guide`).
    Never,
}

/// Largest design the folding guide is drawn for unless asked: its path (the solver's
/// continuation from flat) took 6 s on a 961-vertex Miura-ori on the test machine, and
/// grows faster than the vertex count.
pub const GUIDE_MAX_VERTICES: usize = 1_000;

/// Pictures on the folding guide: the flat sheet, four shapes between, the design.
pub const GUIDE_PICTURES: usize = 6;

/// Steps of `fab --motion`'s `motion.png`: two seconds of folding at 15 frames a second.
pub const MOTION_PREVIEW_FRAMES: usize = 30;

/// A tube's glue tab width when none is given (mm): room for a line of glue.
pub const GLUE_TAB_MM: f64 = 6.0;

/// Narrowest sheet `--width` may ask for, mm: a cutter's step is 0.025–0.05 mm, and a
/// pattern much smaller than this leaves strokes that round to nothing (the lower end of
/// [`crate::limits::SHEET_WIDTH`]).
pub const MIN_WIDTH_MM: f64 = crate::limits::SHEET_WIDTH.min;

pub use crate::output::pdf::TILE_OVERLAP_MM;
