//! From a drawing of line segments (ORIPA `.cp`, SVG, edges-only FOLD) to a triangle mesh:
//! merge near-coincident points, split lines where they cross or touch, find the faces of
//! the planar graph, drop holes, and triangulate every face with flat creases.

use crate::limits;
use crate::mesh::{
    edge_key, triangulate_polygon, Assignment, Edge, MeshParts, TriangulationBudget, Vec2,
};
use std::collections::{HashMap, HashSet};

/// One drawn line of a crease pattern.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    /// Start point.
    pub a: Vec2,
    /// End point.
    pub b: Vec2,
    /// What the line is.
    pub assignment: Assignment,
    /// Fold angle, radians, paper convention.
    pub fold_angle: f64,
}

/// What the conversion did beyond the obvious, for the user to know.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlanarReport {
    /// Line pieces that ended in the open paper (no face on either side) and were dropped.
    pub dangling_removed: usize,
    /// Closed regions bounded only by boundary lines inside the paper (kirigami holes).
    pub holes: usize,
}

struct VertexPool {
    points: Vec<Vec2>,
    grid: HashMap<(i64, i64), Vec<usize>>,
    tol: f64,
}

impl VertexPool {
    fn cell(&self, p: Vec2) -> (i64, i64) {
        (
            (p.x / self.tol).floor() as i64,
            (p.y / self.tol).floor() as i64,
        )
    }

    fn insert(&mut self, p: Vec2) -> usize {
        let (cx, cy) = self.cell(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(list) = self.grid.get(&(cx + dx, cy + dy)) {
                    if let Some(&i) = list
                        .iter()
                        .find(|&&i| (self.points[i] - p).norm() <= self.tol)
                    {
                        return i;
                    }
                }
            }
        }
        self.points.push(p);
        let i = self.points.len() - 1;
        self.grid.entry((cx, cy)).or_default().push(i);
        i
    }
}

/// Priority when two drawn lines cover the same piece: the paper's edge wins over creases,
/// folded creases over free ones, and anything over triangulation lines.
fn priority(a: Assignment) -> u8 {
    match a {
        Assignment::Boundary | Assignment::Cut => 4,
        Assignment::Mountain | Assignment::Valley => 3,
        Assignment::Unassigned => 2,
        Assignment::Flat | Assignment::Join => 1,
    }
}

/// Builds a flat mesh from drawn segments. Errors are plain causes; the caller adds the
/// file name.
pub fn mesh_from_segments(segments: &[Segment]) -> Result<(MeshParts, PlanarReport), String> {
    let tol = merge_tolerance(segments)?;
    let segs: Vec<&Segment> = segments
        .iter()
        .filter(|s| (s.b - s.a).norm() > tol)
        .collect();
    let mut pool = VertexPool {
        points: Vec::new(),
        grid: HashMap::new(),
        tol,
    };
    let segs = unique_segments(&segs, &mut pool);
    insert_crossings(&segs, &mut pool)?;
    let mut graph = split_at_points(&segs, &pool)?;
    let mut report = PlanarReport::default();
    prune_dangling(&mut graph, &mut report);
    if graph.is_empty() {
        return Err("the lines enclose no region of paper".into());
    }
    // Keep only vertices in use, renumbered.
    let mut used: Vec<usize> = graph.keys().flat_map(|&(a, b)| [a, b]).collect();
    used.sort_unstable();
    used.dedup();
    let index: HashMap<usize, usize> = used.iter().enumerate().map(|(i, &v)| (v, i)).collect();
    let flat: Vec<Vec2> = used.iter().map(|&v| pool.points[v]).collect();
    let mut keys: Vec<(usize, usize)> = graph.keys().copied().collect();
    keys.sort_unstable();
    let edges: Vec<Edge> = keys
        .iter()
        .map(|k| {
            let (assignment, fold_angle) = graph[k];
            let mut e = Edge::new(index[&k.0], index[&k.1], assignment);
            e.fold_angle = fold_angle;
            e
        })
        .collect();
    let faces = trace_faces(&flat, &edges, tol, &mut report)?;
    Ok((only_paper(flat, faces, edges), report))
}

/// The parts that bound paper: where holes meet (four cut-out squares around one point,
/// two sharing a side), the points and lines between them border no face and are left
/// out, the rest renumbered.
fn only_paper(flat: Vec<Vec2>, faces: Vec<[usize; 3]>, edges: Vec<Edge>) -> MeshParts {
    let mut on_paper = vec![false; flat.len()];
    for &v in faces.iter().flatten() {
        on_paper[v] = true;
    }
    let mut index = vec![usize::MAX; flat.len()];
    let mut kept = Vec::with_capacity(flat.len());
    for v in (0..flat.len()).filter(|&v| on_paper[v]) {
        index[v] = kept.len();
        kept.push(flat[v]);
    }
    let sides: HashSet<(usize, usize)> = faces
        .iter()
        .flat_map(|f| (0..3).map(move |k| edge_key(f[k], f[(k + 1) % 3])))
        .collect();
    let edges = edges
        .into_iter()
        .filter(|e| sides.contains(&e.key()))
        .map(|mut e| {
            e.vertices = e.vertices.map(|v| index[v]);
            e
        })
        .collect();
    let faces = faces.iter().map(|f| f.map(|v| index[v])).collect();
    MeshParts {
        positions: None,
        flat: Some(kept),
        faces,
        edges,
    }
}

/// The distance within which points are one: [`crate::tolerance::POINT_MERGE_RELATIVE`] of the drawing's
/// diagonal. Refuses coordinates that are not finite or lie beyond a kilometre, and a
/// drawing of zero size.
fn merge_tolerance(segments: &[Segment]) -> Result<f64, String> {
    if segments.is_empty() {
        return Err("no crease or boundary lines found".into());
    }
    limits::DRAWING_LINES
        .check_count("its line count", segments.len() as u64)
        .map_err(|e| e.to_string())?;
    let mut lo = Vec2::repeat(f64::INFINITY);
    let mut hi = Vec2::repeat(f64::NEG_INFINITY);
    for s in segments {
        for p in [s.a, s.b] {
            if !p.x.is_finite() || !p.y.is_finite() {
                return Err("a line has a coordinate that is not a finite number".into());
            }
            let far = p.x.abs().max(p.y.abs());
            if far > crate::mesh::MAX_COORDINATE_MM {
                return Err(format!(
                    "a line reaches {far:.3e} mm, which is not a finite length within 1 km"
                ));
            }
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        }
    }
    let diag = (hi - lo).norm();
    if diag == 0.0 {
        return Err("all lines have zero length".into());
    }
    Ok(crate::tolerance::POINT_MERGE_RELATIVE * diag)
}

/// One segment per pair of end points, the one that wins by priority: a line drawn again
/// (a copied shape, a crease under a cut) joins the same two points. Sorted by the pair,
/// so the result does not depend on drawing order.
fn unique_segments<'a>(segs: &[&'a Segment], pool: &mut VertexPool) -> Vec<&'a Segment> {
    let mut unique: HashMap<(usize, usize), &Segment> = HashMap::new();
    for s in segs {
        let (a, b) = (pool.insert(s.a), pool.insert(s.b));
        let entry = unique.entry((a.min(b), a.max(b))).or_insert(s);
        if (priority(s.assignment), s.assignment) > (priority(entry.assignment), entry.assignment) {
            *entry = s;
        }
    }
    let mut pairs: Vec<((usize, usize), &Segment)> = unique.into_iter().collect();
    pairs.sort_unstable_by_key(|(k, _)| *k);
    pairs.into_iter().map(|(_, s)| s).collect()
}

fn min_x(s: &Segment) -> f64 {
    s.a.x.min(s.b.x)
}

fn max_x(s: &Segment) -> f64 {
    s.a.x.max(s.b.x)
}

/// Adds the proper crossings of the segments to the pool; a sweep by x compares only
/// overlapping spans.
/// The pairs compared are counted first and refused past [`limits::ARRANGEMENT_WORK`].
fn insert_crossings(segs: &[&Segment], pool: &mut VertexPool) -> Result<(), String> {
    let tol = pool.tol;
    let mut order: Vec<usize> = (0..segs.len()).collect();
    order.sort_by(|&i, &j| min_x(segs[i]).total_cmp(&min_x(segs[j])));
    let starts: Vec<f64> = order.iter().map(|&i| min_x(segs[i])).collect();
    let pairs: u64 = order
        .iter()
        .enumerate()
        .map(|(oi, &i)| {
            let end = starts.partition_point(|&x| x <= max_x(segs[i]) + tol);
            end.saturating_sub(oi + 1) as u64
        })
        .sum();
    if pairs > limits::ARRANGEMENT_WORK {
        return Err(too_tangled(
            segs.len(),
            pairs,
            "pairs of lines side by side",
        ));
    }
    for (oi, &i) in order.iter().enumerate() {
        for &j in &order[oi + 1..] {
            if min_x(segs[j]) > max_x(segs[i]) + tol {
                break;
            }
            if let Some(p) = crossing(segs[i], segs[j], tol) {
                pool.insert(p);
                if pool.points.len() > limits::DRAWING_POINTS {
                    return Err(format!(
                        "its {} lines cross at more than {} points, more than a crease pattern has: remove the stray lines",
                        segs.len(),
                        limits::DRAWING_POINTS
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The refusal of a drawing past [`limits::ARRANGEMENT_WORK`].
fn too_tangled(lines: usize, work: u64, what: &str) -> String {
    format!(
        "its {lines} lines make {work} {what}, more than crease arranges ({}): \
         a crease pattern has no such pile of overlapping lines; remove the duplicates or split the drawing",
        limits::ARRANGEMENT_WORK
    )
}

/// Pieces of the drawing between points, each with the assignment and fold angle that won it.
type PieceGraph = HashMap<(usize, usize), (Assignment, f64)>;

/// Every segment split at the pool's points lying on it: the pieces as vertex pairs, with
/// the assignment and fold angle of the segment that wins each piece by priority.
fn split_at_points(segs: &[&Segment], pool: &VertexPool) -> Result<PieceGraph, String> {
    let tol = pool.tol;
    let mut by_x: Vec<usize> = (0..pool.points.len()).collect();
    by_x.sort_by(|&i, &j| pool.points[i].x.total_cmp(&pool.points[j].x));
    let xs: Vec<f64> = by_x.iter().map(|&i| pool.points[i].x).collect();
    let span = |s: &Segment| {
        let from = xs.partition_point(|&x| x < min_x(s) - tol);
        let to = xs.partition_point(|&x| x <= max_x(s) + tol);
        (from, to)
    };
    let tests: u64 = segs
        .iter()
        .map(|s| {
            let (from, to) = span(s);
            to.saturating_sub(from) as u64
        })
        .sum();
    if tests > limits::ARRANGEMENT_WORK {
        return Err(too_tangled(
            segs.len(),
            tests,
            "tests of a point against a line",
        ));
    }
    let mut graph: PieceGraph = HashMap::new();
    for s in segs {
        let d = s.b - s.a;
        let len = d.norm();
        let u = d / len;
        let (from, to) = span(s);
        let mut on: Vec<(f64, usize)> = by_x[from..to]
            .iter()
            .filter_map(|&k| {
                let r = pool.points[k] - s.a;
                let t = r.dot(&u);
                (t > -tol && t < len + tol && u.perp(&r).abs() <= tol).then_some((t, k))
            })
            .collect();
        on.sort_by(|a, b| a.0.total_cmp(&b.0));
        on.dedup_by_key(|x| x.1);
        for w in on.windows(2) {
            let (p, q) = (w[0].1, w[1].1);
            if p == q {
                continue;
            }
            let k = (p.min(q), p.max(q));
            let entry = graph.entry(k).or_insert((s.assignment, s.fold_angle));
            // Higher priority wins; between equals the larger assignment, so the result
            // does not depend on drawing order.
            if (priority(s.assignment), s.assignment) > (priority(entry.0), entry.0) {
                *entry = (s.assignment, s.fold_angle);
            }
        }
    }
    Ok(graph)
}

fn crossing(s: &Segment, t: &Segment, tol: f64) -> Option<Vec2> {
    let r = s.b - s.a;
    let q = t.b - t.a;
    let denom = r.perp(&q);
    if denom.abs() <= 1e-12 * r.norm() * q.norm() {
        return None; // parallel: overlaps are handled by splitting at endpoints
    }
    let w = t.a - s.a;
    let u = w.perp(&q) / denom;
    let v = w.perp(&r) / denom;
    let (eu, ev) = (tol / r.norm(), tol / q.norm());
    (u > -eu && u < 1.0 + eu && v > -ev && v < 1.0 + ev).then(|| s.a + r * u)
}

fn prune_dangling(graph: &mut PieceGraph, report: &mut PlanarReport) {
    loop {
        let mut degree: HashMap<usize, usize> = HashMap::new();
        for &(a, b) in graph.keys() {
            *degree.entry(a).or_default() += 1;
            *degree.entry(b).or_default() += 1;
        }
        let before = graph.len();
        graph.retain(|&(a, b), _| degree[&a] > 1 && degree[&b] > 1);
        let removed = before - graph.len();
        if removed == 0 {
            return;
        }
        report.dangling_removed += removed;
    }
}

/// The face cycle each directed edge (from, to) belongs to.
type CycleOfEdge = HashMap<(usize, usize), usize>;

/// Every face cycle of the planar graph, each traced with its face on the left, and which
/// cycle each directed edge belongs to.
fn face_cycles(flat: &[Vec2], edges: &[Edge]) -> (Vec<Vec<usize>>, CycleOfEdge) {
    let n = flat.len();
    let mut around: Vec<Vec<usize>> = vec![Vec::new(); n];
    for e in edges {
        let [a, b] = e.vertices;
        around[a].push(b);
        around[b].push(a);
    }
    for (v, list) in around.iter_mut().enumerate() {
        let p = flat[v];
        list.sort_by(|&x, &y| {
            let (dx, dy) = (flat[x] - p, flat[y] - p);
            dx.y.atan2(dx.x).total_cmp(&dy.y.atan2(dy.x))
        });
    }
    let mut visited: HashMap<(usize, usize), usize> = HashMap::new();
    let mut cycles: Vec<Vec<usize>> = Vec::new();
    for e in edges {
        for (a, b) in [
            (e.vertices[0], e.vertices[1]),
            (e.vertices[1], e.vertices[0]),
        ] {
            if visited.contains_key(&(a, b)) {
                continue;
            }
            let id = cycles.len();
            let mut cycle = Vec::new();
            let (mut u, mut v) = (a, b);
            while !visited.contains_key(&(u, v)) {
                visited.insert((u, v), id);
                cycle.push(u);
                // The next edge of the face on the left turns clockwise from v→u.
                let list = &around[v];
                let k = list.iter().position(|&x| x == u).expect("twin in list");
                let w = list[(k + list.len() - 1) % list.len()];
                (u, v) = (v, w);
            }
            cycles.push(cycle);
        }
    }
    (cycles, visited)
}

/// Faces of the planar graph, triangulated. Each bounded face is traced with the paper on
/// its left; the unbounded face and holes are dropped.
fn trace_faces(
    flat: &[Vec2],
    edges: &[Edge],
    tol: f64,
    report: &mut PlanarReport,
) -> Result<Vec<[usize; 3]>, String> {
    let (cycles, visited) = face_cycles(flat, edges);
    let area = |c: &[usize]| -> f64 {
        (0..c.len())
            .map(|i| flat[c[i]].perp(&flat[c[(i + 1) % c.len()]]))
            .sum::<f64>()
    };
    let bounded: Vec<bool> = cycles.iter().map(|c| area(c) > 0.0).collect();
    let edge_kind: HashMap<(usize, usize), Assignment> =
        edges.iter().map(|e| (e.key(), e.assignment)).collect();
    let mut faces = Vec::new();
    let mut budget = TriangulationBudget::default();
    for (id, c) in cycles.iter().enumerate() {
        if !bounded[id] {
            continue;
        }
        let sides = (0..c.len()).map(|i| (c[i], c[(i + 1) % c.len()]));
        let is_hole = sides
            .clone()
            .all(|(a, b)| edge_kind[&edge_key(a, b)].is_boundary() && bounded[visited[&(b, a)]]);
        if is_hole {
            report.holes += 1;
            continue;
        }
        let corners: Vec<Vec2> = c.iter().map(|&v| flat[v]).collect();
        budget.charge(corners.len())?;
        let tris = triangulate_polygon(&corners, tol)
            .or_else(|| triangulate_polygon(&corners, 0.0))
            .ok_or_else(|| {
            format!(
                "the region with corners at vertices {:?} cannot be triangulated (self-touching or degenerate)",
                c
            )
        })?;
        faces.extend(tris.iter().map(|t| [c[t[0]], c[t[1]], c[t[2]]]));
    }
    if faces.is_empty() {
        return Err("the lines enclose no region of paper".into());
    }
    Ok(faces)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(a: (f64, f64), b: (f64, f64), asg: Assignment) -> Segment {
        Segment {
            a: Vec2::new(a.0, a.1),
            b: Vec2::new(b.0, b.1),
            assignment: asg,
            fold_angle: asg.default_target(),
        }
    }

    /// The area the triangles cover (mm²).
    fn paper_area(faces: &[[usize; 3]], flat: &[Vec2]) -> f64 {
        faces
            .iter()
            .map(|f| 0.5 * (flat[f[1]] - flat[f[0]]).perp(&(flat[f[2]] - flat[f[0]])))
            .sum()
    }

    fn square(size: f64) -> Vec<Segment> {
        let c = [(0.0, 0.0), (size, 0.0), (size, size), (0.0, size)];
        (0..4)
            .map(|i| seg(c[i], c[(i + 1) % 4], Assignment::Boundary))
            .collect()
    }

    #[test]
    fn crossing_diagonals_are_split_into_four_creases() {
        let mut s = square(2.0);
        s.push(seg((0.0, 0.0), (2.0, 2.0), Assignment::Mountain));
        s.push(seg((2.0, 0.0), (0.0, 2.0), Assignment::Valley));
        let (parts, _) = mesh_from_segments(&s).unwrap();
        assert_eq!(parts.flat.as_ref().unwrap().len(), 5);
        let creases = parts
            .edges
            .iter()
            .filter(|e| e.assignment.is_folded())
            .count();
        assert_eq!(creases, 4);
        assert_eq!(parts.faces.len(), 4);
    }

    #[test]
    fn near_coincident_endpoints_merge_and_t_junctions_split() {
        let mut s = square(10.0);
        // Ends 1e-6 off the boundary: merged onto it, splitting the bottom side.
        s.push(seg((5.0, 1e-6), (5.0, 10.0), Assignment::Valley));
        let (parts, report) = mesh_from_segments(&s).unwrap();
        assert_eq!(report.dangling_removed, 0);
        assert_eq!(parts.flat.as_ref().unwrap().len(), 6);
        let boundary = parts
            .edges
            .iter()
            .filter(|e| e.assignment == Assignment::Boundary);
        assert_eq!(boundary.count(), 6);
    }

    #[test]
    fn a_closed_boundary_loop_inside_the_paper_is_a_hole() {
        let mut s = square(10.0);
        let c = [(4.0, 4.0), (6.0, 4.0), (6.0, 6.0), (4.0, 6.0)];
        for i in 0..4 {
            s.push(seg(c[i], c[(i + 1) % 4], Assignment::Cut));
        }
        s.push(seg((0.0, 0.0), (4.0, 4.0), Assignment::Flat));
        s.push(seg((10.0, 10.0), (6.0, 6.0), Assignment::Flat));
        let (parts, report) = mesh_from_segments(&s).unwrap();
        assert_eq!(report.holes, 1);
        let flat = parts.flat.unwrap();
        let area = paper_area(&parts.faces, &flat);
        assert!((area - 96.0).abs() < 1e-9, "area {area}");
    }

    /// Four square holes around one point: the point and the cuts between the holes
    /// border no paper, so they are left out and the rest is a valid mesh.
    #[test]
    fn points_and_lines_between_holes_are_left_out() {
        let mut s = square(30.0);
        for (a, b) in [
            ((10.0, 10.0), (20.0, 10.0)),
            ((20.0, 10.0), (20.0, 20.0)),
            ((20.0, 20.0), (10.0, 20.0)),
            ((10.0, 20.0), (10.0, 10.0)),
            ((15.0, 10.0), (15.0, 20.0)),
            ((10.0, 15.0), (20.0, 15.0)),
        ] {
            s.push(seg(a, b, Assignment::Cut));
        }
        s.push(seg((0.0, 0.0), (10.0, 10.0), Assignment::Flat));
        s.push(seg((30.0, 30.0), (20.0, 20.0), Assignment::Flat));
        let (parts, report) = mesh_from_segments(&s).unwrap();
        assert_eq!(report.holes, 4);
        let flat = parts.flat.clone().unwrap();
        assert!(flat
            .iter()
            .all(|p| (p - Vec2::new(15.0, 15.0)).norm() > 1.0));
        assert!(parts.edges.iter().all(|e| {
            let mid = (flat[e.vertices[0]] + flat[e.vertices[1]]) / 2.0;
            (mid - Vec2::new(15.0, 15.0)).norm() > 4.0
        }));
        let area = paper_area(&parts.faces, &flat);
        assert!((area - 800.0).abs() < 1e-9, "area {area}");
        let mesh = crate::mesh::Mesh::new(parts).unwrap();
        assert_eq!(mesh.shape().holes, 1);
    }

    #[test]
    fn a_crease_ending_in_open_paper_is_dropped_and_counted() {
        let mut s = square(10.0);
        s.push(seg((5.0, 0.0), (5.0, 5.0), Assignment::Mountain));
        let (parts, report) = mesh_from_segments(&s).unwrap();
        assert_eq!(report.dangling_removed, 1);
        assert!(parts
            .edges
            .iter()
            .all(|e| e.assignment != Assignment::Mountain));
    }
}
