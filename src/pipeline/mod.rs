//! Whole jobs that chain the stages (solver → fab), shared by the CLI and the tests so
//! both run exactly the same thing: folding a pattern, running a design script
//! ([`Script`], run by [`run_design`] in `design_job`), and fabricating a design
//! ([`fabricate`]).

mod convert;
mod design_job;
mod fab_options;
mod fab_report;
mod fabricate;
mod fit;
mod fold_job;
mod guide;
mod motion;
pub mod names;
mod path;
pub mod plot_job;
mod report_json;
mod script;
mod step_order;
mod tube;

pub use convert::{convert, crease_pattern_first, with_sides_found, ConvertError, Converted};
pub use design_job::{
    finish_design, fold_mesh, is_flat_start, record_fold_angles, run_design, set_alpha, DesignJob,
    DesignOutcome, SheetResize, LEAVE_FLAT_AMOUNT, SHEET_RESIZE_MM,
};
pub use fab_options::{
    FabOptions, Guide, GLUE_TAB_MM, GUIDE_MAX_VERTICES, GUIDE_PICTURES, MIN_WIDTH_MM,
    MOTION_PREVIEW_FRAMES, TILE_OVERLAP_MM,
};
pub use fabricate::{
    fabricate, fabricate_verified, remove_stale_outputs, FabError, FabOutput, NextSteps, Rejected,
    OUTPUT_FILES,
};
pub use fit::{BlockedBy, ConditionResidual, Distances, FitReport, FitStage, PlacementRecord};
pub use fold_job::{
    flat_folded_file, fold_refusal, FlatFoldError, FlatFoldedFile, FoldRefusal, GOT_NOWHERE,
};
pub use motion::{
    fold_motion, fold_motion_on, motion_files, panels, Motion, MotionFormat, PanelBending,
    MAX_FRAME_VERTICES, RIGID_PANEL_MM,
};
pub use path::{
    foldable_sheet, folding_path, verdict_with_path, PathCollision, PathReport, PathShort,
    PATH_STEPS, REACHED_RADIANS,
};
pub use report_json::{
    DesignPreview, FabReport, HingeFold, HingeReport, MediaReport, PlotterReport, PreviewsReport,
    SheetPreview, SheetReport, TwoSidedReport, UnscoredCrease,
};
pub use script::{Script, ScriptFit};
pub use step_order::{layer_order_of_step, StepOrder, STEP_ORDER_TIME};

use crate::geometry::unfold::UnfoldError;
use crate::solver::SolverError;

/// Progress callback: phase name, steps done, steps planned.
pub type Progress<'a> = &'a mut dyn FnMut(&str, usize, usize);

/// Why a job failed. `is_input_error` separates bad arguments (exit 2) from solves that
/// did not work out (exit 1).
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// A bad argument or script entry.
    #[error("{0}")]
    Input(String),
    /// A value outside its range ([`crate::limits`]).
    #[error(transparent)]
    Range(#[from] crate::limits::OutOfRange),
    /// A file the job names (a script's base design, a fit's target) that cannot be read.
    #[error(transparent)]
    File(#[from] crate::io::FileError),
    /// The solver failed.
    #[error(transparent)]
    Solver(#[from] SolverError),
    /// The result could not be unfolded.
    #[error(transparent)]
    Unfold(#[from] UnfoldError),
}

impl PipelineError {
    /// Bad input rather than a failed solve.
    pub fn is_input_error(&self) -> bool {
        matches!(
            self,
            PipelineError::Input(_)
                | PipelineError::Range(_)
                | PipelineError::File(_)
                | PipelineError::Solver(
                    SolverError::UnknownVertex { .. } | SolverError::NotADisk { .. }
                )
        )
    }
}
