//! Parametric generators for the paper's six starting patterns (§6) and the curved-crease
//! patterns of its future work (§6.6, §7). Each writes the exact crease pattern; Miura-ori,
//! Yoshimura, plane, curved strip, arc, concentric and pleat also write an exact partially
//! folded 3D state (closed form) for a fold amount in [0, 1].

mod arc;
mod lattice;
mod pleat;
mod resch;
mod tube;

pub use arc::ARC_TARGET;
pub use tube::KRESLING_MAX_FOLD;

use crate::mesh::{Assignment, Mesh, MeshError, MeshParts, Vec2, Vec3};
use lattice::{build, rows_zipper};
use std::f64::consts::PI;

/// The paper's starting patterns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatternKind {
    /// Miura-ori (§6.2): parallelograms, flat-foldable, rigid-foldable.
    Miura,
    /// Waterbomb tessellation (§6.1): right isosceles triangles, degree-6 vertices.
    Waterbomb,
    /// Yoshimura (§6.3): diamond pattern folding to a cylinder.
    Yoshimura,
    /// Resch's triangular pattern (§6.4): tiles with hidden three-fold tucks.
    Resch,
    /// Plane (§6.5): a regular triangular grid with no creases.
    Plane,
    /// Curved-fold strip (§6.6): a rectangular grid of planar-quad strips.
    Curved,
    /// One curved crease (§6.6, §7): a circular arc across an annular strip, folded by
    /// the mirror construction, rulings along the folded cones' generators.
    Arc,
    /// Concentric circular creases, mountains and valleys alternating: the mirror
    /// construction repeated ring by ring.
    Concentric,
    /// A curved pleat: parallel sinusoidal creases, mountains and valleys alternating, a
    /// ruled strip reflected again and again.
    Pleat,
    /// The waterbomb closed into a tube (§6.1's stent graft, §7): `nx` cells round.
    WaterbombTube,
    /// Yoshimura closed into a tube (§6.3, §7): rings of `nx` diamonds.
    YoshimuraTube,
    /// Kresling's twisted tube: a parallelogram lattice, each cell cut by a diagonal,
    /// whose rings turn as it folds.
    Kresling,
}

impl PatternKind {
    /// Every kind, in the order of the paper.
    pub const ALL: [PatternKind; 12] = [
        PatternKind::Waterbomb,
        PatternKind::Miura,
        PatternKind::Yoshimura,
        PatternKind::Resch,
        PatternKind::Plane,
        PatternKind::Curved,
        PatternKind::Arc,
        PatternKind::Concentric,
        PatternKind::Pleat,
        PatternKind::WaterbombTube,
        PatternKind::YoshimuraTube,
        PatternKind::Kresling,
    ];

    /// The name used on the command line and for files in `patterns/`.
    pub fn name(self) -> &'static str {
        match self {
            PatternKind::Miura => "miura",
            PatternKind::Waterbomb => "waterbomb",
            PatternKind::Yoshimura => "yoshimura",
            PatternKind::Resch => "resch",
            PatternKind::Plane => "plane",
            PatternKind::Curved => "curved",
            PatternKind::Arc => "arc",
            PatternKind::Concentric => "concentric",
            PatternKind::Pleat => "pleat",
            PatternKind::WaterbombTube => "waterbomb-tube",
            PatternKind::YoshimuraTube => "yoshimura-tube",
            PatternKind::Kresling => "kresling",
        }
    }

    /// Looks a kind up by name.
    pub fn from_name(name: &str) -> Option<PatternKind> {
        PatternKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Looks a kind up by name; the refusal names every pattern there is.
    pub fn parse(name: &str) -> Result<PatternKind, String> {
        PatternKind::from_name(name).ok_or_else(|| {
            let names: Vec<&str> = PatternKind::ALL.iter().map(|k| k.name()).collect();
            format!(
                "unknown pattern \"{}\" (choose one of: {})",
                crate::limits::short_text(name),
                names.join(", ")
            )
        })
    }

    /// Whether the generator has a closed-form 3D state that a fold amount chooses.
    pub fn has_closed_form_3d(self) -> bool {
        !matches!(
            self,
            PatternKind::Waterbomb
                | PatternKind::Resch
                | PatternKind::WaterbombTube
                | PatternKind::YoshimuraTube
        )
    }

    /// Whether the pattern is a tube (§7): generated closed, with no flat state of its
    /// own (its strip is the tube cut open along its seam).
    pub fn is_tube(self) -> bool {
        matches!(
            self,
            PatternKind::WaterbombTube | PatternKind::YoshimuraTube | PatternKind::Kresling
        )
    }
}

/// Generator parameters. Lengths in millimetres.
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    /// Which pattern.
    pub kind: PatternKind,
    /// Cells across.
    pub nx: usize,
    /// Cells along.
    pub ny: usize,
    /// Cell edge length (mm).
    pub size: f64,
    /// Miura parallelogram angle γ in degrees (between the straight crease and the zigzag).
    pub angle_deg: f64,
    /// Fold amount in [0, 1] for the closed-form 3D state: the creases reach this fraction
    /// of their target angles on average, as with `crease fold --amount`; `None` writes the
    /// flat pattern only. 0 is flat, 1 is flat-folded (for the plane, which has no
    /// creases, 1 is a half turn of bending).
    pub fold: Option<f64>,
    /// Twist allowance α of triangulation creases (§2.4).
    pub alpha: f64,
}

impl Params {
    /// The defaults of `kind` on a square grid of `cells` × `cells` cells of `size` mm
    /// (benchmarks and scaling tests).
    pub fn square(kind: PatternKind, cells: usize, size: f64) -> Params {
        Params {
            nx: cells,
            ny: cells,
            size,
            ..Params::defaults(kind)
        }
    }

    /// The defaults used for the files in `patterns/`.
    pub fn defaults(kind: PatternKind) -> Params {
        Params {
            kind,
            nx: 8,
            ny: 8,
            size: 20.0,
            angle_deg: 60.0,
            fold: match kind {
                // A Yoshimura folds tightly: creases at 6.5% of their targets already curl
                // 8 cells into an arch.
                PatternKind::Yoshimura => Some(0.065),
                PatternKind::Miura => Some(0.3),
                // Waterbomb and Yoshimura tubes close in one state, Kresling's strip is
                // made for the amount it is generated at.
                _ => kind.has_closed_form_3d().then_some(0.5),
            },
            alpha: 0.0,
        }
    }
}

/// Why a pattern cannot be generated.
#[derive(Debug, thiserror::Error)]
pub enum GenerateError {
    /// A parameter outside its range ([`crate::limits`]).
    #[error(transparent)]
    Range(#[from] crate::limits::OutOfRange),
    /// Parameters that do not make the pattern together.
    #[error("{0}")]
    BadParameter(String),
    /// The generated mesh failed validation (a bug, reported rather than hidden).
    #[error("generated mesh is invalid: {0}")]
    Mesh(#[from] MeshError),
}

/// Generates a pattern.
pub fn generate(p: &Params) -> Result<Mesh, GenerateError> {
    let bad = |m: String| Err(GenerateError::BadParameter(m));
    check_ranges(p)?;
    if p.fold.is_some() {
        // Resch's closed form is its fully folded state; its generator checks the amount.
        if !p.kind.has_closed_form_3d() && p.kind != PatternKind::Resch && !p.kind.is_tube() {
            return bad(format!(
                "{} has no closed-form folded state; generate it flat and fold it with the solver",
                p.kind.name()
            ));
        }
    }
    crate::limits::ALPHA.check("alpha", p.alpha)?;
    let mut mesh = match p.kind {
        PatternKind::Miura => miura(p)?,
        PatternKind::Waterbomb => waterbomb(p)?,
        PatternKind::Yoshimura => yoshimura(p)?,
        PatternKind::Resch => resch::resch(p)?,
        PatternKind::Plane => plane(p)?,
        PatternKind::Curved => curved(p)?,
        PatternKind::Arc => arc::arc(p)?,
        PatternKind::Concentric => arc::concentric(p)?,
        PatternKind::Pleat => pleat::pleat(p)?,
        PatternKind::WaterbombTube | PatternKind::YoshimuraTube | PatternKind::Kresling => {
            tube::tube(p)?
        }
    };
    mesh.title = format!("{} {}x{}", p.kind.name(), p.nx, p.ny);
    // Remeshing does not yet carry a tube's seam across a collapse.
    mesh.lock_topology = p.kind == PatternKind::Resch || p.kind.is_tube();
    Ok(mesh)
}

/// Every parameter in its range ([`crate::limits`]), before anything is sized from it:
/// cells along each side and in all, the cell size and the extent it gives, the angle
/// and the fold amount.
fn check_ranges(p: &Params) -> Result<(), GenerateError> {
    use crate::limits::{CELLS, CELLS_IN_ALL, FRACTION, LENGTH, MIURA_ANGLE, PATTERN_EXTENT};
    CELLS.check_count("nx", p.nx as u64)?;
    CELLS.check_count("ny", p.ny as u64)?;
    CELLS_IN_ALL.check_count("nx × ny", p.nx as u64 * p.ny as u64)?;
    LENGTH.check("size", p.size)?;
    PATTERN_EXTENT.check("size × cells", p.size * p.nx.max(p.ny) as f64)?;
    MIURA_ANGLE.check("angle", p.angle_deg)?;
    if let Some(t) = p.fold {
        FRACTION.check("fold", t)?;
    }
    Ok(())
}

/// Sign of the fold angle decides mountain or valley for patterns with a closed form: the
/// assignment is read off the geometry at a mid fold, so it cannot disagree with it.
pub(crate) fn assign_by_fold(
    parts: &mut MeshParts,
    folded_mid: Vec<Vec3>,
) -> Result<(), GenerateError> {
    let probe = Mesh::new(MeshParts {
        positions: Some(folded_mid),
        ..parts.clone()
    })?;
    let angles = crate::geometry::fold_angles(&probe);
    for (edge, (probe_edge, rho)) in parts.edges.iter_mut().zip(probe.edges().iter().zip(angles)) {
        debug_assert_eq!(edge.vertices, probe_edge.vertices);
        if edge.assignment == Assignment::Unassigned {
            let a = if rho > crate::tolerance::SAME_ANGLE_RADIANS {
                Assignment::Mountain
            } else if rho < -crate::tolerance::SAME_ANGLE_RADIANS {
                Assignment::Valley
            } else {
                Assignment::Flat
            };
            edge.assignment = a;
            edge.target = a.default_target();
            edge.fold_angle = edge.target;
        }
    }
    Ok(())
}

/// [`assign_by_fold`], then the twist allowance `alpha` on the creases it finds flat.
pub(crate) fn assign_by_fold_with_twist(
    parts: &mut MeshParts,
    folded_mid: Vec<Vec3>,
    alpha: f64,
) -> Result<(), GenerateError> {
    assign_by_fold(parts, folded_mid)?;
    for e in &mut parts.edges {
        if e.assignment == Assignment::Flat {
            e.alpha = alpha;
        }
    }
    Ok(())
}

fn miura(p: &Params) -> Result<Mesh, GenerateError> {
    let gamma = p.angle_deg.to_radians();
    if !(gamma > 0.0 && gamma < PI / 2.0) {
        return Err(GenerateError::BadParameter(format!(
            "Miura angle must be strictly between 0 and 90 degrees (got {})",
            crate::limits::short(p.angle_deg)
        )));
    }
    let (a, b) = (p.size, p.size);
    let (s, h) = (b * gamma.cos(), b * gamma.sin());
    let idx = |i: usize, j: usize| j * (p.nx + 1) + i;
    let mut flat = Vec::new();
    for j in 0..=p.ny {
        for i in 0..=p.nx {
            flat.push(Vec2::new(i as f64 * a + (j % 2) as f64 * s, j as f64 * h));
        }
    }
    // Each parallelogram is cut along its shorter diagonal.
    let mut faces = Vec::new();
    for j in 0..p.ny {
        for i in 0..p.nx {
            let q = [idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)];
            let d02 = (flat[q[2]] - flat[q[0]]).norm();
            let d13 = (flat[q[3]] - flat[q[1]]).norm();
            if d02 <= d13 {
                faces.push([q[0], q[1], q[2]]);
                faces.push([q[0], q[2], q[3]]);
            } else {
                faces.push([q[0], q[1], q[3]]);
                faces.push([q[1], q[2], q[3]]);
            }
        }
    }
    // Folded: rows zigzag in the xz-plane, columns in the xy-plane; every parallelogram
    // keeps its sides a, b and the product of its in-plane offsets ℓ·s' = a·s, so it stays
    // congruent to the flat one. φ runs from 0 (flat) to γ (flat-folded).
    let folded_at = |t: f64| -> Vec<Vec3> {
        let phi = t * gamma;
        let (l, hz) = (a * phi.cos(), a * phi.sin());
        let s2 = s / phi.cos();
        let w = (b * b - s2 * s2).max(0.0).sqrt();
        let mut out = Vec::new();
        for j in 0..=p.ny {
            for i in 0..=p.nx {
                out.push(Vec3::new(
                    i as f64 * l + (j % 2) as f64 * s2,
                    j as f64 * w,
                    (i % 2) as f64 * hz,
                ));
            }
        }
        out
    };
    finish(p, flat, faces, |t| Ok(folded_at(t)))
}

/// Flat and, when asked, folded parts; interior edges get mountain, valley or flat from
/// the sign of their fold angle at t = 0.5.
pub(crate) fn finish(
    p: &Params,
    flat: Vec<Vec2>,
    faces: Vec<[usize; 3]>,
    folded_at: impl Fn(f64) -> Result<Vec<Vec3>, GenerateError>,
) -> Result<Mesh, GenerateError> {
    finish_with(p, flat, faces, folded_at, true)
}

/// [`finish`], with the fold amount taken as the closed form's own parameter when
/// `amount_is_crease_fraction` is false (the plane, whose bends are not creases).
fn finish_with(
    p: &Params,
    flat: Vec<Vec2>,
    faces: Vec<[usize; 3]>,
    folded_at: impl Fn(f64) -> Result<Vec<Vec3>, GenerateError>,
    amount_is_crease_fraction: bool,
) -> Result<Mesh, GenerateError> {
    let mut parts = build(flat, faces, |_, _| Assignment::Unassigned, p.alpha);
    assign_by_fold_with_twist(&mut parts, folded_at(0.5)?, p.alpha)?;
    let mut mesh = Mesh::new(parts)?;
    if let Some(t) = p.fold {
        let u = if amount_is_crease_fraction {
            parameter_for_fraction(&mut mesh, t, &folded_at)?
        } else {
            t
        };
        mesh.set_positions(folded_at(u)?);
    }
    Ok(mesh)
}

/// The closed form's own parameter u (0 flat, 1 flat-folded) at which the creases reach
/// `fraction` of their targets on average, mean(ρ / target) = `fraction` — what
/// `crease fold --amount` aims for, so a fold amount means one thing everywhere. The
/// mean rises monotonically with u in every closed form, so bisection finds it; a
/// pattern without targets (the plane) takes u = `fraction` itself.
pub(crate) fn parameter_for_fraction(
    mesh: &mut Mesh,
    fraction: f64,
    folded_at: &impl Fn(f64) -> Result<Vec<Vec3>, GenerateError>,
) -> Result<f64, GenerateError> {
    let creases: Vec<(usize, f64)> = mesh
        .edges()
        .iter()
        .enumerate()
        .filter(|(_, e)| e.target != 0.0)
        .map(|(i, e)| (i, e.target))
        .collect();
    if creases.is_empty() || fraction == 0.0 || fraction == 1.0 {
        return Ok(fraction);
    }
    let mut mean_at = |u: f64| -> Result<f64, GenerateError> {
        mesh.set_positions(folded_at(u)?);
        let rho = crate::geometry::fold_angles(mesh);
        Ok(creases
            .iter()
            .map(|&(e, target)| rho[e] / target)
            .sum::<f64>()
            / creases.len() as f64)
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if mean_at(mid)? < fraction {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}

fn waterbomb(p: &Params) -> Result<Mesh, GenerateError> {
    // Lattice of points (x, y) with x + y even, in units of half the cell size; every
    // vertex is a waterbomb base: horizontal mountains, diagonal valleys (2 M + 4 V).
    let u = p.size / 2.0;
    let (w, m) = (2 * p.nx, 2 * p.ny);
    let rows: Vec<Vec<f64>> = (0..=m)
        .map(|y| {
            (0..=w)
                .filter(|&x| (x + y) % 2 == 0 || x == 0 || x == w)
                .map(|x| x as f64 * u)
                .collect()
        })
        .collect();
    let (flat, faces) = rows_zipper(&rows, u);
    let parts = build(
        flat,
        faces,
        |a, b| {
            if (a.y - b.y).abs() < 1e-9 * u {
                Assignment::Mountain
            } else {
                Assignment::Valley
            }
        },
        p.alpha,
    );
    Ok(Mesh::new(parts)?)
}

fn yoshimura(p: &Params) -> Result<Mesh, GenerateError> {
    // Rows of equal-sided diamonds: horizontal creases of length w, diagonals to the
    // half-offset neighbours in the next row.
    let (w, h) = (p.size, p.size * 3f64.sqrt() / 2.0);
    let rows: Vec<Vec<f64>> = (0..=p.ny)
        .map(|j| {
            let shift = if j % 2 == 1 { 0.5 } else { 0.0 };
            let count = if j % 2 == 1 { p.nx } else { p.nx + 1 };
            (0..count).map(|i| (i as f64 + shift) * w).collect()
        })
        .collect();
    let (flat, faces) = rows_zipper(&rows, h);
    // Folded: each row is a polygon inscribed in a circle of radius R, rows stacked along
    // the axis at spacing hz. Horizontal chords stay w; diagonals stay √((w/2)² + h²) by
    // the choice of hz. Δ (the angle per cell) runs from 0 (flat) to Δmax (flat-folded).
    let d = ((w / 2.0).powi(2) + h * h).sqrt();
    let delta_max = 4.0 * (w / (2.0 * d)).acos();
    let flat_ref = flat.clone();
    let folded_at = move |t: f64| -> Result<Vec<Vec3>, GenerateError> {
        let delta = t * delta_max;
        if delta == 0.0 {
            return Ok(flat_ref.iter().map(|q| Vec3::new(q.x, q.y, 0.0)).collect());
        }
        let r = w / (2.0 * (delta / 2.0).sin());
        let hz = (d * d - (2.0 * r * (delta / 4.0).sin()).powi(2))
            .max(0.0)
            .sqrt();
        Ok(flat_ref
            .iter()
            .map(|q| {
                let phi = q.x / w * delta;
                let row = (q.y / h).round();
                Vec3::new(r * phi.sin(), row * hz, 2.0 * r * (phi / 2.0).sin().powi(2))
            })
            .collect())
    };
    finish(p, flat, faces, folded_at)
}

fn plane(p: &Params) -> Result<Mesh, GenerateError> {
    // Regular triangular grid on a rectangle; the folded state bends it along the
    // horizontal grid lines into a polygonal cylinder (rows keep their x, each row step
    // keeps its length h), a half turn in all at fold 1.
    let (w, h) = (p.size, p.size * 3f64.sqrt() / 2.0);
    let width = p.nx as f64 * w;
    let rows: Vec<Vec<f64>> = (0..=p.ny)
        .map(|j| {
            let mut xs: Vec<f64> = if j % 2 == 1 {
                (0..p.nx).map(|i| (i as f64 + 0.5) * w).collect()
            } else {
                (0..=p.nx).map(|i| i as f64 * w).collect()
            };
            if j % 2 == 1 {
                xs.insert(0, 0.0);
                xs.push(width);
            }
            xs
        })
        .collect();
    let (flat, faces) = rows_zipper(&rows, h);
    let flat_ref = flat.clone();
    let ny = p.ny;
    let folded_at = move |t: f64| -> Result<Vec<Vec3>, GenerateError> {
        let beta = t * PI / ny as f64;
        let mut profile = vec![(0.0f64, 0.0f64)];
        for k in 0..ny {
            let (y, z) = profile[k];
            let ang = beta * (k as f64 + 0.5);
            profile.push((y + h * ang.cos(), z + h * ang.sin()));
        }
        Ok(flat_ref
            .iter()
            .map(|q| {
                let (y, z) = profile[(q.y / h).round() as usize];
                Vec3::new(q.x, y, z)
            })
            .collect())
    };
    finish_with(p, flat, faces, folded_at, false).map(|mut m| {
        // No creases in a plane: every interior line may bend either way.
        for e in m.edges_mut() {
            if !e.assignment.is_boundary() {
                e.assignment = Assignment::Unassigned;
                e.target = 0.0;
                e.fold_angle = 0.0;
            }
        }
        m
    })
}

fn curved(p: &Params) -> Result<Mesh, GenerateError> {
    // Rectangular grid: the lines across the strip (x constant) are the folds, alternating
    // mountain and valley; lines along it and the quad diagonals are rulings (target 0,
    // α = 0), so each quad stays planar. Folded: an accordion, each fold by ±t·π.
    let (w, hy) = (p.size, p.size);
    let idx = |i: usize, j: usize| j * (p.nx + 1) + i;
    let mut flat = Vec::new();
    for j in 0..=p.ny {
        for i in 0..=p.nx {
            flat.push(Vec2::new(i as f64 * w, j as f64 * hy));
        }
    }
    let mut faces = Vec::new();
    for j in 0..p.ny {
        for i in 0..p.nx {
            faces.push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)]);
            faces.push([idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]);
        }
    }
    let (nx, ny) = (p.nx, p.ny);
    let folded_at = move |t: f64| -> Result<Vec<Vec3>, GenerateError> {
        let half = t * PI / 2.0;
        let mut xz = vec![(0.0f64, 0.0f64)];
        for i in 0..nx {
            let (x, z) = xz[i];
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            xz.push((x + w * half.cos(), z + sign * w * half.sin()));
        }
        let mut out = Vec::new();
        for j in 0..=ny {
            for &(x, z) in xz.iter() {
                out.push(Vec3::new(x, j as f64 * hy, z));
            }
        }
        Ok(out)
    };
    finish(p, flat, faces, folded_at)
}
