//! Fabrication: verify a design before anything is cut (its crease pattern comes from
//! [`crate::geometry::unfold`]), lay it out on the media, score it with dash codes and
//! order the cuts.

pub mod advice;
pub mod assign;
pub mod budget;
pub mod clearance;
pub mod curve;
pub mod flat_fold;
pub mod glue_tab;
pub mod hinge;
pub mod intersect;
pub mod labels;
pub mod layers;
pub mod layout;
pub mod lines;
pub mod precision;
pub mod print_and_cut;
pub mod registration;
pub mod rounding;
pub mod route;
pub mod score;
pub mod toolpath;
pub mod verify;

pub use advice::{Advice, FabOption};
pub use assign::{assign_sides, SideSearch};
pub use budget::{Budget, OverBudget};
pub use curve::{Cubic, SmoothCurve};
pub use flat_fold::{closure_tolerance, flat_folded, FlatFolded, NotFlatFoldable, PlaneMotion};
pub use glue_tab::{glue_tab, with_tab, GlueTab};
pub use intersect::{self_intersections, Crossing};
pub use layers::{
    count_states, layer_conflict, layer_order, layer_order_naming_within, layer_order_within,
    GroupCount, LayerConflict, LayerError, LayerOrder, StateTotal, ADVISORY_SHRINK_WORK,
    SHRINK_WORK,
};
pub use layout::{layout, LayoutError, Media, Sheet, SheetLabel, Sizing};
pub use lines::{crease_lines, smooth_creases, CreaseLine, LineKind, SmoothCrease};
pub use route::{route, route_with, RouteSearch};

pub use score::{score, score_lines};
pub use toolpath::{dashes, DashCode, ScoreSettings, ShortFolds, Stroke, ToolSetting, Toolpath};
pub use verify::{
    count_flat_states, verify, verify_searched, verify_within, Excess, FamilyReport, Report,
    Tolerances, Verdict,
};
