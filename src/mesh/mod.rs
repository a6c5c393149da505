//! The design: a triangle mesh whose edges are creases with a target fold angle.
//!
//! Angles inside crease use the paper's sign convention: a mountain fold is `+π`, a valley
//! `−π` (Tachi 2010, §2). The FOLD convention (degrees, valley positive) is converted in
//! [`crate::io`] and nowhere else.

mod chains;
mod cuts;
mod error;
mod info;
mod seam;
mod source;
mod topology;
mod triangulate;
mod union_find;

pub use chains::{boundary_runs, crease_chains, curve_runs, run_edges, turn, CreaseChain, CORNER};
pub use cuts::split_along_cuts;
pub use error::MeshError;
pub use info::MeshInfo;
pub use seam::{seam_keys, SeamError, Strip};
pub use source::{polygon_faces, Fingerprint, SourceAttachment};
pub use topology::{Topology, TopologySummary, VertexFan};
pub use triangulate::{triangulate_polygon, TriangulationBudget};
pub use union_find::UnionFind;

use nalgebra::{SVector, Vector2, Vector3};
use std::f64::consts::PI;

/// A point or direction in 3D, millimetres.
pub type Vec3 = Vector3<f64>;
/// A point or direction in the crease-pattern plane, millimetres.
pub type Vec2 = Vector2<f64>;

/// What a crease does, as in FOLD's `edges_assignment`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Assignment {
    /// Paper boundary (`B`).
    Boundary,
    /// Mountain fold (`M`), target `+π`.
    Mountain,
    /// Valley fold (`V`), target `−π`.
    Valley,
    /// Crease that stays unfolded, such as a triangulation line (`F`), target 0.
    Flat,
    /// Crease whose fold is not prescribed (`U`); its angle is free.
    Unassigned,
    /// A cut through the paper (`C`, FOLD 1.2). Import splits the mesh along cuts.
    Cut,
    /// A join line (`J`, FOLD 1.2), treated like [`Assignment::Flat`].
    Join,
}

impl Assignment {
    /// Parses a FOLD `edges_assignment` letter (either case).
    pub fn from_fold(letter: &str) -> Option<Self> {
        Some(match letter {
            "B" | "b" => Self::Boundary,
            "M" | "m" => Self::Mountain,
            "V" | "v" => Self::Valley,
            "F" | "f" => Self::Flat,
            "U" | "u" => Self::Unassigned,
            "C" | "c" => Self::Cut,
            "J" | "j" => Self::Join,
            _ => return None,
        })
    }

    /// The FOLD letter.
    pub fn fold_letter(self) -> &'static str {
        match self {
            Self::Boundary => "B",
            Self::Mountain => "M",
            Self::Valley => "V",
            Self::Flat => "F",
            Self::Unassigned => "U",
            Self::Cut => "C",
            Self::Join => "J",
        }
    }

    /// The target fold angle a crease of this kind is driven to (paper §2: mountain `+π`,
    /// valley `−π`, anything else 0).
    pub fn default_target(self) -> f64 {
        match self {
            Self::Mountain => PI,
            Self::Valley => -PI,
            _ => 0.0,
        }
    }

    /// Whether the edge lies on the paper's perimeter or a cut.
    pub fn is_boundary(self) -> bool {
        matches!(self, Self::Boundary | Self::Cut)
    }

    /// Mountain or valley: a crease with a prescribed direction.
    pub fn is_folded(self) -> bool {
        matches!(self, Self::Mountain | Self::Valley)
    }
}

/// The key of the undirected edge between `a` and `b`: its ends in increasing order.
pub fn edge_key(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

/// One crease (or boundary segment) of the mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    /// The two end vertices.
    pub vertices: [usize; 2],
    /// Mountain, valley, flat, …
    pub assignment: Assignment,
    /// Target fold angle in radians, paper convention (mountain `+π`). For merged creases
    /// (§4) it may be any multiple of π.
    pub target: f64,
    /// The fold angle this crease had in its source (FOLD `edges_foldAngle`, SVG opacity),
    /// radians, paper convention. Used when writing files back; geometry computes its own.
    pub fold_angle: f64,
    /// Twist allowance α of a target-0 crease (§2.4): its fold angle stays in `[−απ, απ]`.
    pub alpha: f64,
    /// True when crease inserted this edge to triangulate a polygon of the source file.
    pub synthetic: bool,
}

impl Edge {
    /// A flat line crease added to triangulate a polygon face of the source: the file did
    /// not have it, and formats of lines (SVG, `.cp`) leave it out so that converting does
    /// not add lines (reading the file back triangulates the polygon again).
    pub fn is_triangulation_line(&self) -> bool {
        self.synthetic && self.assignment == Assignment::Flat
    }

    /// A crease with the default target, fold angle equal to the target and α = 0.
    pub fn new(a: usize, b: usize, assignment: Assignment) -> Self {
        let target = assignment.default_target();
        Edge {
            vertices: [a, b],
            assignment,
            target,
            fold_angle: target,
            alpha: 0.0,
            synthetic: false,
        }
    }

    /// The edge's [`edge_key`].
    pub fn key(&self) -> (usize, usize) {
        edge_key(self.vertices[0], self.vertices[1])
    }

    /// The other end of the edge seen from `v`.
    pub fn other(&self, v: usize) -> usize {
        if self.vertices[0] == v {
            self.vertices[1]
        } else {
            self.vertices[0]
        }
    }
}

/// A validated triangle mesh with crease data, its 3D form and (when known) its flat
/// crease pattern. Faces are counter-clockwise seen from the front of the paper.
#[derive(Clone, Debug)]
pub struct Mesh {
    positions: Vec<Vec3>,
    flat: Option<Vec<Vec2>>,
    has_3d: bool,
    faces: Vec<[usize; 3]>,
    edges: Vec<Edge>,
    topology: Topology,
    /// Pattern name or title carried into output files.
    pub title: String,
    /// Patterns whose topology must stay (Resch, §6.4) set this; remeshing then refuses.
    pub lock_topology: bool,
    /// Groups of vertices that meet in one point of the folded form: the three corners of
    /// each of Resch's tucks (§6.4). Kept coincident by the `coincidence` conditions.
    pub coincident: Vec<Vec<usize>>,
    /// A tube's seam (paper §7): the edges, as [`edge_key`] pairs, it is cut open along to
    /// be laid out as one strip. Empty for a sheet, and for a tube whose seam is the
    /// shortest path between its rims ([`Mesh::seam_edges`]).
    pub seam: Vec<[usize; 2]>,
    /// Rounding step of the source file's coordinates in mm (half its last decimal place),
    /// 0 when exact. Verification does not count rounding as a design error.
    pub coordinate_precision: f64,
    /// What the source file had beyond the mesh, kept for lossless conversion.
    pub source: Option<SourceAttachment>,
}

/// Largest coordinate a design may have, mm: a kilometre is beyond any sheet of paper,
/// and past it the geometry's tolerances mean nothing.
pub const MAX_COORDINATE_MM: f64 = 1e6;

/// Raw parts of a mesh before validation.
#[derive(Clone, Debug, Default)]
pub struct MeshParts {
    /// 3D positions; when `None`, the flat positions lifted to `z = 0` are used.
    pub positions: Option<Vec<Vec3>>,
    /// Crease-pattern positions, when known.
    pub flat: Option<Vec<Vec2>>,
    /// Triangles, vertex indices.
    pub faces: Vec<[usize; 3]>,
    /// Every edge the source lists; edges of `faces` that are missing get
    /// [`Assignment::Flat`] if interior and [`Assignment::Boundary`] if not.
    pub edges: Vec<Edge>,
}

impl Mesh {
    /// Validates the parts (indices, degenerate and non-manifold elements, orientation) and
    /// builds adjacency. Faces are reoriented consistently, counter-clockwise in the crease
    /// pattern when one is given.
    pub fn new(parts: MeshParts) -> Result<Mesh, MeshError> {
        let MeshParts {
            positions,
            flat,
            faces,
            edges,
        } = parts;
        let has_3d = positions.is_some();
        let positions = match (positions, &flat) {
            (Some(p), _) => p,
            (None, Some(f)) => f.iter().map(|q| Vec3::new(q.x, q.y, 0.0)).collect(),
            (None, None) => return Err(MeshError::NoPositions),
        };
        if let Some(f) = &flat {
            if f.len() != positions.len() {
                return Err(MeshError::FrameMismatch {
                    flat: f.len(),
                    folded: positions.len(),
                });
            }
        }
        let coords = positions
            .iter()
            .enumerate()
            .flat_map(|(v, p)| p.iter().map(move |&c| (v, c)))
            .chain(
                flat.iter()
                    .flatten()
                    .enumerate()
                    .flat_map(|(v, p)| p.iter().map(move |&c| (v, c))),
            );
        for (vertex, value) in coords {
            if !(value.is_finite() && value.abs() <= MAX_COORDINATE_MM) {
                return Err(MeshError::CoordinateOutOfRange { vertex, value });
            }
        }
        let (faces, edges, topology) = topology::build(&positions, flat.as_deref(), faces, edges)?;
        Ok(Mesh {
            positions,
            flat,
            has_3d,
            faces,
            edges,
            topology,
            title: String::new(),
            lock_topology: false,
            coincident: Vec::new(),
            seam: Vec::new(),
            coordinate_precision: 0.0,
            source: None,
        })
    }

    /// 3D vertex positions (mm). For a file with only a crease pattern this is that
    /// pattern at `z = 0`.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Replaces the 3D positions (same vertex count), e.g. after a solver step.
    pub fn set_positions(&mut self, positions: Vec<Vec3>) {
        assert_eq!(positions.len(), self.positions.len());
        self.positions = positions;
        self.has_3d = true;
    }

    /// The crease pattern: the sheet's flat positions (mm), when known. ("Flat" alone
    /// names other things too: the flat-folded state, a crease that does not fold.)
    pub fn crease_pattern(&self) -> Option<&[Vec2]> {
        self.flat.as_deref()
    }

    /// The crease pattern's width and height (mm), when known.
    pub fn crease_pattern_size(&self) -> Option<Vec2> {
        self.crease_pattern().map(|f| {
            let (lo, hi) = bounds(f);
            hi - lo
        })
    }

    /// Sets or replaces the crease pattern.
    pub fn set_crease_pattern(&mut self, flat: Vec<Vec2>) {
        assert_eq!(flat.len(), self.positions.len());
        self.flat = Some(flat);
    }

    /// Whether the 3D positions came from a folded form rather than the crease pattern.
    pub fn has_3d(&self) -> bool {
        self.has_3d
    }

    /// Triangles, counter-clockwise from the front.
    pub fn faces(&self) -> &[[usize; 3]] {
        &self.faces
    }

    /// Edges (creases and boundary).
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// Mutable access to crease data (assignment, target, α); topology is unchanged.
    pub fn edges_mut(&mut self) -> &mut [Edge] {
        &mut self.edges
    }

    /// Adjacency built at construction.
    pub fn topology(&self) -> &Topology {
        &self.topology
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// The surface's shape: pieces, boundary loops, χ; whether a disk or a tube.
    pub fn shape(&self) -> TopologySummary {
        self.topology
            .summary(self.vertex_count(), self.edges.len(), self.faces.len())
    }

    /// Whether vertex `v` is interior (its faces close around it).
    pub fn is_interior(&self, v: usize) -> bool {
        !self.topology.fans[v].boundary
    }

    /// Decomposes the mesh, e.g. to rebuild it after a topology change.
    pub fn into_parts(self) -> MeshParts {
        MeshParts {
            positions: self.has_3d.then_some(self.positions),
            flat: self.flat,
            faces: self.faces,
            edges: self.edges,
        }
    }

    /// Axis-aligned bounding box of the 3D positions: (min, max).
    pub fn bounding_box(&self) -> (Vec3, Vec3) {
        bounds(&self.positions)
    }
}

/// Distance from `p` to the segment `a`–`b` in the plane (to `a` if the segment is a point).
pub fn distance_to_segment(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let d = b - a;
    let len2 = d.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + d * t - p).norm()
}

/// Axis-aligned bounds (min, max) of points in any dimension; (+∞, −∞) for none.
pub fn bounds<const D: usize>(points: &[SVector<f64, D>]) -> (SVector<f64, D>, SVector<f64, D>) {
    points.iter().fold(
        (
            SVector::repeat(f64::INFINITY),
            SVector::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    )
}
