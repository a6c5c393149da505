//! The fit's Gauss–Newton steps: the motion in the null space of the conditions (eq. 10)
//! that best lowers the fit's energy, to first order in each of its terms.
//!
//! The energy is Σ_g d_g² + w_l Σ_e (l_e − l̄_e)² + w_s Σ_(g,h) (|p_g − p_h| − r̄_gh)²:
//! each surface point's distance to the target, and the preferences for the starting
//! edge lengths and distances between neighbouring points ([`super::Fitter`]'s springs,
//! at their current softness). The fit's pull is a gradient step on it (each vertex
//! asked for its share of its groups' gaps). Where the conditions refuse nearly all of
//! that pull, the part they let through is small and the design creeps for thousands of
//! steps along directions whose pull is weak: a waterbomb onto a saddle was 5.46 mm away
//! after 182 steps and 3.76 mm after 4,000. A Gauss–Newton step weighs each direction by
//! how much it changes the terms, so it goes the whole way along the weak ones at once:
//! the same waterbomb reaches 0.99 mm after 337 steps. Damped as Levenberg and Marquardt
//! do, a step that does not lower the energy is undone and the next is shorter.

use super::Measure;
use crate::mesh::Vec3;
use crate::solver::{Solver, SolverError};
use crate::surface::TriSurface;

/// Conjugate-gradient iterations of one step at most.
const MAX_ITERATIONS: usize = 200;

/// The relative residual at which the conjugate gradients stop.
const CG_TOLERANCE: f64 = 1e-6;

/// One term of the energy, linearised: weight × (value + Σ coefficient · dx_v)².
struct Row {
    weight: f64,
    value: f64,
    terms: Vec<(usize, Vec3)>,
}

impl Row {
    /// ∂r · dx.
    fn apply(&self, dx: &[Vec3]) -> f64 {
        self.terms.iter().map(|(v, c)| c.dot(&dx[*v])).sum()
    }
    /// out += s ∂rᵀ.
    fn add_transpose(&self, s: f64, out: &mut [Vec3]) {
        self.terms.iter().for_each(|(v, c)| out[*v] += c * s);
    }
}

/// What the fit prefers besides the target: its starting lengths (the springs of
/// [`super::Fitter`]'s wish, at their current softness).
pub struct Preferences<'a> {
    /// Each edge's starting length.
    pub rest: &'a [f64],
    /// Neighbouring groups and their points' starting distance.
    pub neighbours: &'a [(usize, usize, f64)],
    /// Weight of the edge lengths.
    pub lengths: f64,
    /// Weight of the neighbouring points' distances.
    pub size: f64,
}

/// The damping a Gauss–Newton phase starts with, relative to the mean diagonal of the
/// normal matrix.
pub const INITIAL_DAMPING: f64 = 1e-2;

/// The damping at which a Gauss–Newton phase gives up: its steps have shrunk to nothing
/// and still do not lower the energy.
pub const MAX_DAMPING: f64 = 1e4;

/// The damping never falls below this (it halves after every step that lowers the
/// energy): the mean diagonal times it keeps the normal matrix positive definite.
const MIN_DAMPING: f64 = 1e-8;

/// The damping after a step that lowered the energy (`better`) or did not.
pub fn next_damping(damping: f64, better: bool) -> f64 {
    if better {
        (damping * 0.5).max(MIN_DAMPING)
    } else {
        damping * 4.0
    }
}

/// Adds the terms of `sign` × `direction` · (the mean motion of `group`).
fn mean_terms(group: &[usize], direction: Vec3, sign: f64, terms: &mut Vec<(usize, Vec3)>) {
    let share = direction * (sign / group.len() as f64);
    terms.extend(group.iter().map(|&v| (v, share)));
}

/// The energy's terms at the solver's positions: each surface point's distance to the
/// target, each edge's change of length, each pair of neighbouring points' change of
/// distance.
fn rows(
    solver: &Solver,
    groups: &[Vec<usize>],
    m: &Measure,
    target: &TriSurface,
    keep: &Preferences,
) -> Vec<Row> {
    let x = solver.positions();
    let mut rows = Vec::new();
    for (g, (p, q)) in groups.iter().zip(m.points.iter().zip(&m.nearest)) {
        let d = p - q;
        let l = d.norm();
        let n = if l > 1e-12 {
            d / l
        } else {
            target.normal(target.closest(*p).triangle)
        };
        let mut terms = Vec::new();
        mean_terms(g, n, 1.0, &mut terms);
        rows.push(Row {
            weight: 1.0,
            value: l,
            terms,
        });
    }
    for (e, &rest) in solver.mesh().edges().iter().zip(keep.rest) {
        let [a, b] = e.vertices;
        let d = x[a] - x[b];
        let l = d.norm();
        if l > 0.0 && keep.lengths > 0.0 {
            let u = d / l;
            rows.push(Row {
                weight: keep.lengths,
                value: l - rest,
                terms: vec![(a, u), (b, -u)],
            });
        }
    }
    for &(g, h, rest) in keep.neighbours {
        let d = m.points[g] - m.points[h];
        let l = d.norm();
        if l > 0.0 && keep.size > 0.0 {
            let u = d / l;
            let mut terms = Vec::new();
            mean_terms(&groups[g], u, 1.0, &mut terms);
            mean_terms(&groups[h], u, -1.0, &mut terms);
            rows.push(Row {
                weight: keep.size,
                value: l - rest,
                terms,
            });
        }
    }
    rows
}

/// μ of [`motion`]: `damping` times the mean diagonal entry of the normal matrix
/// Σ w ∂rᵀ∂r over `vertices` (so the damping is relative to the terms' own scale).
fn damping_weight(rows: &[Row], vertices: usize, damping: f64) -> f64 {
    // Summed vertex by vertex: the fit's path depends on μ to the last bit.
    let mut diag = vec![0.0; vertices];
    for r in rows {
        r.terms
            .iter()
            .for_each(|(v, c)| diag[*v] += r.weight * c.norm_squared());
    }
    damping * diag.iter().sum::<f64>() / vertices.max(1) as f64
}

/// The fit's energy Σ w r² at the solver's positions (`m` measured there).
pub fn energy(
    solver: &Solver,
    groups: &[Vec<usize>],
    m: &Measure,
    target: &TriSurface,
    keep: &Preferences,
) -> f64 {
    rows(solver, groups, m, target, keep)
        .iter()
        .map(|r| r.weight * r.value * r.value)
        .sum()
}

/// The Levenberg–Marquardt step dx minimising Σ w (r + ∂r dx)² + μ |dx|² over the null
/// space of the conditions, for the fit's energy: each group's distance to the target,
/// and the preferences for lengths. Solved by conjugate gradients projected onto the null
/// space (each iteration one projection through one factor).
pub fn motion(
    solver: &mut Solver,
    groups: &[Vec<usize>],
    m: &Measure,
    target: &TriSurface,
    keep: &Preferences,
    damping: f64,
) -> Result<Vec<Vec3>, SolverError> {
    let rows = rows(solver, groups, m, target, keep);
    let vertices = solver.positions().len();
    let mu = damping_weight(&rows, vertices, damping);
    let h = |p: &[Vec3]| -> Vec<Vec3> {
        let mut out: Vec<Vec3> = p.iter().map(|q| q * mu).collect();
        for r in &rows {
            r.add_transpose(r.weight * r.apply(p), &mut out);
        }
        out
    };
    let dot = |a: &[Vec3], b: &[Vec3]| a.iter().zip(b).map(|(x, y)| x.dot(y)).sum::<f64>();
    let mut b = vec![Vec3::zeros(); vertices];
    for r in &rows {
        r.add_transpose(-r.weight * r.value, &mut b);
    }
    let mut r = solver.null_space_step(&b)?;
    let mut dx = vec![Vec3::zeros(); vertices];
    let mut p = r.clone();
    let mut rr = dot(&r, &r);
    let stop = rr * CG_TOLERANCE * CG_TOLERANCE;
    for _ in 0..MAX_ITERATIONS {
        if rr <= stop {
            break;
        }
        let q = solver.null_space_step_reusing(&h(&p))?;
        let pq = dot(&p, &q);
        if pq <= 0.0 {
            break;
        }
        let alpha = rr / pq;
        dx.iter_mut().zip(&p).for_each(|(xi, pi)| *xi += pi * alpha);
        r.iter_mut().zip(&q).for_each(|(ri, qi)| *ri -= qi * alpha);
        let rr_new = dot(&r, &r);
        let beta = rr_new / rr;
        rr = rr_new;
        p.iter_mut()
            .zip(&r)
            .for_each(|(pi, ri)| *pi = ri + *pi * beta);
    }
    Ok(dx)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::{measure, surface_groups, SurfaceChoice};
    use crate::generate::{generate, Params, PatternKind};
    use crate::random::Rng;
    use crate::solver::{Mode, Options};
    use crate::surface::shapes::Shape;

    /// What a folded 3 × 3 Miura-ori in design mode, 5 mm above a saddle, is fitted
    /// with: its groups, the saddle, and preferences for lengths 10% shorter than its own
    /// (so every term of the energy is non-zero).
    struct Scene {
        groups: Vec<Vec<usize>>,
        target: TriSurface,
        rest: Vec<f64>,
        neighbours: Vec<(usize, usize, f64)>,
    }

    impl Scene {
        fn keep(&self) -> Preferences<'_> {
            Preferences {
                rest: &self.rest,
                neighbours: &self.neighbours,
                lengths: 0.3,
                size: 0.7,
            }
        }
    }

    /// The Miura-ori's solver and its [`Scene`].
    fn setting() -> (Solver, Scene) {
        let mut mesh = generate(&Params::square(PatternKind::Miura, 3, 20.0)).unwrap();
        let lifted: Vec<Vec3> = mesh
            .positions()
            .iter()
            .map(|p| p + Vec3::new(0.0, 0.0, 5.0))
            .collect();
        mesh.set_positions(lifted);
        let set = Mode::Design.conditions(None, &mesh);
        let solver = Solver::new(mesh, set, &[], Options::default()).unwrap();
        let target = Shape::Saddle { depth: 20.0 }.surface(120.0, 24).unwrap();
        let groups = surface_groups(solver.mesh(), SurfaceChoice::Mid);
        let x = solver.positions();
        let rest = solver
            .mesh()
            .edges()
            .iter()
            .map(|e| 0.9 * (x[e.vertices[0]] - x[e.vertices[1]]).norm())
            .collect();
        let m = measure(x, &groups, &target);
        let last = groups.len() - 1;
        let neighbours = vec![(0, last, 0.9 * (m.points[0] - m.points[last]).norm())];
        let scene = Scene {
            groups,
            target,
            rest,
            neighbours,
        };
        (solver, scene)
    }

    fn random_motion(rng: &mut Rng, n: usize) -> Vec<Vec3> {
        (0..n)
            .map(|_| {
                Vec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                )
            })
            .collect()
    }

    /// The linearised model Σ w (r + ∂r dx)² + μ |dx|².
    fn model(rows: &[Row], mu: f64, dx: &[Vec3]) -> f64 {
        let fit: f64 = rows
            .iter()
            .map(|r| r.weight * (r.value + r.apply(dx)).powi(2))
            .sum();
        fit + mu * dx.iter().map(|d| d.norm_squared()).sum::<f64>()
    }

    #[test]
    fn the_energy_terms_derivatives_match_central_differences() {
        let (mut solver, scene) = setting();
        let (groups, target, keep) = (&scene.groups, &scene.target, scene.keep());
        let x0 = solver.positions().to_vec();
        let m = measure(&x0, groups, target);
        let rows = rows(&solver, groups, &m, target, &keep);
        let mut rng = Rng::new(7);
        for _ in 0..5 {
            let v = random_motion(&mut rng, x0.len());
            let predicted: f64 = rows
                .iter()
                .map(|r| 2.0 * r.weight * r.value * r.apply(&v))
                .sum();
            let h = 1e-5;
            let mut at = |t: f64| {
                solver.restore(x0.iter().zip(&v).map(|(p, d)| p + d * t).collect());
                let m = measure(solver.positions(), groups, target);
                energy(&solver, groups, &m, target, &keep)
            };
            let measured = (at(h) - at(-h)) / (2.0 * h);
            assert!(
                (measured - predicted).abs() <= 1e-6 * predicted.abs().max(1.0),
                "{measured} against {predicted}"
            );
        }
    }

    #[test]
    fn the_step_minimises_the_linearised_energy_over_the_null_space() {
        let (mut solver, scene) = setting();
        let (groups, target, keep) = (&scene.groups, &scene.target, scene.keep());
        let m = measure(solver.positions(), groups, target);
        let damping = 1e-3;
        let dx = motion(&mut solver, groups, &m, target, &keep, damping).unwrap();
        let rows = rows(&solver, groups, &m, target, &keep);
        let n = dx.len();
        let mu = damping_weight(&rows, n, damping);
        // In the null space: the projection leaves it as it is.
        let projected = solver.null_space_step(&dx).unwrap();
        let size = dx.iter().map(|d| d.norm()).fold(0.0, f64::max);
        assert!(size > 1e-3, "the step moves: {size}");
        let off = dx
            .iter()
            .zip(&projected)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        assert!(off <= 1e-8 * size, "{off} off the null space");
        // Lower than the start, and than every valid motion near it.
        let best = model(&rows, mu, &dx);
        assert!(best < model(&rows, mu, &vec![Vec3::zeros(); n]));
        let mut rng = Rng::new(11);
        for _ in 0..20 {
            let u = solver.null_space_step(&random_motion(&mut rng, n)).unwrap();
            for t in [1e-2, -1e-2, 1e-1, -1e-1] {
                let moved: Vec<Vec3> = dx.iter().zip(&u).map(|(a, b)| a + b * t).collect();
                assert!(model(&rows, mu, &moved) >= best * (1.0 - 1e-9), "t = {t}");
            }
        }
    }
}
