//! An order checker written apart from crease's layer solver, for the `faceOrders` the
//! tool writes. It reads only the FOLD text: folds the crease pattern itself (reflecting
//! each face across every ±180° line on the way from face 0), then checks the stacking
//! rules of a flat fold at sample points —
//! - every pair of faces over one point is ordered, and the order over that point is a
//!   total order (no cycles: transitivity);
//! - each mountain/valley crease puts its faces the right way round;
//! - at every folded line, faces passing straight through it (a face crossing the line,
//!   or two faces joined flat across it) keep their order from one side to the other
//!   (tortilla–tortilla), no pass-through lies between the two faces of a crease folded
//!   there (taco–tortilla), and two creases folded there on one side nest or stay apart
//!   (taco–taco).

use serde_json::Value;

type P = [f64; 2];

struct Edge {
    id: usize,
    vertices: [usize; 2],
    a: usize,
    b: Option<usize>,
    angle: f64,
}

/// The box around some points, as (lowest corner, highest corner).
fn bounds(points: &[P]) -> (P, P) {
    points.iter().fold((points[0], points[0]), |(lo, hi), p| {
        (
            [lo[0].min(p[0]), lo[1].min(p[1])],
            [hi[0].max(p[0]), hi[1].max(p[1])],
        )
    })
}

/// `p` lies in the box `b` grown by `margin`.
fn in_box(b: &(P, P), p: P, margin: f64) -> bool {
    (0..2).all(|i| p[i] >= b.0[i] - margin && p[i] <= b.1[i] + margin)
}

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1]]
}
fn cross(a: P, b: P) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// The flat-folded faces of a FOLD file and their written order.
pub struct Folded {
    /// Each face's folded polygon.
    pub polygons: Vec<Vec<P>>,
    /// Whether the face's front (its crease-pattern orientation) faces +z once folded.
    pub up: Vec<bool>,
    /// Each edge: its vertices, the faces across it and its fold angle in degrees.
    edges: Vec<Edge>,
    /// above[f·F + g]: Some(true) when f lies higher (+z) than g, from `faceOrders`
    /// (F faces; a table, not a map, since the sampling reads it for every pair of
    /// faces stacked over every sample point).
    above: Vec<Option<bool>>,
    size: f64,
    /// Each polygon's box: a point outside it is outside the polygon (only what makes
    /// the sampling below fast; the tests are the same).
    boxes: Vec<(P, P)>,
    /// Each edge's folded image, seen from its face `a`.
    images: Vec<(P, P)>,
}

fn coords(v: &Value) -> Vec<P> {
    v.as_array()
        .expect("vertices_coords")
        .iter()
        .map(|c| [c[0].as_f64().unwrap(), c[1].as_f64().unwrap()])
        .collect()
}

impl Folded {
    /// Folds the file's crease pattern (the `creasePattern` frame when the top level is
    /// a folded form) across its ±180° lines and reads `faceOrders`; `None` for a
    /// folded form without a crease pattern.
    pub fn read(json: &Value) -> Option<Folded> {
        let top_is_cp = json["frame_classes"]
            .as_array()
            .is_none_or(|c| !c.iter().any(|x| x == "foldedForm"));
        let cp = if top_is_cp {
            coords(&json["vertices_coords"])
        } else {
            coords(json["file_frames"].get(0)?.get("vertices_coords")?)
        };
        let faces: Vec<Vec<usize>> =
            serde_json::from_value(json["faces_vertices"].clone()).unwrap();
        let ev: Vec<[usize; 2]> = serde_json::from_value(json["edges_vertices"].clone()).unwrap();
        let assignment: Vec<String> =
            serde_json::from_value(json["edges_assignment"].clone()).unwrap();
        let angles: Vec<f64> = match json.get("edges_foldAngle") {
            Some(a) => serde_json::from_value(a.clone()).unwrap(),
            None => assignment
                .iter()
                .map(|a| match a.as_str() {
                    "V" => 180.0,
                    "M" => -180.0,
                    _ => 0.0,
                })
                .collect(),
        };
        let mut by_pair = std::collections::HashMap::new();
        for (e, &[u, v]) in ev.iter().enumerate() {
            by_pair.insert((u.min(v), u.max(v)), e);
        }
        let mut edge_faces: Vec<Vec<usize>> = vec![Vec::new(); ev.len()];
        for (f, poly) in faces.iter().enumerate() {
            for k in 0..poly.len() {
                let (u, v) = (poly[k], poly[(k + 1) % poly.len()]);
                edge_faces[by_pair[&(u.min(v), u.max(v))]].push(f);
            }
        }
        // Affine maps x ↦ m·x + t per face, by breadth-first reflection.
        type Map = ([[f64; 2]; 2], P);
        let apply = |m: &Map, x: P| {
            [
                m.0[0][0] * x[0] + m.0[0][1] * x[1] + m.1[0],
                m.0[1][0] * x[0] + m.0[1][1] * x[1] + m.1[1],
            ]
        };
        let mut maps: Vec<Option<Map>> = vec![None; faces.len()];
        maps[0] = Some(([[1.0, 0.0], [0.0, 1.0]], [0.0, 0.0]));
        let mut queue = std::collections::VecDeque::from([0]);
        while let Some(f) = queue.pop_front() {
            let m = maps[f].unwrap();
            let poly = &faces[f];
            for k in 0..poly.len() {
                let (u, v) = (poly[k], poly[(k + 1) % poly.len()]);
                let e = by_pair[&(u.min(v), u.max(v))];
                for &g in edge_faces[e].iter().filter(|&&g| g != f) {
                    if maps[g].is_some() {
                        continue;
                    }
                    let folded = angles[e].abs() > 90.0;
                    let next = if folded {
                        // Reflect across the line u–v (in the crease pattern), then map.
                        let (a, b) = (cp[u], cp[v]);
                        let d = sub(b, a);
                        let l2 = d[0] * d[0] + d[1] * d[1];
                        let r = [
                            [(d[0] * d[0] - d[1] * d[1]) / l2, 2.0 * d[0] * d[1] / l2],
                            [2.0 * d[0] * d[1] / l2, (d[1] * d[1] - d[0] * d[0]) / l2],
                        ];
                        let ra = [
                            r[0][0] * a[0] + r[0][1] * a[1],
                            r[1][0] * a[0] + r[1][1] * a[1],
                        ];
                        let rt = [a[0] - ra[0], a[1] - ra[1]];
                        let mm = [
                            [
                                m.0[0][0] * r[0][0] + m.0[0][1] * r[1][0],
                                m.0[0][0] * r[0][1] + m.0[0][1] * r[1][1],
                            ],
                            [
                                m.0[1][0] * r[0][0] + m.0[1][1] * r[1][0],
                                m.0[1][0] * r[0][1] + m.0[1][1] * r[1][1],
                            ],
                        ];
                        (mm, apply(&m, rt))
                    } else {
                        m
                    };
                    maps[g] = Some(next);
                    queue.push_back(g);
                }
            }
        }
        let polygons: Vec<Vec<P>> = faces
            .iter()
            .zip(&maps)
            .map(|(poly, m)| {
                let m = m.expect("a connected crease pattern");
                poly.iter().map(|&v| apply(&m, cp[v])).collect()
            })
            .collect();
        // A face's front is the side its crease-pattern winding makes +z.
        let up = maps
            .iter()
            .zip(&faces)
            .map(|(m, poly)| {
                let m = m.unwrap().0;
                let area: f64 = (0..poly.len())
                    .map(|i| cross(cp[poly[i]], cp[poly[(i + 1) % poly.len()]]))
                    .sum();
                (m[0][0] * m[1][1] - m[0][1] * m[1][0] > 0.0) == (area > 0.0)
            })
            .collect::<Vec<_>>();
        let edges: Vec<Edge> = ev
            .iter()
            .enumerate()
            .map(|(e, &vertices)| Edge {
                id: e,
                vertices,
                a: edge_faces[e][0],
                b: edge_faces[e].get(1).copied(),
                angle: angles[e],
            })
            .collect();
        let count = faces.len();
        let mut above = vec![None; count * count];
        let orders: Vec<[i64; 3]> =
            serde_json::from_value(json["faceOrders"].clone()).expect("faceOrders");
        for [f, g, s] in orders {
            let (f, g) = (f as usize, g as usize);
            let f_above = (s > 0) == up[g];
            above[f * count + g] = Some(f_above);
            above[g * count + f] = Some(!f_above);
        }
        let all: Vec<P> = polygons.iter().flatten().copied().collect();
        let (lo, hi) = bounds(&all);
        let size = (sub(hi, lo)[0].powi(2) + sub(hi, lo)[1].powi(2)).sqrt();
        let boxes = polygons.iter().map(|poly| bounds(poly)).collect();
        let images = edges
            .iter()
            .map(|e| {
                let image = |v: usize| {
                    let k = faces[e.a].iter().position(|&x| x == v).unwrap();
                    polygons[e.a][k]
                };
                (image(e.vertices[0]), image(e.vertices[1]))
            })
            .collect();
        Some(Folded {
            polygons,
            up,
            edges,
            above,
            size,
            boxes,
            images,
        })
    }

    /// Faces whose interior holds `p` by more than `margin`.
    fn over(&self, p: P, margin: f64) -> Vec<usize> {
        (0..self.polygons.len())
            .filter(|&f| in_box(&self.boxes[f], p, margin) && inside(&self.polygons[f], p, margin))
            .collect()
    }

    /// Every rule the file breaks, in words (empty when its order is valid).
    pub fn violations(&self) -> Vec<String> {
        let mut bad = Vec::new();
        // Overlaps thinner than a hundred-thousandth of the folded size are contact: what
        // rounding leaves where layers meet edge to edge.
        let margin = 1e-5 * self.size;
        let step = 1e-4 * self.size;
        let count = self.polygons.len();
        let above = |f: usize, g: usize| self.above[f * count + g];
        // Levels over a point: each face's count of faces below it, when a total order.
        let levels = |stack: &[usize], bad: &mut Vec<String>| -> Option<Vec<usize>> {
            let mut below = Vec::new();
            for &f in stack {
                let mut n = 0;
                for &g in stack.iter().filter(|&&g| g != f) {
                    match above(f, g) {
                        Some(true) => n += 1,
                        Some(false) => {}
                        None => {
                            bad.push(format!("faces {f} and {g} overlap with no order"));
                            return None;
                        }
                    }
                }
                below.push(n);
            }
            let mut sorted = below.clone();
            sorted.sort_unstable();
            if sorted.iter().enumerate().any(|(i, &n)| i != n) {
                bad.push(format!("faces {stack:?} form a cycle"));
                return None;
            }
            Some(below)
        };
        // Stacks over interior points of every face.
        for poly in &self.polygons {
            for k in 1..poly.len() - 1 {
                let c = [0, 1].map(|i| (poly[0][i] + poly[k][i] + poly[k + 1][i]) / 3.0);
                levels(&self.over(c, margin), &mut bad);
            }
        }
        // Mountain and valley.
        for &Edge {
            id: e, a, b, angle, ..
        } in &self.edges
        {
            let Some(b) = b else { continue };
            if angle.abs() < 90.0 {
                continue;
            }
            // Valley: each face comes to lie on the other's front.
            let want = (angle > 0.0) == self.up[a];
            if above(b, a) != Some(want) {
                bad.push(format!(
                    "edge {e} ({angle}°): faces {a} and {b} the wrong way round"
                ));
            }
        }
        // The rules at each folded line, sampled just either side of one point on it.
        for poly in &self.polygons {
            for k in 0..poly.len() {
                let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
                let d = sub(q, p);
                let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
                if len < 1e3 * margin {
                    continue;
                }
                let at = [p[0] + 0.37 * d[0], p[1] + 0.37 * d[1]];
                let n = [-d[1] / len * step, d[0] / len * step];
                let left = self.over([at[0] + n[0], at[1] + n[1]], margin);
                let right = self.over([at[0] - n[0], at[1] - n[1]], margin);
                let (Some(ll), Some(rl)) = (levels(&left, &mut bad), levels(&right, &mut bad))
                else {
                    continue;
                };
                self.check_line(at, (&left, &ll), (&right, &rl), &mut bad);
            }
        }
        bad.sort();
        bad.dedup();
        bad
    }

    fn check_line(
        &self,
        at: P,
        (left, ll): (&[usize], &[usize]),
        (right, rl): (&[usize], &[usize]),
        bad: &mut Vec<String>,
    ) {
        // Edge e's folded image (seen from its face a) passes through `at`.
        let on_line = |e: &Edge| {
            let (p, q) = self.images[e.id];
            let reach = 1e-6 * self.size;
            if !in_box(&bounds(&[p, q]), at, reach) {
                return false;
            }
            let d = sub(q, p);
            let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
            let t = (sub(at, p)[0] * d[0] + sub(at, p)[1] * d[1]) / (len * len);
            cross(d, sub(at, p)).abs() / len < reach && t > 0.0 && t < 1.0
        };
        // Pass-throughs: (level on the left, level on the right).
        let mut through: Vec<(usize, usize, String)> = Vec::new();
        for (i, &f) in left.iter().enumerate() {
            if let Some(r) = level(right, rl, f) {
                through.push((ll[i], r, format!("face {f}")));
            }
        }
        // Hinges at this point: tacos per side, tortillas through.
        let mut tacos: [Vec<(usize, usize, String)>; 2] = [Vec::new(), Vec::new()];
        for edge in &self.edges {
            let (e, a) = (edge.id, edge.a);
            let Some(b) = edge.b else { continue };
            if !on_line(edge) {
                continue;
            }
            let name = format!("edge {e} (faces {a}, {b})");
            let sides = |x: usize| (level(left, ll, x), level(right, rl, x));
            match (sides(a), sides(b)) {
                ((Some(x), None), (Some(y), None)) => tacos[0].push((x.min(y), x.max(y), name)),
                ((None, Some(x)), (None, Some(y))) => tacos[1].push((x.min(y), x.max(y), name)),
                ((Some(x), None), (None, Some(y))) => through.push((x, y, name)),
                ((None, Some(y)), (Some(x), None)) => through.push((x, y, name)),
                _ => {}
            }
        }
        for (i, x) in through.iter().enumerate() {
            for y in &through[i + 1..] {
                if (x.0 < y.0) != (x.1 < y.1) {
                    bad.push(format!(
                        "{} and {} swap order across the line at {at:?} (tortilla-tortilla)",
                        x.2, y.2
                    ));
                }
            }
        }
        for (side, list) in tacos.iter().enumerate() {
            for (i, t) in list.iter().enumerate() {
                for x in &through {
                    let l = if side == 0 { x.0 } else { x.1 };
                    if t.0 < l && l < t.1 {
                        bad.push(format!(
                            "{} lies inside the fold of {} (taco-tortilla)",
                            x.2, t.2
                        ));
                    }
                }
                for u in &list[i + 1..] {
                    let interleave = (t.0 < u.0 && u.0 < t.1 && t.1 < u.1)
                        || (u.0 < t.0 && t.0 < u.1 && u.1 < t.1);
                    if interleave {
                        bad.push(format!("{} and {} interleave (taco-taco)", t.2, u.2));
                    }
                }
            }
        }
    }
}

/// The level of face `x` in a stack (`side`, with each face's `levels`), if it is there.
fn level(side: &[usize], levels: &[usize], x: usize) -> Option<usize> {
    side.iter().position(|&y| y == x).map(|i| levels[i])
}

/// `p` lies inside polygon `poly` (either orientation) by more than `margin`.
fn inside(poly: &[P], p: P, margin: f64) -> bool {
    let mut winding = 0i32;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let d = sub(b, a);
        let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let t = ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / (len * len);
        let t = t.clamp(0.0, 1.0);
        let c = [a[0] + t * d[0] - p[0], a[1] + t * d[1] - p[1]];
        if c[0].hypot(c[1]) <= margin {
            return false;
        }
        if (a[1] <= p[1]) != (b[1] <= p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * d[0];
            if x > p[0] {
                winding += if b[1] > a[1] { 1 } else { -1 };
            }
        }
    }
    winding != 0
}
