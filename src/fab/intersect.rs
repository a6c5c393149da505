//! Self-intersection of a 3D design: panels that pass through each other. The paper's
//! fold-angle ranges (§2.4) only keep neighbouring panels from swinging through one
//! another; a sheet rolled or bent far enough can close through itself elsewhere, and the
//! maker finds out only after cutting. This finds every pair of faces that cross other
//! than along a shared edge or vertex.
//!
//! A crossing is *transversal*: an edge of one triangle passes through the interior of
//! the other, its ends strictly on opposite sides of that triangle's plane. Faces that
//! only touch — layers stacked in a plane, as in a flat-folded state, or a vertex resting
//! on a panel — are not crossings (that is the layer order's business). "Strictly" means
//! by more than [`SELF_CONTACT_RELATIVE`] of the design's size, so rounding never decides.
//! Candidate pairs come from a bounding-volume hierarchy of axis-aligned boxes (median
//! split), so the check is O(n log n) in the number of faces.

use crate::mesh::{Mesh, Vec3};
use crate::tolerance::SELF_CONTACT_RELATIVE;

/// Two faces that pass through each other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// The face whose edge passes through the other (the smaller index first overall).
    pub faces: (usize, usize),
    /// Where that edge pierces the other face.
    pub at: Vec3,
    /// How far the pierced edge reaches through the face: the smaller of its two ends'
    /// distances from the face's plane (mm).
    pub depth: f64,
}

/// Every pair of faces of `mesh`'s 3D form that cross, ordered by face indices.
pub fn self_intersections(mesh: &Mesh) -> Vec<Crossing> {
    let x = mesh.positions();
    let faces = mesh.faces();
    let (lo, hi) = mesh.bounding_box();
    let eps = SELF_CONTACT_RELATIVE * (hi - lo).norm().max(1e-300);
    let boxes: Vec<Aabb> = faces
        .iter()
        .map(|f| Aabb::around(f.iter().map(|&v| x[v]), eps))
        .collect();
    let mut tree = Bvh::build(&boxes);
    tree.share_vertices(faces);
    let mut found = Vec::new();
    for (a, b) in candidate_pairs(mesh, &tree, eps) {
        let (fa, fb) = (&faces[a], &faces[b]);
        let shared = fa.iter().filter(|v| fb.contains(v)).count();
        if shared >= 2 {
            continue; // neighbours across an edge: the fold-angle ranges' concern
        }
        let ta = fa.map(|v| x[v]);
        let tb = fb.map(|v| x[v]);
        // With a shared vertex, only the edges opposite it can pierce the other face.
        let hit = piercing(fa, &ta, fb, &tb, eps).or_else(|| piercing(fb, &tb, fa, &ta, eps));
        if let Some((at, depth)) = hit {
            found.push(Crossing {
                faces: (a, b),
                at,
                depth,
            });
        }
    }
    found
}

/// Pairs (a, b), a < b, where an edge of one face can reach into the other: the edge's
/// box meets the face's and the edge touches none of its vertices. Driven by edges, not
/// faces: where thousands of long thin faces meet at one vertex (a cone's apex) every
/// pair of their boxes overlaps, but only the short edges opposite the apex can pierce,
/// and their boxes meet few faces. Sorted, each pair once.
fn candidate_pairs(mesh: &Mesh, tree: &Bvh, eps: f64) -> Vec<(usize, usize)> {
    let x = mesh.positions();
    let faces = mesh.faces();
    let mut pairs = Vec::new();
    let mut candidates = Vec::new();
    for (e, edge) in mesh.edges().iter().enumerate() {
        let [u, w] = edge.vertices;
        let query = Aabb::around([x[u], x[w]].into_iter(), eps);
        candidates.clear();
        // Around a vertex where thousands of faces meet, whole subtrees hold it: skipped.
        tree.overlapping_without(&query, &[u, w], &mut candidates);
        let owners = mesh.topology().edge_faces[e];
        for &q in &candidates {
            if faces[q].contains(&u) || faces[q].contains(&w) {
                continue;
            }
            for a in owners.into_iter().flatten() {
                pairs.push((a.min(q), a.max(q)));
            }
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// The first edge of triangle `p` (not touching `q`'s vertices) that passes through
/// triangle `q`'s interior: where, and how deep.
fn piercing(
    p_ids: &[usize; 3],
    p: &[Vec3; 3],
    q_ids: &[usize; 3],
    q: &[Vec3; 3],
    eps: f64,
) -> Option<(Vec3, f64)> {
    // An edge whose box misses q's cannot pierce it: a candidate pair was found through
    // one of its edges, and this rejects the others before any plane is computed.
    let q_box = Aabb::around(q.iter().copied(), eps);
    let mut normal = None;
    for k in 0..3 {
        let (i, j) = (k, (k + 1) % 3);
        if q_ids.contains(&p_ids[i]) || q_ids.contains(&p_ids[j]) {
            continue;
        }
        if !q_box.overlaps(&Aabb::around([p[i], p[j]].into_iter(), 0.0)) {
            continue;
        }
        let n = *normal.get_or_insert_with(|| {
            let n = (q[1] - q[0]).cross(&(q[2] - q[0]));
            let area2 = n.norm();
            // A degenerate face has no interior.
            (area2 > eps * eps).then(|| n / area2)
        });
        let n = n?;
        let (di, dj) = ((p[i] - q[0]).dot(&n), (p[j] - q[0]).dot(&n));
        if di * dj >= 0.0 || di.abs() <= eps || dj.abs() <= eps {
            continue;
        }
        let at = p[i] + (p[j] - p[i]) * (di / (di - dj));
        // Strictly inside q: at least eps from each of its sides.
        let inside = (0..3).all(|s| {
            let (a, b) = (q[s], q[(s + 1) % 3]);
            let side = (b - a).cross(&(at - a)).dot(&n) / (b - a).norm();
            side > eps
        });
        if inside {
            return Some((at, di.abs().min(dj.abs())));
        }
    }
    None
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug)]
struct Aabb {
    lo: Vec3,
    hi: Vec3,
}

impl Aabb {
    fn around(points: impl Iterator<Item = Vec3>, pad: f64) -> Aabb {
        let mut b = Aabb {
            lo: Vec3::repeat(f64::INFINITY),
            hi: Vec3::repeat(f64::NEG_INFINITY),
        };
        for p in points {
            b.lo = b.lo.inf(&p);
            b.hi = b.hi.sup(&p);
        }
        b.lo -= Vec3::repeat(pad);
        b.hi += Vec3::repeat(pad);
        b
    }

    fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            lo: self.lo.inf(&o.lo),
            hi: self.hi.sup(&o.hi),
        }
    }

    fn overlaps(&self, o: &Aabb) -> bool {
        (0..3).all(|k| self.lo[k] <= o.hi[k] && o.lo[k] <= self.hi[k])
    }

    fn centre(&self, axis: usize) -> f64 {
        0.5 * (self.lo[axis] + self.hi[axis])
    }
}

/// A bounding-volume hierarchy over boxes: each node splits its items at the median
/// centre along its box's longest axis; leaves hold a few items.
struct Bvh {
    nodes: Vec<Node>,
    items: Vec<usize>,
    boxes: Vec<Aabb>,
    /// Per node, the vertices every face below it has (empty unless
    /// [`Bvh::share_vertices`] was called): a query that skips faces holding a vertex
    /// skips such a node whole.
    shared: Vec<Vec<usize>>,
}

struct Node {
    bounds: Aabb,
    /// Leaf: range in `items`; inner: children's node indices.
    kind: NodeKind,
}

enum NodeKind {
    Leaf(usize, usize),
    Inner(usize, usize),
}

/// Items per leaf.
const LEAF: usize = 4;

impl Bvh {
    fn build(boxes: &[Aabb]) -> Bvh {
        let mut bvh = Bvh {
            nodes: Vec::new(),
            items: (0..boxes.len()).collect(),
            boxes: boxes.to_vec(),
            shared: Vec::new(),
        };
        if !boxes.is_empty() {
            bvh.split(0, boxes.len());
        }
        bvh
    }

    fn split(&mut self, from: usize, to: usize) -> usize {
        let bounds = self.items[from..to]
            .iter()
            .map(|&i| self.boxes[i])
            .reduce(|a, b| a.union(&b))
            .expect("a node holds items");
        let id = self.nodes.len();
        self.nodes.push(Node {
            bounds,
            kind: NodeKind::Leaf(from, to),
        });
        if to - from > LEAF {
            let extent = bounds.hi - bounds.lo;
            let axis = (0..3)
                .max_by(|&a, &b| extent[a].total_cmp(&extent[b]))
                .unwrap();
            let mid = (from + to) / 2;
            let boxes = &self.boxes;
            self.items[from..to].select_nth_unstable_by(mid - from, |&a, &b| {
                boxes[a].centre(axis).total_cmp(&boxes[b].centre(axis))
            });
            let left = self.split(from, mid);
            let right = self.split(mid, to);
            self.nodes[id].kind = NodeKind::Inner(left, right);
        }
        id
    }

    /// Records, per node, the vertices that all its items (faces) have. Children come
    /// after their parent in `nodes`, so one backward pass sees them first.
    fn share_vertices(&mut self, faces: &[[usize; 3]]) {
        let mut shared = vec![Vec::new(); self.nodes.len()];
        for n in (0..self.nodes.len()).rev() {
            let common = |a: &[usize], b: &[usize]| -> Vec<usize> {
                a.iter().copied().filter(|v| b.contains(v)).collect()
            };
            shared[n] = match self.nodes[n].kind {
                NodeKind::Leaf(a, b) => self.items[a..b]
                    .iter()
                    .map(|&i| faces[i].to_vec())
                    .reduce(|x, y| common(&x, &y))
                    .unwrap_or_default(),
                NodeKind::Inner(l, r) => common(&shared[l], &shared[r]),
            };
        }
        self.shared = shared;
    }

    /// Items whose boxes overlap `query` and whose faces hold none of `skip`, appended to
    /// `out` (needs [`Bvh::share_vertices`]; items holding `skip` in mixed nodes are
    /// still listed).
    fn overlapping_without(&self, query: &Aabb, skip: &[usize], out: &mut Vec<usize>) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = vec![0];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            let skipped = self
                .shared
                .get(n)
                .is_some_and(|s| s.iter().any(|v| skip.contains(v)));
            if skipped || !node.bounds.overlaps(query) {
                continue;
            }
            match node.kind {
                NodeKind::Leaf(a, b) => out.extend(
                    self.items[a..b]
                        .iter()
                        .copied()
                        .filter(|&i| self.boxes[i].overlaps(query)),
                ),
                NodeKind::Inner(l, r) => stack.extend([l, r]),
            }
        }
    }

    /// Items whose boxes overlap `query`, appended to `out`.
    #[cfg(test)]
    fn overlapping(&self, query: &Aabb, out: &mut Vec<usize>) {
        self.overlapping_without(query, &[], out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(p: [[f64; 3]; 3]) -> [Vec3; 3] {
        p.map(|c| Vec3::new(c[0], c[1], c[2]))
    }

    #[test]
    fn an_edge_through_the_interior_pierces_and_a_touch_does_not() {
        let q = tri([[0., 0., 0.], [4., 0., 0.], [0., 4., 0.]]);
        let through = tri([[1., 1., -1.], [1., 1., 1.], [5., 5., 5.]]);
        let (at, depth) = piercing(&[3, 4, 5], &through, &[0, 1, 2], &q, 1e-9).unwrap();
        assert!((at - Vec3::new(1., 1., 0.)).norm() < 1e-12);
        assert!((depth - 1.0).abs() < 1e-12);
        // Resting on the plane (one end in it) or lying in it: contact, not a crossing.
        let resting = tri([[1., 1., 0.], [1., 1., 1.], [2., 1., 1.]]);
        assert!(piercing(&[3, 4, 5], &resting, &[0, 1, 2], &q, 1e-9).is_none());
        let coplanar = tri([[1., 1., 0.], [3., 0.5, 0.], [0.5, 3., 0.]]);
        assert!(piercing(&[3, 4, 5], &coplanar, &[0, 1, 2], &q, 1e-9).is_none());
        // Through the plane but outside the triangle.
        let beside = tri([[5., 5., -1.], [5., 5., 1.], [6., 6., 0.]]);
        assert!(piercing(&[3, 4, 5], &beside, &[0, 1, 2], &q, 1e-9).is_none());
    }

    /// Every pair of faces whose boxes meet, tested as the crossings are (brute force).
    fn brute_force(mesh: &Mesh) -> Vec<(usize, usize)> {
        let x = mesh.positions();
        let faces = mesh.faces();
        let (lo, hi) = mesh.bounding_box();
        let eps = SELF_CONTACT_RELATIVE * (hi - lo).norm();
        let mut out = Vec::new();
        for a in 0..faces.len() {
            for b in a + 1..faces.len() {
                let shared = faces[a].iter().filter(|v| faces[b].contains(v)).count();
                if shared >= 2 {
                    continue;
                }
                let (ta, tb) = (faces[a].map(|v| x[v]), faces[b].map(|v| x[v]));
                if piercing(&faces[a], &ta, &faces[b], &tb, eps)
                    .or_else(|| piercing(&faces[b], &tb, &faces[a], &ta, eps))
                    .is_some()
                {
                    out.push((a, b));
                }
            }
        }
        out
    }

    #[test]
    fn the_edge_driven_search_finds_every_crossing_brute_force_finds() {
        use crate::generate::{generate, Params, PatternKind};
        // A Miura-ori folded past flat crosses itself; a crumpled plane and a cone too.
        for (kind, fold) in [
            (PatternKind::Miura, 0.3),
            (PatternKind::Plane, 0.9),
            (PatternKind::Curved, 0.9),
        ] {
            let p = Params {
                fold: Some(fold),
                ..Params::square(kind, 6, 10.0)
            };
            let mut mesh = generate(&p).unwrap();
            // Crumple it: every vertex moved up to 12 mm (seeded), faces through faces.
            let mut rng = crate::random::Rng::new(0x2545_f491_4f6c_dd1d);
            let mut rand = || rng.range(-0.5, 0.5);
            let mut moved = mesh.positions().to_vec();
            for v in moved.iter_mut() {
                *v += Vec3::new(rand(), rand(), rand()) * 24.0;
            }
            mesh.set_positions(moved);
            let mut got: Vec<(usize, usize)> =
                self_intersections(&mesh).iter().map(|c| c.faces).collect();
            got.sort_unstable();
            let want = brute_force(&mesh);
            assert!(!want.is_empty(), "{kind:?}: the test needs crossings");
            assert_eq!(got, want, "{kind:?}");
        }
    }

    /// A cone of `n` sectors round an apex, with every seventh rim vertex pushed through
    /// the far side: thousands of faces share the apex, as the pruning by shared vertices
    /// assumes, and some cross.
    fn pierced_cone(n: usize) -> Mesh {
        let mut coords = vec!["[0, 0, 30]".to_string()];
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            let r = if i % 7 == 3 { -160.0 } else { 100.0 };
            coords.push(format!(
                "[{}, {}, {}]",
                r * a.cos(),
                r * a.sin(),
                (i % 5) as f64
            ));
        }
        let faces: Vec<String> = (0..n)
            .map(|i| format!("[0, {}, {}]", 1 + i, 1 + (i + 1) % n))
            .collect();
        let text = format!(
            r#"{{"file_spec": 1.1, "vertices_coords": [{}], "faces_vertices": [{}]}}"#,
            coords.join(","),
            faces.join(",")
        );
        crate::io::fold::parse(&text).unwrap()
    }

    #[test]
    fn around_a_vertex_shared_by_every_face_the_pruned_search_misses_no_crossing() {
        for n in [40, 301] {
            let mesh = pierced_cone(n);
            let mut got: Vec<(usize, usize)> =
                self_intersections(&mesh).iter().map(|c| c.faces).collect();
            got.sort_unstable();
            let want = brute_force(&mesh);
            assert!(!want.is_empty(), "the cone must cross itself");
            assert_eq!(got, want, "{n} sectors");
        }
    }

    #[test]
    fn the_hierarchy_finds_exactly_the_overlapping_boxes() {
        // Boxes on a 10 × 10 × 10 grid of unit cells, queried with random boxes; compared
        // with testing every box.
        let mut boxes = Vec::new();
        for i in 0..1000 {
            let c = Vec3::new((i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64);
            boxes.push(Aabb::around([c, c + Vec3::repeat(0.7)].into_iter(), 0.0));
        }
        let bvh = Bvh::build(&boxes);
        let mut rng = crate::random::Rng::new(7);
        let mut rand = || rng.range(0.0, 10.0);
        for _ in 0..200 {
            let a = Vec3::new(rand(), rand(), rand());
            let q = Aabb::around(
                [a, a + Vec3::new(rand(), rand(), rand()) * 0.3].into_iter(),
                0.0,
            );
            let mut got = Vec::new();
            bvh.overlapping(&q, &mut got);
            got.sort_unstable();
            let want: Vec<usize> = (0..boxes.len())
                .filter(|&i| boxes[i].overlaps(&q))
                .collect();
            assert_eq!(got, want);
        }
    }
}
