//! Adjacency of a triangle mesh and the checks that make it a valid origami surface:
//! indices in range, no degenerate triangle, every edge on one or two faces, every vertex a
//! single fan (disk or half-disk), faces consistently oriented.

use super::{edge_key as key, Assignment, Edge, MeshError, Vec2, Vec3};
use std::collections::{HashMap, VecDeque};

/// The faces around one vertex in counter-clockwise order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VertexFan {
    /// Faces in counter-clockwise order; face `i` is `(v, a_i, a_{i+1})`.
    pub faces: Vec<usize>,
    /// Edges `(v, a_i)` in the same order. An interior vertex has as many spokes as faces;
    /// a boundary vertex has one more (the fan is open).
    pub spokes: Vec<usize>,
    /// Whether the vertex lies on a boundary.
    pub boundary: bool,
}

/// Adjacency queries the constraints need, built once per topology.
#[derive(Clone, Debug, Default)]
pub struct Topology {
    /// Fan of each vertex.
    pub fans: Vec<VertexFan>,
    /// For each edge `(a, b)`: the face where `a → b` runs counter-clockwise (left) and the
    /// face where `b → a` does (right).
    pub edge_faces: Vec<[Option<usize>; 2]>,
    /// For face `(a, b, c)` the edges `ab`, `bc`, `ca`.
    pub face_edges: Vec<[usize; 3]>,
    /// Boundary loops as vertex cycles, each following the paper's boundary with the paper
    /// on its left.
    pub boundary_loops: Vec<Vec<usize>>,
    /// Connected components (by faces).
    pub components: usize,
    edge_lookup: HashMap<(usize, usize), usize>,
}

/// Counts that describe the surface's shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TopologySummary {
    /// Connected pieces of paper.
    pub components: usize,
    /// Boundary loops (outer perimeters and holes).
    pub boundary_loops: usize,
    /// Holes: boundary loops beyond one per component.
    pub holes: usize,
    /// V − E + F.
    pub euler_characteristic: i64,
    /// One component, one boundary loop, χ = 1: a sheet.
    pub is_disk: bool,
    /// One component, two boundary loops, χ = 0: a tube (paper §7).
    pub is_tube: bool,
}

impl Topology {
    /// The edge joining `a` and `b`, if any.
    pub fn edge_between(&self, a: usize, b: usize) -> Option<usize> {
        self.edge_lookup.get(&key(a, b)).copied()
    }

    /// Shape counts for reports and for stages that need a disk.
    pub fn summary(&self, vertices: usize, edges: usize, faces: usize) -> TopologySummary {
        let euler = vertices as i64 - edges as i64 + faces as i64;
        let loops = self.boundary_loops.len();
        TopologySummary {
            components: self.components,
            boundary_loops: loops,
            holes: loops.saturating_sub(self.components),
            euler_characteristic: euler,
            is_disk: self.components == 1 && loops == 1 && euler == 1,
            is_tube: self.components == 1 && loops == 2 && euler == 0,
        }
    }
}

fn twice_area_2d(p: &[Vec2], f: [usize; 3]) -> f64 {
    (p[f[1]] - p[f[0]]).perp(&(p[f[2]] - p[f[0]]))
}

fn is_degenerate(positions: &[Vec3], flat: Option<&[Vec2]>, f: [usize; 3]) -> bool {
    if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
        return true;
    }
    // Relative to the longest side, so the check is independent of units.
    let (area2, longest2) = match flat {
        Some(p) => {
            let l = [
                (p[f[1]] - p[f[0]]),
                (p[f[2]] - p[f[1]]),
                (p[f[0]] - p[f[2]]),
            ];
            (
                twice_area_2d(p, f).abs(),
                l.iter().map(|e| e.norm_squared()).fold(0.0, f64::max),
            )
        }
        None => {
            let p = positions;
            let l = [
                (p[f[1]] - p[f[0]]),
                (p[f[2]] - p[f[1]]),
                (p[f[0]] - p[f[2]]),
            ];
            (
                l[0].cross(&l[1]).norm(),
                l.iter().map(|e| e.norm_squared()).fold(0.0, f64::max),
            )
        }
    };
    // NaN coordinates count as degenerate.
    area2.is_nan() || area2 <= 1e-12 * longest2
}

/// Faces, edges and adjacency of a validated mesh.
type Built = (Vec<[usize; 3]>, Vec<Edge>, Topology);

/// Validates and orients faces, completes the edge list and builds adjacency.
pub(super) fn build(
    positions: &[Vec3],
    flat: Option<&[Vec2]>,
    mut faces: Vec<[usize; 3]>,
    mut edges: Vec<Edge>,
) -> Result<Built, MeshError> {
    let n = positions.len();
    check_faces(positions, flat, &faces)?;
    orient(&mut faces, flat)?;
    // Edge list: validate what the source gave, then add what the faces need.
    let mut edge_lookup = index_edges(&edges, n)?;
    let mut half_edges: HashMap<(usize, usize), usize> = HashMap::with_capacity(faces.len() * 3);
    for (fi, f) in faces.iter().enumerate() {
        for k in 0..3 {
            half_edges.insert((f[k], f[(k + 1) % 3]), fi);
        }
    }
    let face_edges = complete_edges(&faces, &half_edges, &mut edges, &mut edge_lookup);
    let edge_faces = faces_of_edges(&edges, &half_edges)?;
    let fans = vertex_fans(n, &faces, &half_edges, &edge_lookup)?;
    let boundary_loops = boundary_loops(&faces, &half_edges);
    let components = count_components(&faces, &face_edges, &edge_faces);
    Ok((
        faces,
        edges,
        Topology {
            fans,
            edge_faces,
            face_edges,
            boundary_loops,
            components,
            edge_lookup,
        },
    ))
}

/// Every face names existing vertices and has area.
fn check_faces(
    positions: &[Vec3],
    flat: Option<&[Vec2]>,
    faces: &[[usize; 3]],
) -> Result<(), MeshError> {
    let n = positions.len();
    if faces.is_empty() {
        return Err(MeshError::Empty);
    }
    for (i, f) in faces.iter().enumerate() {
        if let Some(&v) = f.iter().find(|&&v| v >= n) {
            return Err(MeshError::IndexOutOfRange {
                element: format!("face {i}"),
                vertex: v,
                count: n,
            });
        }
        if is_degenerate(positions, flat, *f) {
            return Err(MeshError::DegenerateFace {
                face: i,
                vertices: *f,
            });
        }
    }
    Ok(())
}

/// The source's edges by their (sorted) ends, refusing bad indices, loops and repeats.
fn index_edges(edges: &[Edge], n: usize) -> Result<HashMap<(usize, usize), usize>, MeshError> {
    let mut edge_lookup = HashMap::with_capacity(edges.len() * 2);
    for (i, e) in edges.iter().enumerate() {
        let [a, b] = e.vertices;
        if let Some(&v) = e.vertices.iter().find(|&&v| v >= n) {
            return Err(MeshError::IndexOutOfRange {
                element: format!("edge {i}"),
                vertex: v,
                count: n,
            });
        }
        if a == b {
            return Err(MeshError::DegenerateEdge { edge: i, vertex: a });
        }
        if let Some(first) = edge_lookup.insert(key(a, b), i) {
            return Err(MeshError::DuplicateEdge {
                first,
                second: i,
                a,
                b,
            });
        }
    }
    Ok(edge_lookup)
}

/// Adds the edges the faces need and the source left out (flat inside, boundary
/// outside, marked synthetic); returns each face's three edges.
fn complete_edges(
    faces: &[[usize; 3]],
    half_edges: &HashMap<(usize, usize), usize>,
    edges: &mut Vec<Edge>,
    edge_lookup: &mut HashMap<(usize, usize), usize>,
) -> Vec<[usize; 3]> {
    let mut face_edges = Vec::with_capacity(faces.len());
    for f in faces {
        let mut fe = [0; 3];
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            fe[k] = *edge_lookup.entry(key(a, b)).or_insert_with(|| {
                let interior = half_edges.contains_key(&(b, a));
                let assignment = if interior {
                    Assignment::Flat
                } else {
                    Assignment::Boundary
                };
                let mut e = Edge::new(a, b, assignment);
                e.synthetic = true;
                edges.push(e);
                edges.len() - 1
            });
        }
        face_edges.push(fe);
    }
    face_edges
}

/// The faces left and right of every edge; an edge of no face is an error.
fn faces_of_edges(
    edges: &[Edge],
    half_edges: &HashMap<(usize, usize), usize>,
) -> Result<Vec<[Option<usize>; 2]>, MeshError> {
    let mut edge_faces = vec![[None, None]; edges.len()];
    for (i, e) in edges.iter().enumerate() {
        let [a, b] = e.vertices;
        edge_faces[i] = [
            half_edges.get(&(a, b)).copied(),
            half_edges.get(&(b, a)).copied(),
        ];
        if edge_faces[i] == [None, None] {
            return Err(MeshError::DanglingEdge { edge: i, a, b });
        }
    }
    Ok(edge_faces)
}

/// Makes neighbouring faces traverse their shared edge in opposite directions, and each
/// component counter-clockwise in the crease pattern when there is one.
fn orient(faces: &mut [[usize; 3]], flat: Option<&[Vec2]>) -> Result<(), MeshError> {
    let mut by_edge: HashMap<(usize, usize), Vec<usize>> = HashMap::with_capacity(faces.len() * 2);
    for (fi, f) in faces.iter().enumerate() {
        for k in 0..3 {
            by_edge
                .entry(key(f[k], f[(k + 1) % 3]))
                .or_default()
                .push(fi);
        }
    }
    if let Some((&(a, b), fs)) = by_edge.iter().find(|(_, fs)| fs.len() > 2) {
        return Err(MeshError::NonManifoldEdge {
            a,
            b,
            faces: fs.len(),
        });
    }
    let runs =
        |f: &[usize; 3], a: usize, b: usize| (0..3).any(|k| f[k] == a && f[(k + 1) % 3] == b);
    let mut done = vec![false; faces.len()];
    for seed in 0..faces.len() {
        if done[seed] {
            continue;
        }
        done[seed] = true;
        let mut component = vec![seed];
        let mut queue = VecDeque::from([seed]);
        while let Some(fi) = queue.pop_front() {
            let f = faces[fi];
            for k in 0..3 {
                let (a, b) = (f[k], f[(k + 1) % 3]);
                for &g in &by_edge[&key(a, b)] {
                    if g == fi {
                        continue;
                    }
                    // A consistent neighbour runs the shared edge b → a.
                    if !done[g] {
                        if runs(&faces[g], a, b) {
                            faces[g].swap(1, 2);
                        }
                        done[g] = true;
                        component.push(g);
                        queue.push_back(g);
                    } else if runs(&faces[g], a, b) {
                        return Err(MeshError::NonOrientable { face: g });
                    }
                }
            }
        }
        if let Some(p) = flat {
            let area: f64 = component
                .iter()
                .map(|&fi| twice_area_2d(p, faces[fi]))
                .sum();
            if area < 0.0 {
                for &fi in &component {
                    faces[fi].swap(1, 2);
                }
            }
        }
    }
    Ok(())
}

fn vertex_fans(
    n: usize,
    faces: &[[usize; 3]],
    half_edges: &HashMap<(usize, usize), usize>,
    edge_lookup: &HashMap<(usize, usize), usize>,
) -> Result<Vec<VertexFan>, MeshError> {
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (fi, f) in faces.iter().enumerate() {
        for &v in f {
            incident[v].push(fi);
        }
    }
    // Face (v, a, b) with v first.
    let corner = |fi: usize, v: usize| {
        let f = faces[fi];
        let k = f.iter().position(|&x| x == v).expect("face contains v");
        (f[(k + 1) % 3], f[(k + 2) % 3])
    };
    let mut fans = Vec::with_capacity(n);
    for (v, inc) in incident.iter().enumerate() {
        if inc.is_empty() {
            return Err(MeshError::IsolatedVertex { vertex: v });
        }
        // Start where the fan opens (edge v–a has no face before it), else anywhere.
        let start = inc
            .iter()
            .copied()
            .find(|&fi| !half_edges.contains_key(&(corner(fi, v).0, v)))
            .unwrap_or(inc[0]);
        let boundary = half_edges.get(&(corner(start, v).0, v)).is_none();
        let mut fan = VertexFan {
            boundary,
            ..Default::default()
        };
        let mut fi = start;
        loop {
            let (a, b) = corner(fi, v);
            fan.faces.push(fi);
            fan.spokes.push(edge_lookup[&key(v, a)]);
            match half_edges.get(&(v, b)) {
                Some(&next) if next != start => fi = next,
                Some(_) => break,
                None => {
                    fan.spokes.push(edge_lookup[&key(v, b)]);
                    break;
                }
            }
            if fan.faces.len() > inc.len() {
                break;
            }
        }
        if fan.faces.len() != inc.len() {
            return Err(MeshError::NonManifoldVertex { vertex: v });
        }
        fans.push(fan);
    }
    Ok(fans)
}

fn boundary_loops(
    faces: &[[usize; 3]],
    half_edges: &HashMap<(usize, usize), usize>,
) -> Vec<Vec<usize>> {
    let mut next: HashMap<usize, usize> = HashMap::new();
    for f in faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            if !half_edges.contains_key(&(b, a)) {
                next.insert(a, b);
            }
        }
    }
    let mut starts: Vec<usize> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut seen = std::collections::HashSet::new();
    let mut loops = Vec::new();
    for s in starts {
        if seen.contains(&s) {
            continue;
        }
        let mut lp = Vec::new();
        let mut v = s;
        while seen.insert(v) {
            lp.push(v);
            match next.get(&v) {
                Some(&w) => v = w,
                None => break,
            }
        }
        loops.push(lp);
    }
    loops
}

fn count_components(
    faces: &[[usize; 3]],
    face_edges: &[[usize; 3]],
    edge_faces: &[[Option<usize>; 2]],
) -> usize {
    let mut seen = vec![false; faces.len()];
    let mut count = 0;
    for seed in 0..faces.len() {
        if seen[seed] {
            continue;
        }
        count += 1;
        seen[seed] = true;
        let mut stack = vec![seed];
        while let Some(f) = stack.pop() {
            for &e in &face_edges[f] {
                for g in edge_faces[e].iter().flatten() {
                    if !seen[*g] {
                        seen[*g] = true;
                        stack.push(*g);
                    }
                }
            }
        }
    }
    count
}
