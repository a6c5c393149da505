//! Which points of a design represent its surface when it is fitted to a target.
//!
//! A corrugated pattern (Miura-ori, Yoshimura, waterbomb, Resch) has its vertices on two
//! sheets, the ridges and the furrows: pulled one by one onto a surface, the corrugation
//! would be ironed flat. So by default each *facet* — the faces a flat line (target 0:
//! a triangulation line or a join) holds together, the pattern's own polygons — is
//! measured by the mean of its vertices: a Miura-ori parallelogram has two corners on a
//! ridge and two in a furrow, and its mean lies on the mid-surface, which then follows the
//! target while the corrugation keeps its depth. A facet of more than [`MAX_FACET`]
//! vertices is no cell, and its vertices are measured one by one; so is every vertex of a
//! pattern without a folding crease (a plain sheet), which is what crumpled paper wants.

use crate::mesh::{Assignment, Mesh, UnionFind};

/// The largest facet measured by its mean: a hexagon with its centre, and room to spare.
pub const MAX_FACET: usize = 8;

/// How the surface points are chosen (`--surface`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceChoice {
    /// Each facet by the mean of its vertices (facets past [`MAX_FACET`] vertex by vertex).
    Mid,
    /// Every vertex by itself.
    All,
}

impl SurfaceChoice {
    /// Every choice, by name.
    pub const ALL: [SurfaceChoice; 2] = [SurfaceChoice::Mid, SurfaceChoice::All];

    /// The name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            SurfaceChoice::Mid => "mid",
            SurfaceChoice::All => "all",
        }
    }

    /// Looks a choice up by name.
    pub fn parse(name: &str) -> Result<SurfaceChoice, String> {
        SurfaceChoice::ALL
            .into_iter()
            .find(|c| c.name() == name)
            .ok_or_else(|| format!("unknown surface \"{name}\" (choose mid or all)"))
    }
}

/// The surface groups of `mesh`: lists of vertex ids, each measured by its mean; every
/// vertex is in at least one.
pub fn surface_groups(mesh: &Mesh, choice: SurfaceChoice) -> Vec<Vec<usize>> {
    let n = mesh.vertex_count();
    // Without a crease that folds there is no corrugation to keep: a plain sheet is
    // measured vertex by vertex whatever its facets.
    let corrugated = mesh.edges().iter().any(|e| e.target != 0.0);
    if choice == SurfaceChoice::All || !corrugated {
        return (0..n).map(|v| vec![v]).collect();
    }
    let faces = mesh.faces();
    let topology = mesh.topology();
    let mut facets = UnionFind::new(faces.len());
    for (e, edge) in mesh.edges().iter().enumerate() {
        let holds =
            edge.target == 0.0 && matches!(edge.assignment, Assignment::Flat | Assignment::Join);
        if let [Some(a), Some(b)] = topology.edge_faces[e] {
            if holds {
                facets.union(a, b);
            }
        }
    }
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); faces.len()];
    for (f, face) in faces.iter().enumerate() {
        let root = facets.find(f);
        members[root].extend(face);
    }
    let mut groups = Vec::new();
    for mut m in members.into_iter().filter(|m| !m.is_empty()) {
        m.sort_unstable();
        m.dedup();
        if m.len() <= MAX_FACET {
            groups.push(m);
        } else {
            groups.extend(m.into_iter().map(|v| vec![v]));
        }
    }
    // A vertex on no face cannot happen in a valid mesh, but every vertex must be measured.
    let mut seen = vec![false; n];
    groups.iter().flatten().for_each(|&v| seen[v] = true);
    groups.extend((0..n).filter(|&v| !seen[v]).map(|v| vec![v]));
    groups.sort();
    groups.dedup();
    groups
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{generate, Params, PatternKind};

    #[test]
    fn a_miura_is_measured_by_its_parallelograms_and_a_plain_sheet_by_its_vertices() {
        let mut p = Params::defaults(PatternKind::Miura);
        (p.nx, p.ny) = (4, 3);
        let miura = generate(&p).unwrap();
        let groups = surface_groups(&miura, SurfaceChoice::Mid);
        assert_eq!(groups.len(), 12);
        assert!(groups.iter().all(|g| g.len() == 4));
        // Each parallelogram's mean lies halfway between the ridge and the furrow: its
        // corners are two high and two low.
        for g in &groups {
            let mut z: Vec<f64> = g.iter().map(|&v| miura.positions()[v].z).collect();
            z.sort_by(f64::total_cmp);
            assert!((z[0] - z[1]).abs() < 1e-9 && (z[2] - z[3]).abs() < 1e-9);
            assert!(z[2] - z[1] > 1.0);
        }
        let plane = generate(&Params::defaults(PatternKind::Plane)).unwrap();
        let groups = surface_groups(&plane, SurfaceChoice::Mid);
        assert_eq!(groups.len(), plane.vertex_count());
        let all = surface_groups(&miura, SurfaceChoice::All);
        assert_eq!(all.len(), miura.vertex_count());
    }
}
