//! Design: the bundled patterns and anchors, the generators, the constraints and their
//! Jacobians, the solver, remeshing, design scripts, fitting, foldability and layer order.
//! One test crate per concept, each module a former crate of its own: compiled and
//! linked once (see tests/run).

mod common;

#[path = "design/anchors.rs"]
mod anchors;
#[path = "design/animate.rs"]
mod animate;
#[path = "design/constraints.rs"]
mod constraints;
#[path = "design/design_scripts.rs"]
mod design_scripts;
#[path = "design/errors.rs"]
mod errors;
#[path = "design/fit.rs"]
mod fit;
#[path = "design/flat_fold.rs"]
mod flat_fold;
#[path = "design/flat_folder.rs"]
mod flat_folder;
#[path = "design/foldability.rs"]
mod foldability;
#[path = "design/generate.rs"]
mod generate;
#[path = "design/layers.rs"]
mod layers;
#[path = "design/patterns.rs"]
mod patterns;
#[path = "design/remesh.rs"]
mod remesh;
#[path = "design/solver.rs"]
mod solver;
#[path = "design/tubes.rs"]
mod tubes;
