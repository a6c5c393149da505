//! Crease lines of a flat pattern: edges of one fold type that continue straight through a
//! vertex are merged into one line, so a plotter draws each fold in one pass. Each line
//! remembers the points along it where three or more creases meet, where dashes must stop.

use crate::mesh::{Assignment, Edge, Mesh, Vec2};
use std::collections::HashMap;

/// What a line does to the paper.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LineKind {
    /// Paper boundary: cut through.
    Cut,
    /// Mountain fold: scored (from the front, or the back in a mirrored pass).
    Mountain,
    /// Valley fold: scored.
    Valley,
    /// Unfolded or free crease (triangulation, twist, unassigned): not scored by default.
    Flat,
}

impl LineKind {
    /// Every kind, in cutting order: scores before the cut so the sheet stays held.
    pub const ALL: [LineKind; 4] = [
        LineKind::Valley,
        LineKind::Mountain,
        LineKind::Flat,
        LineKind::Cut,
    ];

    /// The kind of an edge assignment.
    pub fn of(a: Assignment) -> LineKind {
        match a {
            Assignment::Boundary | Assignment::Cut => LineKind::Cut,
            Assignment::Mountain => LineKind::Mountain,
            Assignment::Valley => LineKind::Valley,
            Assignment::Flat | Assignment::Join | Assignment::Unassigned => LineKind::Flat,
        }
    }

    /// The kind an edge is scored as. An unassigned crease that the design folds (by more
    /// than [`UNASSIGNED_FOLDED`]) is scored as the mountain or valley it became, so the
    /// sheet can take the shape: Resch's tuck sides are flat in the regular pattern but
    /// turn when a design bends its tiles.
    pub fn of_edge(e: &Edge) -> LineKind {
        if e.assignment == Assignment::Unassigned && e.fold_angle.abs() > UNASSIGNED_FOLDED {
            // Paper convention: a positive fold angle is a mountain.
            if e.fold_angle > 0.0 {
                LineKind::Mountain
            } else {
                LineKind::Valley
            }
        } else {
            LineKind::of(e.assignment)
        }
    }

    /// The kind each edge of `mesh` is scored as ([`LineKind::of_edge`]), except that in a
    /// pattern with curved creases an unassigned edge is a ruling of the developable
    /// surface between them: real paper bends smoothly there, so it is never scored,
    /// however far the polyhedral model bends it (scoring the rulings of a curved-crease
    /// model would fold it into facets).
    pub fn of_mesh(mesh: &Mesh) -> Vec<LineKind> {
        let curved = crate::constraints::has_curved_creases(mesh);
        mesh.edges()
            .iter()
            .map(|e| {
                if curved && e.assignment == Assignment::Unassigned {
                    LineKind::Flat
                } else {
                    LineKind::of_edge(e)
                }
            })
            .collect()
    }

    /// Lower-case name, for layers and reports.
    pub fn name(self) -> &'static str {
        match self {
            LineKind::Cut => "cut",
            LineKind::Mountain => "mountain",
            LineKind::Valley => "valley",
            LineKind::Flat => "flat",
        }
    }
}

/// Fold angle (radians, 1°) beyond which an unassigned crease is scored.
pub const UNASSIGNED_FOLDED: f64 = std::f64::consts::PI / 180.0;

/// A straight crease line on the flat pattern.
#[derive(Clone, Debug, PartialEq)]
pub struct CreaseLine {
    /// Start point (mm).
    pub a: Vec2,
    /// End point (mm).
    pub b: Vec2,
    /// Fold type.
    pub kind: LineKind,
    /// Positions along the line (0 = a, 1 = b) of vertices where three or more creases or
    /// cuts meet, ends included when they qualify.
    pub junctions: Vec<f64>,
}

impl CreaseLine {
    /// Length in mm.
    pub fn length(&self) -> f64 {
        (self.b - self.a).norm()
    }
}

/// Merges the mesh's edges, laid out at `flat`, into straight lines per kind.
pub fn crease_lines(mesh: &Mesh, flat: &[Vec2]) -> Vec<CreaseLine> {
    let edges = mesh.edges();
    let kinds = LineKind::of_mesh(mesh);
    // Creases and cuts meeting at each vertex (flat lines are not scored, so they do not
    // weaken the paper and do not count).
    let mut degree = vec![0usize; flat.len()];
    for (e, &k) in edges.iter().zip(&kinds) {
        if k != LineKind::Flat {
            degree[e.vertices[0]] += 1;
            degree[e.vertices[1]] += 1;
        }
    }
    let mut by_vertex: HashMap<(usize, LineKind), Vec<usize>> = HashMap::new();
    for (i, e) in edges.iter().enumerate() {
        let k = kinds[i];
        by_vertex.entry((e.vertices[0], k)).or_default().push(i);
        by_vertex.entry((e.vertices[1], k)).or_default().push(i);
    }
    let dir = |e: usize, from: usize| -> Vec2 {
        let other = edges[e].other(from);
        (flat[other] - flat[from]).normalize()
    };
    // The edge continuing `e` straight through vertex `v`, if exactly one does.
    let continuation = |e: usize, v: usize| -> Option<usize> {
        let k = kinds[e];
        let d = -dir(e, v);
        let mut found = by_vertex[&(v, k)]
            .iter()
            .copied()
            .filter(|&f| f != e && dir(f, v).dot(&d) > 1.0 - 1e-9);
        let first = found.next();
        first.filter(|_| found.next().is_none())
    };
    let mut used = vec![false; edges.len()];
    let mut lines = Vec::new();
    for start in 0..edges.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let kind = kinds[start];
        // Walk both ways from the edge.
        let mut chain = vec![edges[start].vertices[0], edges[start].vertices[1]];
        for forward in [true, false] {
            let (mut e, mut v) = if forward {
                (start, edges[start].vertices[1])
            } else {
                (start, edges[start].vertices[0])
            };
            while let Some(next) = continuation(e, v) {
                if used[next] {
                    break;
                }
                used[next] = true;
                v = edges[next].other(v);
                e = next;
                if forward {
                    chain.push(v);
                } else {
                    chain.insert(0, v);
                }
            }
        }
        let (a, b) = (flat[chain[0]], flat[*chain.last().unwrap()]);
        let len = (b - a).norm();
        let junctions = chain
            .iter()
            .filter(|&&v| degree[v] >= 3)
            .map(|&v| (flat[v] - a).norm() / len)
            .collect();
        lines.push(CreaseLine {
            a,
            b,
            kind,
            junctions,
        });
    }
    drop_second_sides(lines)
}

/// Cut lines once: the two sides of a slit (kirigami) are two boundary chains laid on the
/// same line of the sheet, and a knife that cut both would run the slit twice.
fn drop_second_sides(lines: Vec<CreaseLine>) -> Vec<CreaseLine> {
    let key = |p: Vec2| [(p.x * 1e6).round() as i64, (p.y * 1e6).round() as i64];
    let mut seen = std::collections::HashSet::new();
    lines
        .into_iter()
        .filter(|l| {
            if l.kind != LineKind::Cut {
                return true;
            }
            let (a, b) = (key(l.a), key(l.b));
            seen.insert(if a < b { (a, b) } else { (b, a) })
        })
        .collect()
}
