//! Crease lines of a flat pattern: edges of one fold type that continue straight through a
//! vertex are merged into one line, so a plotter draws each fold in one pass. Each line
//! remembers the points along it where three or more creases meet, where dashes must stop.

use super::curve::{SmoothCurve, FLATTEN_MM};
use crate::mesh::{boundary_runs, curve_runs, run_edges, Assignment, Edge, Mesh, Vec2};
use std::collections::HashMap;

/// What a line does to the paper.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
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
        Self::of_mesh_given(mesh, crate::constraints::has_curved_creases(mesh))
    }

    /// [`LineKind::of_mesh`], knowing whether the mesh has curved creases.
    fn of_mesh_given(mesh: &Mesh, curved: bool) -> Vec<LineKind> {
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

/// A crease line on the flat pattern: straight, or the smooth curve a chain of chords
/// stands for.
#[derive(Clone, Debug, PartialEq)]
pub struct CreaseLine {
    /// Start point (mm).
    pub a: Vec2,
    /// End point (mm).
    pub b: Vec2,
    /// Fold type.
    pub kind: LineKind,
    /// Positions along the line (0 = a, 1 = b, by length) of vertices where three or more
    /// creases or cuts meet, ends included when they qualify.
    pub junctions: Vec<f64>,
    /// The smooth curve from `a` to `b` (back to `a` if closed) that a curved crease's
    /// chords stand for; `None` for a straight line.
    pub curve: Option<SmoothCurve>,
}

impl CreaseLine {
    /// Length in mm (along the curve for a curved line).
    pub fn length(&self) -> f64 {
        match &self.curve {
            Some(c) => c.length(),
            None => (self.b - self.a).norm(),
        }
    }

    /// The line with `f` applied to it (a similarity: the sheet's placement).
    pub fn mapped(&self, f: impl Fn(Vec2) -> Vec2) -> CreaseLine {
        CreaseLine {
            a: f(self.a),
            b: f(self.b),
            curve: self.curve.as_ref().map(|c| c.mapped(&f)),
            ..self.clone()
        }
    }

    /// Points along it: its ends if straight, else chords within [`FLATTEN_MM`] of the
    /// curve (for drawings that take only lines).
    pub fn polyline(&self) -> Vec<Vec2> {
        match &self.curve {
            Some(c) => {
                let mut points = vec![self.a];
                for piece in c.pieces() {
                    points.extend(piece.flatten(FLATTEN_MM).into_iter().skip(1));
                }
                points
            }
            None => vec![self.a, self.b],
        }
    }
}

/// Merges the mesh's edges, laid out at `flat`, into lines per kind: in a pattern with
/// curved creases each curved crease chain is one smooth curve (`curved_lines`); every
/// other run of edges of one kind that goes on straight through its vertices is one
/// straight line.
pub fn crease_lines(mesh: &Mesh, flat: &[Vec2]) -> Vec<CreaseLine> {
    let edges = mesh.edges();
    let curved = crate::constraints::has_curved_creases(mesh);
    let kinds = LineKind::of_mesh_given(mesh, curved);
    // Creases and cuts meeting at each vertex (flat lines are not scored, so they do not
    // weaken the paper and do not count).
    let mut degree = vec![0usize; flat.len()];
    for (e, &k) in edges.iter().zip(&kinds) {
        if k != LineKind::Flat {
            degree[e.vertices[0]] += 1;
            degree[e.vertices[1]] += 1;
        }
    }
    let mut used = vec![false; edges.len()];
    let mut lines = if curved {
        curved_lines(mesh, flat, &degree, &mut used)
    } else {
        Vec::new()
    };
    lines.extend(straight_lines(mesh, flat, &kinds, &degree, &mut used));
    drop_second_sides(lines)
}

/// Every edge not `used` yet, merged with its neighbours of the same kind into straight
/// lines: from each edge, the walk goes on through a vertex while exactly one edge of the
/// kind continues straight there. Junctions are the vertices of `degree` 3 or more.
fn straight_lines(
    mesh: &Mesh,
    flat: &[Vec2],
    kinds: &[LineKind],
    degree: &[usize],
    used: &mut [bool],
) -> Vec<CreaseLine> {
    let edges = mesh.edges();
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
            curve: None,
        });
    }
    lines
}

/// One curved crease of a pattern: its edges in order along it and the smooth curve
/// through its vertices (at the positions it was found at).
#[derive(Clone, Debug)]
pub struct SmoothCrease {
    /// Its vertices in order (a closed one does not repeat its first).
    pub vertices: Vec<usize>,
    /// Its edges in order.
    pub edges: Vec<usize>,
    /// Its fold type.
    pub kind: LineKind,
    /// The curve.
    pub curve: SmoothCurve,
}

/// The curved creases of a pattern that has them ([`crate::constraints::has_curved_creases`]),
/// laid out at `flat`: crease chains broken at corners and changes of fold type
/// ([`curve_runs`]), each with the smooth curve through its vertices. What `fab` scores
/// as curves and the studio draws as curves.
pub fn smooth_creases(mesh: &Mesh, flat: &[Vec2]) -> Vec<SmoothCrease> {
    if !crate::constraints::has_curved_creases(mesh) {
        return Vec::new();
    }
    curves_of(mesh, flat)
}

/// The smooth creases of a mesh known to have curved creases.
fn curves_of(mesh: &Mesh, flat: &[Vec2]) -> Vec<SmoothCrease> {
    curve_runs(mesh, flat)
        .into_iter()
        .map(|run| {
            let edges = run_edges(mesh, &run);
            let points = run.vertices.iter().map(|&i| flat[i]).collect();
            SmoothCrease {
                kind: LineKind::of_edge(&mesh.edges()[edges[0]]),
                curve: SmoothCurve::through(points, run.closed),
                vertices: run.vertices,
                edges,
            }
        })
        .collect()
}

/// The lines of [`smooth_creases`] of a mesh known to have curved creases, and of its
/// outline's curved stretches ([`boundary_runs`]); their edges are marked `used`.
fn curved_lines(
    mesh: &Mesh,
    flat: &[Vec2],
    degree: &[usize],
    used: &mut [bool],
) -> Vec<CreaseLine> {
    // The outline's curved stretches too: a rim cut as its chords leaves corners beside
    // smooth creases, and the margin between them would swell and shrink.
    let rims = boundary_runs(mesh, flat).into_iter().map(|run| {
        let edges = run_edges(mesh, &run);
        let points = run.vertices.iter().map(|&i| flat[i]).collect();
        SmoothCrease {
            kind: LineKind::Cut,
            curve: SmoothCurve::through(points, run.closed),
            vertices: run.vertices,
            edges,
        }
    });
    curves_of(mesh, flat)
        .into_iter()
        .chain(rims)
        .map(|crease| {
            for &e in &crease.edges {
                used[e] = true;
            }
            let v = &crease.vertices;
            let len = crease.curve.length();
            let junctions = v
                .iter()
                .zip(crease.curve.knots())
                .filter(|(&i, _)| degree[i] >= 3)
                .map(|(_, s)| s / len)
                .collect();
            CreaseLine {
                a: flat[v[0]],
                b: flat[if crease.curve.closed() {
                    v[0]
                } else {
                    v[v.len() - 1]
                }],
                kind: crease.kind,
                junctions,
                curve: Some(crease.curve),
            }
        })
        .collect()
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
