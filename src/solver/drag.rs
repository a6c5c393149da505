//! Dragging (§5): Euler integration of a user's drag. Each step asks the dragged vertices
//! to cover an equal share of their remaining way, spreads that wish smoothly to nearby
//! vertices (a surface, not a single point, is being pulled), projects it into the null
//! space, and corrects.

use super::{Solver, SolverError};
use crate::mesh::Vec3;
use serde::Deserialize;
use std::path::PathBuf;

/// One vertex pulled toward a target.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Move {
    /// The vertex.
    pub vertex: usize,
    /// Where it should go (mm).
    pub to: [f64; 3],
}

/// Moves made together over a number of steps.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Stage {
    /// Euler steps for this stage.
    pub steps: usize,
    /// The vertices pulled and their targets.
    pub moves: Vec<Move>,
}

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

/// What a drag did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DragReport {
    /// For each move of each stage: distance to target before and after (mm).
    pub distances: Vec<(usize, f64, f64)>,
    /// Edges collapsed during the stage.
    pub collapses: usize,
    /// Flat creases flipped during the stage.
    pub flips: usize,
}

/// Adds to `wish` the motion of pulling vertex `v` by `share`, spread to the surface
/// around it with the Gaussian weight exp(−|x_u − x_v|² / r²): a surface, not a single
/// point, is being pulled, and the null-space projection (eq. 10) then keeps what the
/// conditions allow.
pub fn pull(x: &[Vec3], v: usize, share: Vec3, radius: f64, wish: &mut [Vec3]) {
    let centre = x[v];
    for (u, d) in wish.iter_mut().enumerate() {
        let w = (-(x[u] - centre).norm_squared() / (radius * radius)).exp();
        *d += share * w;
    }
}

/// Runs one stage. `progress` is called after every accepted step.
pub fn run_stage(
    solver: &mut Solver,
    stage: &Stage,
    radius: f64,
    remesh: Option<f64>,
    progress: &mut dyn FnMut(),
) -> Result<DragReport, SolverError> {
    let mut stage = stage.clone();
    let (mut collapses, mut flips) = (0, 0);
    let n = solver.positions().len();
    for m in &stage.moves {
        if m.vertex >= n {
            return Err(SolverError::UnknownVertex {
                vertex: m.vertex,
                count: n,
            });
        }
    }
    let target = |m: &Move| Vec3::new(m.to[0], m.to[1], m.to[2]);
    let before: Vec<f64> = stage
        .moves
        .iter()
        .map(|m| (target(m) - solver.positions()[m.vertex]).norm())
        .collect();
    for k in 0..stage.steps {
        let n = solver.positions().len();
        let x = solver.positions().to_vec();
        let mut dx0 = vec![Vec3::zeros(); n];
        for m in &stage.moves {
            let share = (target(m) - x[m.vertex]) / (stage.steps - k) as f64;
            pull(&x, m.vertex, share, radius, &mut dx0);
        }
        solver.step(&dx0)?;
        if let Some(threshold) = remesh {
            let dragged: Vec<usize> = stage.moves.iter().map(|m| m.vertex).collect();
            let outcome = solver.remesh(&dragged, threshold);
            collapses += outcome.collapses;
            flips += outcome.flips;
            if let Some(map) = outcome.renumbered {
                for m in &mut stage.moves {
                    m.vertex = map[m.vertex];
                }
            }
        }
        progress();
    }
    let distances = stage
        .moves
        .iter()
        .zip(before)
        .map(|(m, b)| {
            (
                m.vertex,
                b,
                (target(m) - solver.positions()[m.vertex]).norm(),
            )
        })
        .collect();
    Ok(DragReport {
        distances,
        collapses,
        flips,
    })
}
