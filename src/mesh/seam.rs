//! Tubes (paper §7, "nondisk surfaces, especially cylindrical surfaces"): a surface closed
//! into a cylinder, and the seam it is cut open along to be made from one strip of paper.
//!
//! A tube is one mesh whose joined vertices are single vertices, so every condition of the
//! paper holds at a seam vertex as at any other interior vertex (its sector angles close
//! around it). The seam is only where the paper is cut to lay the tube out: a path of
//! edges from one rim to the other.

use super::{edge_key, Assignment, Mesh, Vec3};
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashSet};

/// A tube cut open along its seam: the strip of paper it is made from.
#[derive(Clone, Debug)]
pub struct Strip {
    /// The strip as a sheet: the tube's vertices, then one more copy of every seam vertex;
    /// the seam's edges are boundary on both sides. Its 3D form is the tube's; it has a
    /// crease pattern once unfolded (`geometry::unfold::unfold_tube`).
    pub sheet: Mesh,
    /// For each strip vertex, the tube vertex it is a copy of.
    pub origin: Vec<usize>,
    /// Each seam edge of the tube, in order from one rim to the other and pointing along
    /// that way, as its two sides on the strip: `[[a, b], [a', b']]`, where the paper lies
    /// left of `a → b` on the first side (the glue tab goes on its right) and `a'`, `b'`
    /// are the other copies of `a`, `b`. The first sides join into one path, as do the
    /// second.
    pub sides: Vec<[[usize; 2]; 2]>,
    /// The tube's edge index of each seam edge, in the same order.
    pub edges: Vec<usize>,
}

/// Why a tube cannot be cut open.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SeamError {
    /// The declared seam names an edge the mesh lacks.
    #[error("seam edge {0}–{1} is not an edge of the mesh")]
    NotAnEdge(usize, usize),
    /// The declared seam does not run from one rim to the other as one path.
    #[error("the seam does not cut the tube into one strip: {0}")]
    NotAStrip(String),
    /// Cut along the seam, the strip is not a valid mesh.
    #[error("the seam does not cut the tube into one strip: {0}")]
    StripInvalid(#[source] super::MeshError),
    /// The surface is not a tube.
    #[error("the design is not a tube (it has {loops} boundary loop(s) and χ = {euler}); only a tube has a seam")]
    NotATube {
        /// Boundary loops.
        loops: usize,
        /// Euler characteristic.
        euler: i64,
    },
}

impl Mesh {
    /// Whether the surface is a tube: one piece, two rims, χ = 0 (a cylinder).
    pub fn is_tube(&self) -> bool {
        self.shape().is_tube
    }

    /// The seam's edges from one rim to the other: the declared seam ([`Mesh::seam`]) when
    /// there is one, else the shortest path of edges (3D length) between the rims.
    pub fn seam_edges(&self) -> Result<Vec<usize>, SeamError> {
        let t = self.shape();
        if !t.is_tube {
            return Err(SeamError::NotATube {
                loops: t.boundary_loops,
                euler: t.euler_characteristic,
            });
        }
        if self.seam.is_empty() {
            return Ok(self.shortest_rim_path());
        }
        let topo = self.topology();
        let mut edges = Vec::with_capacity(self.seam.len());
        for &[a, b] in &self.seam {
            edges.push(topo.edge_between(a, b).ok_or(SeamError::NotAnEdge(a, b))?);
        }
        self.order_path(edges)
    }

    /// Cuts the tube open along [`Mesh::seam_edges`] into the strip it is made from.
    pub fn cut_open(&self) -> Result<Strip, SeamError> {
        let edges = self.seam_edges()?;
        let mut parts = self.clone().into_parts();
        parts.positions = Some(self.positions().to_vec());
        for &e in &edges {
            parts.edges[e].assignment = Assignment::Cut;
        }
        let original = self.edges().to_vec();
        let origin = super::cuts::split_along(&mut parts);
        // Each strip edge runs the way its tube edge does, so a tube written as its strip
        // reads back with its own edges.
        for e in &mut parts.edges {
            let [a, b] = e.vertices;
            if let Some(t) = self.topology().edge_between(origin[a], origin[b]) {
                if original[t].vertices[0] != origin[a] {
                    e.vertices = [b, a];
                }
            }
        }
        // The seam's own crease data (a seam may lie on a fold) stays on both sides' record
        // in `Strip::edges`; on the strip its sides are paper boundary.
        let topo = self.topology();
        let mut sides = Vec::with_capacity(edges.len());
        // Along the path from its first rim: the end of the first edge the second lacks.
        let mut at = match edges.as_slice() {
            [e0, e1, ..] => {
                let [p, q] = original[*e0].vertices;
                if original[*e1].vertices.contains(&q) {
                    p
                } else {
                    q
                }
            }
            [e0] => original[*e0].vertices[0],
            [] => return Err(SeamError::NotAStrip("it has no edges".into())),
        };
        for &e in &edges {
            let (a, b) = (at, original[e].other(at));
            at = b;
            let [mut left, mut right] = topo.edge_faces[e];
            if original[e].vertices[0] != a {
                std::mem::swap(&mut left, &mut right);
            }
            let (Some(l), Some(r)) = (left, right) else {
                return Err(SeamError::NotAStrip(format!(
                    "seam edge {a}–{b} lies on a rim"
                )));
            };
            let copy = |face: usize, v: usize| -> usize {
                *parts.faces[face]
                    .iter()
                    .find(|&&c| origin[c] == v)
                    .expect("a face keeps a copy of each of its corners")
            };
            // Face l has a → b counter-clockwise: the paper is left of a → b there.
            sides.push([[copy(l, a), copy(l, b)], [copy(r, a), copy(r, b)]]);
        }
        let mut sheet = Mesh::new(parts).map_err(SeamError::StripInvalid)?;
        let s = sheet.shape();
        if !s.is_disk {
            return Err(SeamError::NotAStrip(format!(
                "cut along it, the paper has {} piece(s) and {} hole(s)",
                s.components, s.holes
            )));
        }
        sheet.title = self.title.clone();
        sheet.lock_topology = self.lock_topology;
        sheet.coordinate_precision = self.coordinate_precision;
        Ok(Strip {
            sheet,
            origin,
            sides,
            edges,
        })
    }

    /// Dijkstra over edge lengths from every vertex of the first rim to the second.
    fn shortest_rim_path(&self) -> Vec<usize> {
        let topo = self.topology();
        let x = self.positions();
        let n = self.vertex_count();
        let (start, goal) = (&topo.boundary_loops[0], &topo.boundary_loops[1]);
        let goal: HashSet<usize> = goal.iter().copied().collect();
        let mut dist = vec![f64::INFINITY; n];
        let mut via: Vec<Option<usize>> = vec![None; n];
        let mut heap = BinaryHeap::new();
        for &v in start {
            dist[v] = 0.0;
            heap.push(Reverse((Ordered(0.0), v)));
        }
        let mut end = None;
        while let Some(Reverse((Ordered(d), v))) = heap.pop() {
            if d > dist[v] {
                continue;
            }
            if goal.contains(&v) {
                end = Some(v);
                break;
            }
            for &e in &topo.fans[v].spokes {
                let w = self.edges()[e].other(v);
                // The seam crosses the tube: it runs through the inside, not along a rim.
                if self.edges()[e].assignment.is_boundary() {
                    continue;
                }
                let nd = d + length(x, v, w);
                if nd < dist[w] {
                    dist[w] = nd;
                    via[w] = Some(e);
                    heap.push(Reverse((Ordered(nd), w)));
                }
            }
        }
        let mut path = Vec::new();
        let mut v = end.expect("a tube's rims are joined by its edges");
        while let Some(e) = via[v] {
            path.push(e);
            v = self.edges()[e].other(v);
        }
        path.reverse();
        path
    }

    /// The declared seam edges as one path from a rim to the other, in order.
    fn order_path(&self, edges: Vec<usize>) -> Result<Vec<usize>, SeamError> {
        let topo = self.topology();
        let on_rim = |v: usize| topo.fans[v].boundary;
        let ends: Vec<usize> = edges
            .iter()
            .flat_map(|&e| self.edges()[e].vertices)
            .filter(|&v| on_rim(v))
            .collect();
        let Some(&first) = ends.first() else {
            return Err(SeamError::NotAStrip("it does not reach a rim".into()));
        };
        let mut left: Vec<usize> = edges;
        let mut path = Vec::with_capacity(left.len());
        let mut v = first;
        while !left.is_empty() {
            let k = left
                .iter()
                .position(|&e| self.edges()[e].vertices.contains(&v))
                .ok_or_else(|| SeamError::NotAStrip(format!("it breaks off at vertex {v}")))?;
            let e = left.swap_remove(k);
            if self.edges()[e].assignment.is_boundary() {
                let [a, b] = self.edges()[e].vertices;
                return Err(SeamError::NotAStrip(format!("edge {a}–{b} lies on a rim")));
            }
            path.push(e);
            v = self.edges()[e].other(v);
            if on_rim(v) && !left.is_empty() {
                return Err(SeamError::NotAStrip(format!(
                    "it reaches a rim at vertex {v} before its end"
                )));
            }
        }
        if !on_rim(v) || self.rim_of(v) == self.rim_of(first) {
            return Err(SeamError::NotAStrip(
                "it must run from one rim to the other".into(),
            ));
        }
        Ok(path)
    }

    fn rim_of(&self, v: usize) -> Option<usize> {
        self.topology()
            .boundary_loops
            .iter()
            .position(|l| l.contains(&v))
    }
}

fn length(x: &[Vec3], a: usize, b: usize) -> f64 {
    (x[a] - x[b]).norm()
}

/// The seam as edge keys, as [`Mesh::seam`] stores it.
pub fn seam_keys(mesh: &Mesh, edges: &[usize]) -> Vec<[usize; 2]> {
    edges
        .iter()
        .map(|&e| {
            let (a, b) = edge_key(mesh.edges()[e].vertices[0], mesh.edges()[e].vertices[1]);
            [a, b]
        })
        .collect()
}

/// A total order on the path lengths Dijkstra compares (never NaN: lengths of finite
/// coordinates).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Ordered(f64);

impl Eq for Ordered {}

impl Ord for Ordered {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

impl PartialOrd for Ordered {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
