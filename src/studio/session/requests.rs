//! What the page may ask of the session, parsed from JSON, and what it gets back.

use serde::Deserialize;

/// A request to the session, already parsed from JSON.
#[derive(Debug)]
pub enum Command {
    /// The full state (`GET /api/state`).
    State,
    /// Pull `vertex` toward `target` (mm, 3D frame) until released.
    Drag {
        /// The vertex.
        vertex: usize,
        /// Where the pointer is.
        target: [f64; 3],
    },
    /// End the drag.
    Release,
    /// Pin or unpin a vertex.
    Pin {
        /// The vertex.
        vertex: usize,
        /// Pinned afterwards.
        pinned: bool,
    },
    /// Undo the last change.
    Undo,
    /// Redo the last undone change.
    Redo,
    /// Change mode, conditions, α or remeshing.
    Settings(Settings),
    /// Fold toward a fraction of every crease's target (simulation mode).
    Fold {
        /// The fraction, in [0, 1].
        amount: f64,
    },
    /// Start from a generated pattern.
    Generate(GenerateRequest),
    /// Start from a file, read on the connection's own thread (a large upload's parsing
    /// must not hold up the session's other requests).
    Open {
        /// Its name (the extension picked the format).
        name: String,
        /// What was read from it.
        imported: Box<crate::io::Imported>,
    },
    /// The design as the FOLD file `deform` writes.
    SaveFold,
    /// Run `fab` on the design.
    Fabricate(FabRequest),
    /// A file of the last fabrication.
    FabFile(String),
    /// Fold the design from flat and keep the motion, for the page to play.
    Motion(MotionRequest),
    /// The motion as a file in a format by its extension (glb, fold, png).
    MotionFile(String),
    /// Load a target surface for the fit, read from a file (.obj, .stl) on the
    /// connection's own thread.
    LoadTarget {
        /// Its name (the extension picked the format).
        name: String,
        /// The surface read from it.
        surface: Box<crate::surface::TriSurface>,
    },
    /// Place the loaded target: shift, turn and offset from where its file put it.
    PlaceTarget(TargetPlacement),
    /// Drop the target (and stop a fit).
    ClearTarget,
    /// The target as placed, for drawing.
    TargetMesh,
    /// Start fitting the design to the target, live.
    Fit(FitRequest),
    /// Stop the fit where it is.
    StopFit,
    /// Panics inside the session (tests of the mailbox's guard only).
    #[cfg(test)]
    Panic,
}

/// Settings a request may change; absent fields stay.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// "design" or "simulation".
    pub mode: Option<String>,
    /// Condition families held in design mode; empty means the design's default set.
    pub conditions: Option<Vec<String>>,
    /// Twist allowance α of facet lines, [0, 1).
    pub alpha: Option<f64>,
    /// Remeshing threshold (fraction of the mean edge), or `null`/absent to leave it.
    pub remesh: Option<f64>,
    /// Turn remeshing off.
    pub remesh_off: Option<bool>,
}

/// A generated starting pattern.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GenerateRequest {
    /// miura, waterbomb, yoshimura, resch, plane, curved.
    pub pattern: String,
    /// Cells across.
    pub nx: Option<usize>,
    /// Cells along.
    pub ny: Option<usize>,
    /// Cell size (mm).
    pub size: Option<f64>,
    /// Miura angle (degrees).
    pub angle: Option<f64>,
    /// Closed-form fold amount, or none for flat.
    pub fold: Option<f64>,
}

/// Where the loaded target goes, from where its file put it (absolute, so the page's
/// sliders can be sent as they stand).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TargetPlacement {
    /// Shift (mm) along x, y, z.
    pub shift: Option<[f64; 3]>,
    /// Turns (degrees) about x, y and z through the target's centre, in that order.
    pub turn: Option<[f64; 3]>,
    /// Offset along the surface's normals (mm).
    pub offset: Option<f64>,
}

/// A fit's settings; absent fields take `crease fit`'s defaults.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitRequest {
    /// Steps at most.
    pub steps: Option<usize>,
    /// The distance goal (mm).
    pub within: Option<f64>,
    /// "mid" or "all".
    pub surface: Option<String>,
}

/// A request for the folding motion.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionRequest {
    /// Steps from flat (`crease animate --frames`); default as many of
    /// `PLAYED_FRAMES` (60) as the page can hold.
    pub frames: Option<usize>,
}

/// A fabrication request.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FabRequest {
    /// Machine profile name.
    pub machine: String,
    /// Media (a4, a3, letter, WxHmm); default the machine's.
    pub media: Option<String>,
    /// Scale to this width (mm).
    pub width: Option<f64>,
    /// Scale to the largest size the media takes within its margins (`fab --fit`).
    pub fit: Option<bool>,
    /// Margin on every side (mm); default the machine's (`fab --margin`).
    pub margin: Option<f64>,
    /// Split a sheet too large for the media over pages (`fab --tile`).
    pub tile: Option<bool>,
    /// Fabricate even if verification fails.
    pub force: Option<bool>,
}

/// What a request produced.
#[derive(Debug)]
pub enum Reply {
    /// JSON.
    Json(serde_json::Value),
    /// A file to download.
    File {
        /// File name.
        name: String,
        /// Bytes.
        bytes: Vec<u8>,
    },
}

/// Why a request was refused: an HTTP status (4xx) and a one-line message.
#[derive(Debug, Clone, PartialEq)]
pub struct Refusal {
    /// 400 bad request, 404 unknown, 409 conflicts with the state, 422 cannot be done.
    pub status: u16,
    /// What is wrong and what to do.
    pub message: String,
}

impl Refusal {
    pub(super) fn bad(message: impl Into<String>) -> Refusal {
        Refusal {
            status: 400,
            message: message.into(),
        }
    }
    pub(super) fn conflict(message: impl Into<String>) -> Refusal {
        Refusal {
            status: 409,
            message: message.into(),
        }
    }
    pub(super) fn failed(message: impl Into<String>) -> Refusal {
        Refusal {
            status: 422,
            message: message.into(),
        }
    }
}
