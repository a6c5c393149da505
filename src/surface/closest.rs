//! Closest points on a triangle mesh: the point of one triangle nearest a query
//! (Ericson, *Real-Time Collision Detection* §5.1.5, by Voronoi regions of the corners
//! and edges), and a bounding-volume hierarchy of axis-aligned boxes over the triangles
//! that finds the nearest triangle by branch and bound: a subtree is skipped when its box
//! is farther than the best point found so far, so a query visits O(log n) boxes on a
//! surface sampled evenly.

use crate::mesh::Vec3;

/// The point of triangle `abc` nearest `p`.
pub fn closest_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    // Inside the face: barycentric coordinates from the signed areas above.
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug)]
struct Aabb {
    lo: Vec3,
    hi: Vec3,
}

impl Aabb {
    fn empty() -> Aabb {
        Aabb {
            lo: Vec3::repeat(f64::INFINITY),
            hi: Vec3::repeat(f64::NEG_INFINITY),
        }
    }

    fn grow(&mut self, p: Vec3) {
        self.lo = self.lo.inf(&p);
        self.hi = self.hi.sup(&p);
    }

    fn merge(&mut self, other: &Aabb) {
        self.lo = self.lo.inf(&other.lo);
        self.hi = self.hi.sup(&other.hi);
    }

    /// Squared distance from `p` to the box (0 inside).
    fn distance_squared(&self, p: Vec3) -> f64 {
        let below = (self.lo - p).sup(&Vec3::zeros());
        let above = (p - self.hi).sup(&Vec3::zeros());
        (below + above).norm_squared()
    }
}

/// A node: a box and either two children or a run of triangles.
#[derive(Clone, Debug)]
struct Node {
    bounds: Aabb,
    /// Children's indices, or `None` for a leaf.
    children: Option<(usize, usize)>,
    /// A leaf's triangles: `order[start..end]`.
    start: usize,
    end: usize,
}

/// Triangles a leaf holds at most.
const LEAF_SIZE: usize = 4;

/// The nearest point of a surface and where it lies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    /// The point on the surface.
    pub point: Vec3,
    /// The triangle it lies on.
    pub triangle: usize,
    /// Its distance from the query (mm).
    pub distance: f64,
}

/// A bounding-volume hierarchy over triangles for nearest-point queries.
#[derive(Clone, Debug)]
pub struct ClosestPointTree {
    nodes: Vec<Node>,
    /// Triangle indices, leaves' runs contiguous.
    order: Vec<usize>,
}

impl ClosestPointTree {
    /// Builds the hierarchy over `triangles` of `vertices` (median split on the longest
    /// axis of the centroids' box).
    pub fn build(vertices: &[Vec3], triangles: &[[usize; 3]]) -> ClosestPointTree {
        let boxes: Vec<Aabb> = triangles
            .iter()
            .map(|t| {
                let mut b = Aabb::empty();
                t.iter().for_each(|&v| b.grow(vertices[v]));
                b
            })
            .collect();
        let centres: Vec<Vec3> = boxes.iter().map(|b| (b.lo + b.hi) / 2.0).collect();
        let mut tree = ClosestPointTree {
            nodes: Vec::with_capacity(2 * triangles.len() / LEAF_SIZE + 1),
            order: (0..triangles.len()).collect(),
        };
        if !triangles.is_empty() {
            tree.split(&boxes, &centres, 0, triangles.len());
        }
        tree
    }

    /// Builds the node over `order[start..end]`; returns its index.
    fn split(&mut self, boxes: &[Aabb], centres: &[Vec3], start: usize, end: usize) -> usize {
        let mut bounds = Aabb::empty();
        let mut spread = Aabb::empty();
        for &t in &self.order[start..end] {
            bounds.merge(&boxes[t]);
            spread.grow(centres[t]);
        }
        let index = self.nodes.len();
        self.nodes.push(Node {
            bounds,
            children: None,
            start,
            end,
        });
        if end - start > LEAF_SIZE {
            let extent = spread.hi - spread.lo;
            let axis = extent.imax();
            let mid = start + (end - start) / 2;
            self.order[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
                centres[a][axis].total_cmp(&centres[b][axis])
            });
            let left = self.split(boxes, centres, start, mid);
            let right = self.split(boxes, centres, mid, end);
            self.nodes[index].children = Some((left, right));
        }
        index
    }

    /// The nearest point to `p` on the triangles the tree was built over (`None` when
    /// there are none).
    pub fn closest(&self, vertices: &[Vec3], triangles: &[[usize; 3]], p: Vec3) -> Option<Closest> {
        if self.nodes.is_empty() {
            return None;
        }
        let mut best: Option<Closest> = None;
        let mut best_d2 = f64::INFINITY;
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            if node.bounds.distance_squared(p) >= best_d2 {
                continue;
            }
            match node.children {
                Some((l, r)) => {
                    // The nearer child last, so it is searched first.
                    let dl = self.nodes[l].bounds.distance_squared(p);
                    let dr = self.nodes[r].bounds.distance_squared(p);
                    if dl < dr {
                        stack.extend([r, l]);
                    } else {
                        stack.extend([l, r]);
                    }
                }
                None => {
                    for &t in &self.order[node.start..node.end] {
                        let [a, b, c] = triangles[t].map(|v| vertices[v]);
                        let q = closest_on_triangle(p, a, b, c);
                        let d2 = (q - p).norm_squared();
                        if d2 < best_d2 {
                            best_d2 = d2;
                            best = Some(Closest {
                                point: q,
                                triangle: t,
                                distance: d2.sqrt(),
                            });
                        }
                    }
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_closest_point_of_a_triangle_is_nearer_than_every_sample_of_it() {
        // Brute force: the triangle sampled on a fine barycentric grid (and its corners
        // and edges exactly); no sample may be nearer than the answer, and the nearest
        // sample is within the grid's spacing of it.
        let mut rng = crate::random::Rng::new(0x9e37_79b9_7f4a_7c15);
        let mut r = || rng.range(-10.0, 10.0);
        for _ in 0..200 {
            let (a, b, c) = (
                Vec3::new(r(), r(), r()),
                Vec3::new(r(), r(), r()),
                Vec3::new(r(), r(), r()),
            );
            let p = Vec3::new(r(), r(), r());
            let q = closest_on_triangle(p, a, b, c);
            let d = (q - p).norm();
            let n = 120;
            let mut nearest = f64::INFINITY;
            for i in 0..=n {
                for j in 0..=(n - i) {
                    let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                    let x = a + (b - a) * u + (c - a) * v;
                    let dx = (x - p).norm();
                    assert!(dx >= d - 1e-9, "a sample is nearer: {dx} < {d}");
                    nearest = nearest.min(dx);
                }
            }
            let longest = (b - a).norm().max((c - a).norm()).max((c - b).norm());
            assert!(nearest - d <= longest / n as f64 + 1e-9);
        }
    }

    #[test]
    fn the_tree_finds_what_every_triangle_tried_finds() {
        // A bumpy grid surface, queried from points around and on it.
        let n = 30;
        let mut vertices = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as f64, j as f64);
                vertices.push(Vec3::new(x, y, (x * 0.4).sin() * (y * 0.3).cos() * 3.0));
            }
        }
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = j * (n + 1) + i;
                triangles.push([v, v + 1, v + n + 2]);
                triangles.push([v, v + n + 2, v + n + 1]);
            }
        }
        let tree = ClosestPointTree::build(&vertices, &triangles);
        let mut rng = crate::random::Rng::new(12345);
        for _ in 0..500 {
            let p = Vec3::new(
                rng.range(-5.0, 35.0),
                rng.range(-5.0, 35.0),
                rng.range(-10.0, 10.0),
            );
            let found = tree.closest(&vertices, &triangles, p).unwrap();
            let brute = triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|v| vertices[v]);
                    (closest_on_triangle(p, a, b, c) - p).norm()
                })
                .fold(f64::INFINITY, f64::min);
            assert!((found.distance - brute).abs() < 1e-12);
            assert!(((found.point - p).norm() - found.distance).abs() < 1e-12);
        }
    }
}
