//! Resch's triangular pattern (§6.4) and its fully folded state.
//!
//! On an equilateral lattice of side `l` every triangle has one of three roles:
//! - **tucks**: one upward triangle in three, chosen so every lattice point is a corner of
//!   exactly one tuck. A tuck collapses so that its three corners meet in one point of the
//!   folded surface ("a group of three vertices forms a vertex", §6.4): creases run from its
//!   centre to the corners and to the side midpoints.
//! - **fins**: every downward triangle. One side is a tuck side; the median from the
//!   opposite corner folds the fin in half into a vertical right triangle hanging under one
//!   edge of the folded surface.
//! - **tiles**: the other upward triangles. They stay rigid and, fully folded, tile the plane
//!   edge to edge (half of them turned by +30°, half by −30°), hiding fins and tucks behind.
//!
//! Fully folded, the tuck centres become the folded surface's vertices: the tuck-centre
//! lattice (spacing `√3 l`) shrunk by `√3`. That closed form is exact and gives every
//! crease its target angle, so the assignment cannot disagree with the geometry. The
//! corners of each tuck are recorded as a coincidence group: with the `coincidence`
//! conditions a design keeps its tucks closed behind a polyhedral surface of tiles.

use super::lattice::{build, rows_zipper};
use super::{GenerateError, Params};
use crate::mesh::{edge_key as key, Assignment, Mesh, MeshParts, Vec2, Vec3};
use std::collections::HashMap;
use std::f64::consts::PI;

const SQRT3: f64 = 1.732_050_807_568_877_2;

/// A lattice point in axial coordinates: position `(i + j/2, j·√3/2)·l`.
type Axial = (i64, i64);

fn axial_of(p: Vec2, l: f64) -> Axial {
    let j = (p.y / (l * SQRT3 / 2.0)).round();
    let i = (p.x / l - j / 2.0).round();
    (i as i64, j as i64)
}

fn point((i, j): Axial, l: f64) -> Vec2 {
    Vec2::new((i as f64 + j as f64 / 2.0) * l, j as f64 * l * SQRT3 / 2.0)
}

/// Upward triangle `(i, j)` has corners `(i, j)`, `(i+1, j)`, `(i, j+1)`; one in three is
/// a tuck, chosen so that the tucks' corners cover every lattice point exactly once.
fn is_tuck((i, j): Axial) -> bool {
    (i - j).rem_euclid(3) == 0
}

/// The upward triangle's name: its lower-left corner (lowest row, then leftmost).
fn upward_base(corners: [Axial; 3]) -> Axial {
    corners
        .into_iter()
        .min_by_key(|&(i, j)| (j, i))
        .expect("three corners")
}

/// The third corner of the triangle on the other side of `u v` from `opposite`.
fn across(u: Axial, v: Axial, opposite: Axial) -> Axial {
    (u.0 + v.0 - opposite.0, u.1 + v.1 - opposite.1)
}

/// The tuck having lattice point `p` as a corner.
fn tuck_of((i, j): Axial) -> Axial {
    [(i, j), (i - 1, j), (i, j - 1)]
        .into_iter()
        .find(|&t| is_tuck(t))
        .expect("one of the three upward triangles at a point is a tuck")
}

/// Where the tuck's three corners meet when fully folded (on the plane z = 0).
fn folded_vertex(t: Axial, l: f64) -> Vec3 {
    let c = point(t, l) + Vec2::new(l / 2.0, l * SQRT3 / 6.0);
    Vec3::new(c.x, c.y, 0.0) / SQRT3
}

/// What a crease is, which decides its assignment.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Role {
    /// Between a tile and a fin: the surface turns down into the fin.
    TileEdge,
    /// A fin's median: the fin's two halves fold onto each other (valley, −π).
    FinMedian,
    /// Tuck centre to side midpoint: the tuck's side folds in half (valley, −π).
    TuckMidline,
    /// Tuck centre to corner: between two of the tuck's three fins.
    TuckSpoke,
    /// Half of a tuck side, between tuck and fin: flat at both ends of the motion.
    TuckSide,
}

/// Resch's triangular pattern on `p.nx × p.ny` lattice cells of side `p.size`, with its
/// fully folded 3D state when `p.fold == Some(1.0)`.
pub fn resch(p: &Params) -> Result<Mesh, GenerateError> {
    if let Some(t) = p.fold {
        if t != 1.0 {
            return Err(GenerateError::BadParameter(format!(
                "resch has a closed-form 3D state only fully folded (--fold 1), not {}; \
                 fold it part way with `crease fold`",
                crate::limits::short(t)
            )));
        }
    }
    let l = p.size;
    let rows: Vec<Vec<f64>> = (0..=p.ny)
        .map(|j| {
            let shift = if j % 2 == 1 { 0.5 } else { 0.0 };
            (0..=p.nx).map(|i| (i as f64 + shift) * l).collect()
        })
        .collect();
    let (lattice, lattice_faces) = rows_zipper(&rows, l * SQRT3 / 2.0);
    let ax: Vec<Axial> = lattice.iter().map(|&q| axial_of(q, l)).collect();
    let mut b = Builder {
        flat: lattice.clone(),
        folded: ax.iter().map(|&a| folded_vertex(tuck_of(a), l)).collect(),
        lattice,
        ax,
        l,
        roles: HashMap::new(),
        midpoints: HashMap::new(),
        faces: Vec::new(),
    };
    for &corners in &lattice_faces {
        let low = corners
            .iter()
            .map(|&v| b.ax[v].1)
            .min()
            .expect("three corners");
        let upward = corners.iter().filter(|&&v| b.ax[v].1 == low).count() == 2;
        if upward {
            b.upward(corners);
        } else {
            b.fin(corners);
        }
    }
    let mut parts = build(b.flat, b.faces, |_, _| Assignment::Unassigned, 0.0);
    let probe = Mesh::new(MeshParts {
        positions: Some(b.folded.clone()),
        ..parts.clone()
    })?;
    assign_by_role(&mut parts, &b.roles, &crate::geometry::fold_angles(&probe));
    if p.fold.is_some() {
        parts.positions = Some(b.folded);
    }
    let mut mesh = Mesh::new(parts)?;
    // The lattice points come first, in order; those of one tuck meet when folded.
    let mut groups: HashMap<Axial, Vec<usize>> = HashMap::new();
    for (v, &a) in b.ax.iter().enumerate() {
        groups.entry(tuck_of(a)).or_default().push(v);
    }
    let mut coincident: Vec<Vec<usize>> = groups.into_values().filter(|g| g.len() > 1).collect();
    coincident.sort();
    mesh.coincident = coincident;
    Ok(mesh)
}

/// The pattern as it is built: vertices flat and fully folded, faces, and each crease's
/// role.
struct Builder {
    lattice: Vec<Vec2>,
    ax: Vec<Axial>,
    l: f64,
    flat: Vec<Vec2>,
    folded: Vec<Vec3>,
    faces: Vec<[usize; 3]>,
    roles: HashMap<(usize, usize), Role>,
    midpoints: HashMap<(usize, usize), usize>,
}

impl Builder {
    /// Midpoint of a tuck side: the fin's fold line ends there; fully folded it hangs
    /// √3/4·l under the folded edge, a quarter of the way along it (the fin is a right
    /// triangle with legs l/2 and √3/2·l).
    fn midpoint(&mut self, a: usize, b: usize, apex: Axial) -> usize {
        let l = self.l;
        *self.midpoints.entry(key(a, b)).or_insert_with(|| {
            let v = folded_vertex(tuck_of(self.ax[a]), l);
            let w = folded_vertex(tuck_of(apex), l);
            self.flat.push((self.lattice[a] + self.lattice[b]) / 2.0);
            self.folded
                .push(v + (w - v) / 4.0 - Vec3::new(0.0, 0.0, l * SQRT3 / 4.0));
            self.flat.len() - 1
        })
    }

    /// An upward lattice triangle: a plain tile, or a tuck split about its centre into
    /// six triangles.
    fn upward(&mut self, corners: [usize; 3]) {
        let base = upward_base(corners.map(|v| self.ax[v]));
        if !is_tuck(base) {
            self.faces.push(corners);
            return;
        }
        let [a, b, c] = corners;
        let g = self.flat.len();
        self.flat
            .push((self.lattice[a] + self.lattice[b] + self.lattice[c]) / 3.0);
        self.folded
            .push(folded_vertex(base, self.l) - Vec3::new(0.0, 0.0, self.l / SQRT3));
        for k in 0..3 {
            let (u, v, opposite) = (corners[k], corners[(k + 1) % 3], corners[(k + 2) % 3]);
            let apex = across(self.ax[u], self.ax[v], self.ax[opposite]);
            let m = self.midpoint(u, v, apex);
            self.faces.extend([[u, m, g], [m, v, g]]);
            self.roles.insert(key(g, u), Role::TuckSpoke);
            self.roles.insert(key(g, m), Role::TuckMidline);
            self.roles.insert(key(u, m), Role::TuckSide);
            self.roles.insert(key(m, v), Role::TuckSide);
        }
    }

    /// A downward lattice triangle, a fin: split along its median from the side whose
    /// far neighbour is a tuck (its base).
    fn fin(&mut self, corners: [usize; 3]) {
        let ax = &self.ax;
        let k = (0..3)
            .find(|&k| {
                let (u, v, apex) = (corners[k], corners[(k + 1) % 3], corners[(k + 2) % 3]);
                let far = across(ax[u], ax[v], ax[apex]);
                is_tuck(upward_base([ax[u], ax[v], far]))
            })
            .expect("one side of every downward triangle faces a tuck");
        let (u, v, apex) = (corners[k], corners[(k + 1) % 3], corners[(k + 2) % 3]);
        let m = self.midpoint(u, v, self.ax[apex]);
        self.faces.extend([[u, m, apex], [m, v, apex]]);
        self.roles.insert(key(apex, m), Role::FinMedian);
        self.roles.entry(key(apex, u)).or_insert(Role::TileEdge);
        self.roles.entry(key(apex, v)).or_insert(Role::TileEdge);
        self.roles.insert(key(u, m), Role::TuckSide);
        self.roles.insert(key(m, v), Role::TuckSide);
    }
}

/// Each crease's assignment and target by its role; `full` holds the fold angles of the
/// fully folded state, which give the tile edges and tuck spokes theirs.
fn assign_by_role(parts: &mut MeshParts, roles: &HashMap<(usize, usize), Role>, full: &[f64]) {
    for (e, edge) in parts.edges.iter_mut().enumerate() {
        if edge.assignment == Assignment::Boundary {
            continue;
        }
        let role = roles.get(&edge.key()).copied().unwrap_or(Role::TileEdge);
        let (assignment, target) = match role {
            // Fully folded these are ±π where the sign is not in the geometry; the fin's
            // halves close with their front faces inside (tile edges turn the surface down).
            Role::FinMedian | Role::TuckMidline => (Assignment::Valley, -PI),
            Role::TuckSide => (Assignment::Unassigned, 0.0),
            Role::TileEdge | Role::TuckSpoke => {
                let rho = full[e];
                let a = if rho > 0.0 {
                    Assignment::Mountain
                } else {
                    Assignment::Valley
                };
                (a, rho)
            }
        };
        edge.assignment = assignment;
        edge.target = target;
        edge.fold_angle = target;
    }
}
