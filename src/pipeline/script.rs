//! The design-script format: a reproducible design as TOML, a base pattern and a sequence
//! of drags, then perhaps a fit (`crease deform --script`, the bundled `patterns/*.toml`).
//! The solver takes its stages ([`Stage`]); the file's other keys are the job's
//! ([`super::DesignJob::from_script`]).

use crate::solver::Stage;
use serde::Deserialize;
use std::path::PathBuf;

/// A reproducible design: a base pattern and a sequence of drags (TOML).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Script {
    /// The pattern to start from, relative to the script's folder.
    pub base: Option<PathBuf>,
    /// "design" (default) or "simulation".
    pub mode: Option<String>,
    /// Condition names; default: what the pattern's assignment calls for.
    pub conditions: Option<Vec<String>>,
    /// Twist allowance α for every flat crease (§2.4).
    pub alpha: Option<f64>,
    /// Vertices held still; default: the face nearest the middle.
    pub fix: Option<Vec<usize>>,
    /// Falloff radius of a drag (mm); default a quarter of the design's diagonal.
    pub radius: Option<f64>,
    /// Fold the base toward this fraction of its targets first (simulation mode).
    pub fold: Option<f64>,
    /// Collapse edges shorter than this fraction of the mean edge (paper §4); absent: no
    /// remeshing.
    pub remesh: Option<f64>,
    /// The drags, in order.
    #[serde(default)]
    pub stage: Vec<Stage>,
    /// A fit to a target surface after the drags (`crease fit`).
    pub fit: Option<ScriptFit>,
}

/// A script's `[fit]`: the target surface and the fit's settings (as `crease fit`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ScriptFit {
    /// The target surface (.obj, .stl), relative to the script's folder.
    pub target: PathBuf,
    /// "mid" (default) or "all".
    pub surface: Option<String>,
    /// Steps at most.
    pub steps: Option<usize>,
    /// The distance goal in mm.
    pub within: Option<f64>,
    /// Place the design on the target first (default true).
    pub align: Option<bool>,
}

impl Script {
    /// Parses script text.
    pub fn parse(text: &str) -> Result<Script, String> {
        toml::from_str(text).map_err(|e| crate::io::toml_error(text, &e))
    }
}
