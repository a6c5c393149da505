//! Why a set of faces and edges is not a usable mesh.

/// Why a set of faces and edges is not a usable mesh. Each names the element at fault.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// Neither 3D nor flat positions were given.
    #[error("no vertex positions")]
    NoPositions,
    /// A coordinate is not a number or lies beyond any physical sheet.
    #[error("vertex {vertex} has a coordinate of {value:.3e} mm, which is not a finite length within 1 km")]
    CoordinateOutOfRange {
        /// The vertex.
        vertex: usize,
        /// The coordinate.
        value: f64,
    },
    /// No faces at all.
    #[error("no faces: the mesh is empty")]
    Empty,
    /// The two frames disagree on the vertex count.
    #[error("crease pattern has {flat} vertices but the folded form has {folded}")]
    FrameMismatch {
        /// Vertices in the flat frame.
        flat: usize,
        /// Vertices in the 3D frame.
        folded: usize,
    },
    /// A face or edge names a vertex that does not exist.
    #[error("{element} refers to vertex {vertex}, but there are only {count} vertices")]
    IndexOutOfRange {
        /// e.g. "face 3" or "edge 7".
        element: String,
        /// The bad index.
        vertex: usize,
        /// Number of vertices.
        count: usize,
    },
    /// A face repeats a vertex or has (nearly) zero area.
    #[error("face {face} {vertices:?} is degenerate (zero area or repeated vertex)")]
    DegenerateFace {
        /// Face index.
        face: usize,
        /// Its vertices.
        vertices: [usize; 3],
    },
    /// An edge joins a vertex to itself.
    #[error("edge {edge} joins vertex {vertex} to itself")]
    DegenerateEdge {
        /// Edge index.
        edge: usize,
        /// The vertex.
        vertex: usize,
    },
    /// Two edges join the same pair of vertices.
    #[error("edges {first} and {second} both join vertices {a} and {b}")]
    DuplicateEdge {
        /// First edge index.
        first: usize,
        /// Second edge index.
        second: usize,
        /// End vertex.
        a: usize,
        /// End vertex.
        b: usize,
    },
    /// More than two faces share an edge.
    #[error("non-manifold edge {a}–{b}: shared by {faces} faces")]
    NonManifoldEdge {
        /// End vertex.
        a: usize,
        /// End vertex.
        b: usize,
        /// How many faces share it.
        faces: usize,
    },
    /// The faces around a vertex do not form one fan.
    #[error("non-manifold vertex {vertex}: its faces do not form a single fan")]
    NonManifoldVertex {
        /// The vertex.
        vertex: usize,
    },
    /// No consistent orientation exists (a Möbius-like surface).
    #[error("the surface is not orientable (found at face {face})")]
    NonOrientable {
        /// A face where orientation conflicted.
        face: usize,
    },
    /// An edge bounds no face.
    #[error("edge {edge} ({a}–{b}) bounds no face")]
    DanglingEdge {
        /// Edge index.
        edge: usize,
        /// End vertex.
        a: usize,
        /// End vertex.
        b: usize,
    },
    /// A vertex belongs to no face.
    #[error("vertex {vertex} belongs to no face")]
    IsolatedVertex {
        /// The vertex.
        vertex: usize,
    },
}
