//! A summary of a mesh for people: counts, size, crease types, shape.

use super::{Assignment, Mesh, TopologySummary};
use std::fmt;

/// Counts and extents of a mesh, printed by `crease info`.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshInfo {
    /// Pattern title.
    pub title: String,
    /// Vertex count.
    pub vertices: usize,
    /// Interior vertex count.
    pub interior_vertices: usize,
    /// Edges the source file had.
    pub source_edges: usize,
    /// Edges crease added to triangulate polygons.
    pub added_edges: usize,
    /// Triangle count.
    pub triangles: usize,
    /// Whether a 3D folded form is present.
    pub has_3d: bool,
    /// Whether a flat crease pattern is present.
    pub has_crease_pattern: bool,
    /// 3D bounding-box size (mm).
    pub size_3d: [f64; 3],
    /// Crease-pattern bounding-box size (mm), when known.
    pub size_flat: Option<[f64; 2]>,
    /// Edge count per assignment, in FOLD letter order B M V F U C J.
    pub assignments: Vec<(Assignment, usize)>,
    /// Shape of the surface.
    pub topology: TopologySummary,
}

impl Mesh {
    /// Summarises the mesh.
    pub fn info(&self) -> MeshInfo {
        let (lo, hi) = self.bounding_box();
        let size_flat = self.crease_pattern_size().map(|s| [s.x, s.y]);
        let kinds = [
            Assignment::Boundary,
            Assignment::Mountain,
            Assignment::Valley,
            Assignment::Flat,
            Assignment::Unassigned,
            Assignment::Cut,
            Assignment::Join,
        ];
        let assignments = kinds
            .iter()
            .map(|&k| (k, self.edges().iter().filter(|e| e.assignment == k).count()))
            .filter(|&(_, n)| n > 0)
            .collect();
        let added = self.edges().iter().filter(|e| e.synthetic).count();
        MeshInfo {
            title: self.title.clone(),
            vertices: self.vertex_count(),
            interior_vertices: (0..self.vertex_count())
                .filter(|&v| self.is_interior(v))
                .count(),
            source_edges: self.edges().len() - added,
            added_edges: added,
            triangles: self.faces().len(),
            has_3d: self.has_3d(),
            has_crease_pattern: self.crease_pattern().is_some(),
            size_3d: [hi.x - lo.x, hi.y - lo.y, hi.z - lo.z],
            size_flat,
            assignments,
            topology: self.shape(),
        }
    }
}

impl fmt::Display for MeshInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.title.is_empty() {
            writeln!(f, "title:        {}", self.title)?;
        }
        writeln!(
            f,
            "vertices:     {} ({} interior)",
            self.vertices, self.interior_vertices
        )?;
        if self.added_edges > 0 {
            writeln!(
                f,
                "edges:        {} (+{} flat creases added to triangulate polygons)",
                self.source_edges, self.added_edges
            )?;
        } else {
            writeln!(f, "edges:        {}", self.source_edges)?;
        }
        writeln!(f, "triangles:    {}", self.triangles)?;
        let yes = |b: bool| if b { "yes" } else { "no" };
        writeln!(
            f,
            "frames:       3D folded form: {}, crease pattern: {}",
            yes(self.has_3d),
            yes(self.has_crease_pattern)
        )?;
        let [x, y, z] = self.size_3d;
        writeln!(f, "size 3D:      {x:.3} × {y:.3} × {z:.3} mm")?;
        if let Some([x, y]) = self.size_flat {
            writeln!(f, "size flat:    {x:.3} × {y:.3} mm")?;
        }
        let hist: Vec<String> = self
            .assignments
            .iter()
            .map(|(a, n)| format!("{} {n}", a.fold_letter()))
            .collect();
        writeln!(f, "assignments:  {}", hist.join(", "))?;
        let t = &self.topology;
        if t.is_tube {
            // A tube's second rim is not a hole in its paper: it is one strip, closed.
            return writeln!(
                f,
                "topology:     cylinder (a tube: one strip closed along a seam, 2 rims, χ = {})",
                t.euler_characteristic
            );
        }
        writeln!(
            f,
            "topology:     {} ({} piece(s), {} boundary loop(s), {} hole(s), χ = {})",
            if t.is_disk {
                "disk"
            } else {
                "neither a disk nor a tube"
            },
            t.components,
            t.boundary_loops,
            t.holes,
            t.euler_characteristic
        )
    }
}

impl Mesh {
    /// One line per vertex, so vertex ids can be found without reading the file: id, 3D
    /// position, crease-pattern position, creases by kind (M/V/other) and whether it lies
    /// on the boundary.
    pub fn vertex_table(&self) -> String {
        use fmt::Write;
        let mut out = String::from(
            "vertex         x         y         z      cp.x      cp.y   M  V  other  where\n",
        );
        let topo = self.topology();
        for (v, p) in self.positions().iter().enumerate() {
            let (mut m, mut val, mut other) = (0, 0, 0);
            for &e in &topo.fans[v].spokes {
                match self.edges()[e].assignment {
                    Assignment::Mountain => m += 1,
                    Assignment::Valley => val += 1,
                    _ => other += 1,
                }
            }
            let cp = self
                .crease_pattern()
                .map(|f| format!("{:>9.3} {:>9.3}", f[v].x, f[v].y))
                .unwrap_or_else(|| format!("{:>9} {:>9}", "-", "-"));
            let place = if topo.fans[v].boundary {
                "boundary"
            } else {
                "interior"
            };
            let _ = writeln!(
                out,
                "{v:>6} {:>9.3} {:>9.3} {:>9.3} {cp} {m:>3}{val:>3}{other:>7}  {place}",
                p.x, p.y, p.z
            );
        }
        out
    }
}
