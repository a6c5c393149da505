//! Crease chains: curved creases as they are drawn, straight creases joined end to end
//! through vertices where exactly two creases meet (issue 30). The smoothness conditions
//! walk along them (`constraints`), fabrication scores each curved one as one smooth curve
//! (`fab::lines`) and FOLD files name them (`crease:curves`).

use super::{Mesh, Vec2};

/// One crease chain: creases (mountain or valley) joined end to end through interior
/// vertices where exactly two creases meet, which is how a curved crease is drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct CreaseChain {
    /// Its vertices in order (a closed chain does not repeat its first).
    pub vertices: Vec<usize>,
    /// Whether it closes on itself (a circle drawn inside the sheet).
    pub closed: bool,
}

impl CreaseChain {
    /// The chain's vertices at which it turns, each with the one before and after:
    /// every vertex of a closed chain, the inner ones of an open chain.
    pub fn turns(&self) -> Vec<[usize; 3]> {
        let v = &self.vertices;
        let n = v.len();
        if self.closed {
            (0..n)
                .map(|i| [v[(i + n - 1) % n], v[i], v[(i + 1) % n]])
                .collect()
        } else {
            v.windows(3).map(|w| [w[0], w[1], w[2]]).collect()
        }
    }
}

/// The creases of `mesh` joined into chains: maximal runs of mountain and valley edges
/// through interior vertices with exactly two of them. Chains of one edge are left out
/// (nothing turns there).
pub fn crease_chains(mesh: &Mesh) -> Vec<CreaseChain> {
    let topo = mesh.topology();
    let folded = |e: usize| mesh.edges()[e].assignment.is_folded();
    // Per vertex, its folded spokes; a vertex passes a chain on when it is interior and
    // has exactly two.
    let creases_at: Vec<Vec<usize>> = topo
        .fans
        .iter()
        .map(|fan| fan.spokes.iter().copied().filter(|&e| folded(e)).collect())
        .collect();
    let passes = |v: usize| !topo.fans[v].boundary && creases_at[v].len() == 2;
    let other_end = |e: usize, v: usize| {
        let [a, b] = mesh.edges()[e].vertices;
        if a == v {
            b
        } else {
            a
        }
    };
    let mut used = vec![false; mesh.edges().len()];
    let mut chains = Vec::new();
    // Walks from `start` along crease `e` while the vertices pass the chain on.
    let walk = |start: usize, first: usize, used: &mut Vec<bool>| {
        let mut vertices = vec![start];
        let (mut v, mut e) = (start, first);
        loop {
            used[e] = true;
            v = other_end(e, v);
            if v == start {
                return CreaseChain {
                    vertices,
                    closed: true,
                };
            }
            vertices.push(v);
            if !passes(v) {
                break;
            }
            let [a, b] = [creases_at[v][0], creases_at[v][1]];
            e = if a == e { b } else { a };
            if used[e] {
                break;
            }
        }
        CreaseChain {
            vertices,
            closed: false,
        }
    };
    // Open chains from their ends, then what is left: closed loops.
    for v in (0..mesh.vertex_count()).filter(|&v| !passes(v)) {
        for &e in &creases_at[v] {
            if !used[e] {
                chains.push(walk(v, e, &mut used));
            }
        }
    }
    for v in (0..mesh.vertex_count()).filter(|&v| passes(v)) {
        let e = creases_at[v][0];
        if !used[e] {
            chains.push(walk(v, e, &mut used));
        }
    }
    chains.retain(|c| c.vertices.len() >= 3);
    chains
}

/// A turn sharper than this (radians, 30°) at a chain vertex is a corner, not a sample of
/// a smooth curve: a curved crease is broken there.
pub const CORNER: f64 = std::f64::consts::PI / 6.0;

/// The unsigned turn (radians) at `p` of a polyline coming from `a` and going on to `b`.
pub fn turn(a: Vec2, p: Vec2, b: Vec2) -> f64 {
    let (u, w) = ((p - a).normalize(), (b - p).normalize());
    (u.x * w.y - u.y * w.x).atan2(u.dot(&w)).abs()
}

/// The curved creases of `mesh` laid out at `flat`: its crease chains broken where the
/// fold type changes or the chain turns by more than [`CORNER`], those pieces with three
/// or more turns that turn at all (a closed chain with no break stays closed).
pub fn curve_runs(mesh: &Mesh, flat: &[Vec2]) -> Vec<CreaseChain> {
    let topo = mesh.topology();
    let edge = |a: usize, b: usize| topo.edge_between(a, b).expect("a chain's step is an edge");
    let kind = |a: usize, b: usize| mesh.edges()[edge(a, b)].assignment;
    let mut runs = Vec::new();
    for chain in crease_chains(mesh) {
        let mut v = chain.vertices.clone();
        let n = v.len();
        let breaks = |i: usize, v: &[usize]| {
            let m = v.len();
            let (a, p, b) = (v[(i + m - 1) % m], v[i], v[(i + 1) % m]);
            kind(a, p) != kind(p, b) || turn(flat[a], flat[p], flat[b]) > CORNER
        };
        // A closed chain with a break is opened there; else it stays one closed curve.
        let mut closed = chain.closed;
        if closed {
            if let Some(i) = (0..n).find(|&i| breaks(i, &v)) {
                v.rotate_left(i);
                v.push(v[0]);
                closed = false;
            }
        }
        runs.extend(curved_pieces(v, closed, flat, breaks));
    }
    runs
}

/// `v` (a chain, `closed` when it has no break) cut at the vertices `breaks` names, the
/// pieces with three or more turns that turn at all.
fn curved_pieces(
    v: Vec<usize>,
    closed: bool,
    flat: &[Vec2],
    breaks: impl Fn(usize, &[usize]) -> bool,
) -> Vec<CreaseChain> {
    let mut pieces: Vec<Vec<usize>> = vec![vec![v[0]]];
    for i in 1..v.len() {
        pieces.last_mut().expect("a piece").push(v[i]);
        if !closed && i + 1 < v.len() && breaks(i, &v) {
            pieces.push(vec![v[i]]);
        }
    }
    pieces
        .into_iter()
        .map(|vertices| CreaseChain { vertices, closed })
        .filter(|run| {
            // As for the smoothness conditions: a run of fewer than three turns has no
            // second difference, so nothing says it samples a curve (Resch's pattern has
            // two-edge runs that turn once at a tuck).
            let turns = run.turns();
            let curved = turns
                .iter()
                .any(|&[a, p, b]| turn(flat[a], flat[p], flat[b]) > 1e-6);
            turns.len() >= 3 && curved
        })
        .collect()
}

/// The curved stretches of the paper's outline laid out at `flat`: each boundary loop
/// broken where it turns by more than [`CORNER`], the pieces with three or more turns
/// that turn at all (a loop with no corner stays closed). The concentric pattern's rims
/// are such stretches: cut as their chords they left corners beside smooth creases.
pub fn boundary_runs(mesh: &Mesh, flat: &[Vec2]) -> Vec<CreaseChain> {
    let topo = mesh.topology();
    let mut runs = Vec::new();
    for boundary in &topo.boundary_loops {
        let n = boundary.len();
        if n < 3 {
            continue;
        }
        let mut v = boundary.clone();
        let breaks = |i: usize, v: &[usize]| {
            let m = v.len();
            let (a, p, b) = (v[(i + m - 1) % m], v[i], v[(i + 1) % m]);
            turn(flat[a], flat[p], flat[b]) > CORNER
        };
        let mut closed = true;
        if let Some(i) = (0..n).find(|&i| breaks(i, &v)) {
            v.rotate_left(i);
            v.push(v[0]);
            closed = false;
        }
        runs.extend(curved_pieces(v, closed, flat, breaks));
    }
    runs
}

/// The edges of a run in order along it (a closed run's last one back to its start).
pub fn run_edges(mesh: &Mesh, run: &CreaseChain) -> Vec<usize> {
    let topo = mesh.topology();
    let v = &run.vertices;
    let steps = if run.closed { v.len() } else { v.len() - 1 };
    (0..steps)
        .map(|i| {
            topo.edge_between(v[i], v[(i + 1) % v.len()])
                .expect("a chain's step is an edge")
        })
        .collect()
}
