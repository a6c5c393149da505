//! crease — design freeform variations of origami (Tachi 2010) and fabricate them.
//!
//! Data flows one way: [`mesh`] → constraints → solver → fabrication → output → plotter.
#![warn(missing_docs)]

pub mod allocator;
pub mod constraints;
pub mod fab;
pub mod fit;
pub mod generate;
pub mod geometry;
pub mod io;
pub mod limits;
pub mod mesh;
pub mod output;
pub mod pipeline;
pub mod plotter;
pub mod solver;
pub mod studio;
pub mod surface;
