//! Isometric unfolding of a developable 3D design to its crease pattern: triangles are laid
//! out across a spanning tree of the faces, each placed from its 3D edge lengths on the far
//! side of the edge it shares with its parent, so orientation is kept; the result is then
//! turned and moved onto the previous crease pattern when one is known.

use crate::mesh::{Mesh, SeamError, Strip, Vec2};
use std::borrow::Cow;
use std::collections::VecDeque;

/// Why a design cannot be unfolded.
#[derive(Debug, thiserror::Error)]
pub enum UnfoldError {
    /// Some faces are not reachable from the first across shared edges.
    #[error("the design has {0} separate pieces; unfold them one at a time")]
    Disconnected(usize),
    /// The flat sheet would lie over itself.
    #[error("the unfolded sheet overlaps itself: faces {0} and {1} cover the same paper")]
    Overlap(usize, usize),
    /// A face comes out mirrored (the sheet folds over itself).
    #[error("the unfolded sheet overlaps itself: face {0} is laid out mirrored")]
    Flipped(usize),
    /// A tube cannot be cut open along its seam.
    #[error(transparent)]
    Seam(#[from] SeamError),
    /// A tube has no crease pattern of its own: its strip, cut open along the seam, has.
    #[error("a tube has no crease pattern of its own: cut it open along its seam into its strip")]
    Tube,
}

/// Checks that no two faces of a flat layout cover the same paper (interiors overlapping by
/// more than `1e-9` of the layout's size), and none is mirrored.
pub fn check_overlap(faces: &[[usize; 3]], flat: &[Vec2]) -> Result<(), UnfoldError> {
    let tri = |f: [usize; 3]| [flat[f[0]], flat[f[1]], flat[f[2]]];
    let (lo, hi) = crate::mesh::bounds(flat);
    let eps = 1e-9 * (hi - lo).norm().max(1e-300);
    for (i, &f) in faces.iter().enumerate() {
        let [a, b, c] = tri(f);
        if (b - a).perp(&(c - a)) <= 0.0 {
            return Err(UnfoldError::Flipped(i));
        }
    }
    // Grid of face bounding boxes; cells about the size of an average face.
    let area: f64 = faces
        .iter()
        .map(|&f| {
            let [a, b, c] = tri(f);
            0.5 * (b - a).perp(&(c - a))
        })
        .sum();
    let mut cell = (area / faces.len() as f64).sqrt().max(1e-12) * 2.0;
    // Long slivers (a fan across a many-cornered face) each cover thousands of cells of
    // that size, and every cell is compared with every earlier face in it: coarser
    // cells until the faces cover at most a few cells each on average.
    let extent = |f: [usize; 3], cell: f64| {
        let [a, b, c] = tri(f);
        let (lo, hi) = (a.inf(&b).inf(&c), a.sup(&b).sup(&c));
        (((hi.x - lo.x) / cell).floor() + 2.0) * (((hi.y - lo.y) / cell).floor() + 2.0)
    };
    while cell < (hi - lo).norm()
        && faces.iter().map(|&f| extent(f, cell)).sum::<f64>() > 16.0 * faces.len() as f64
    {
        cell *= 2.0;
    }
    let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> =
        std::collections::HashMap::new();
    let key = |p: Vec2| {
        (
            ((p.x - lo.x) / cell).floor() as i64,
            ((p.y - lo.y) / cell).floor() as i64,
        )
    };
    for (i, &f) in faces.iter().enumerate() {
        let t = tri(f);
        let (a, b) = (
            key(t[0].inf(&t[1]).inf(&t[2])),
            key(t[0].sup(&t[1]).sup(&t[2])),
        );
        for x in a.0..=b.0 {
            for y in a.1..=b.1 {
                let list = grid.entry((x, y)).or_default();
                for &j in list.iter() {
                    if interiors_overlap(tri(faces[j]), t, eps) {
                        return Err(UnfoldError::Overlap(j, i));
                    }
                }
                list.push(i);
            }
        }
    }
    Ok(())
}

/// Separating-axis test on two counter-clockwise triangles: interiors overlap unless some
/// edge's outward normal separates them (touching within `eps` counts as separate).
fn interiors_overlap(p: [Vec2; 3], q: [Vec2; 3], eps: f64) -> bool {
    for (t, other) in [(p, q), (q, p)] {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let n = Vec2::new(b.y - a.y, a.x - b.x).normalize(); // outward for CCW
            let min_other = other
                .iter()
                .map(|v| (v - a).dot(&n))
                .fold(f64::INFINITY, f64::min);
            if min_other >= -eps {
                return false;
            }
        }
    }
    true
}

/// The flat layout of `mesh`'s 3D form, aligned to its current crease pattern if any.
pub fn unfold(mesh: &Mesh) -> Result<Vec<Vec2>, UnfoldError> {
    let x = mesh.positions();
    let faces = mesh.faces();
    let topo = mesh.topology();
    let n = x.len();
    let mut placed: Vec<Option<Vec2>> = vec![None; n];
    let mut done = vec![false; faces.len()];
    // Seed: the first face, laid along the x axis.
    let [a, b, c] = faces[0];
    let (lab, lac, lbc) = (
        (x[b] - x[a]).norm(),
        (x[c] - x[a]).norm(),
        (x[c] - x[b]).norm(),
    );
    placed[a] = Some(Vec2::zeros());
    placed[b] = Some(Vec2::new(lab, 0.0));
    placed[c] = Some(apex(Vec2::zeros(), Vec2::new(lab, 0.0), lac, lbc));
    done[0] = true;
    let mut queue = VecDeque::from([0usize]);
    let mut reached = 1;
    while let Some(f) = queue.pop_front() {
        for &e in &topo.face_edges[f] {
            for g in topo.edge_faces[e].iter().flatten().copied() {
                if done[g] {
                    continue;
                }
                done[g] = true;
                reached += 1;
                queue.push_back(g);
                // g = (p, q, r) counter-clockwise; p, q on the shared edge are placed.
                let fg = faces[g];
                let k = (0..3)
                    .find(|&k| {
                        placed[fg[k]].is_some() && placed[fg[(k + 1) % 3]].is_some() && {
                            let [u, v] = mesh.edges()[e].vertices;
                            let (s, t) = (fg[k], fg[(k + 1) % 3]);
                            (s == u && t == v) || (s == v && t == u)
                        }
                    })
                    .expect("shared edge is placed");
                let (p, q, r) = (fg[k], fg[(k + 1) % 3], fg[(k + 2) % 3]);
                if placed[r].is_none() {
                    let (pp, pq) = (placed[p].unwrap(), placed[q].unwrap());
                    placed[r] = Some(apex(pp, pq, (x[r] - x[p]).norm(), (x[r] - x[q]).norm()));
                }
            }
        }
    }
    if reached < faces.len() {
        return Err(UnfoldError::Disconnected(topo.components));
    }
    let mut flat: Vec<Vec2> = placed
        .into_iter()
        .map(|p| p.expect("every vertex is on a face"))
        .collect();
    if let Some(old) = mesh.crease_pattern() {
        align(&mut flat, old);
    }
    Ok(flat)
}

/// A tube (paper §7) laid out: the strip it is cut open to along its seam
/// ([`Mesh::cut_open`]), its sheet given the crease pattern unfolded from its 3D form.
pub fn unfold_tube(tube: &Mesh) -> Result<Strip, UnfoldError> {
    let mut strip = tube.cut_open()?;
    let flat = unfold(&strip.sheet)?;
    strip.sheet.set_crease_pattern(flat);
    Ok(strip)
}

/// Which of a design's two forms its crease pattern is taken from when it has both.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatternFrom {
    /// The stored crease pattern: simulation mode keeps every length, so it still
    /// describes the 3D form, and it is the file's own drawing.
    Stored,
    /// The 3D form unfolded (and moved onto the stored pattern): design mode changed
    /// lengths, or the sheet must fold into exactly this form (what `fab` cuts).
    Form,
}

/// The crease pattern of a design (mm), decided here and nowhere else: a design with no
/// 3D form is its crease pattern; otherwise the stored one or the 3D form unfolded, as
/// `from` says (the form when nothing is stored). A tube has none of its own: its strip
/// ([`sheet_of`]) has.
pub fn crease_pattern_of(mesh: &Mesh, from: PatternFrom) -> Result<Cow<'_, [Vec2]>, UnfoldError> {
    if mesh.is_tube() {
        return Err(UnfoldError::Tube);
    }
    match mesh.crease_pattern() {
        Some(stored) if !mesh.has_3d() || from == PatternFrom::Stored => Ok(Cow::Borrowed(stored)),
        _ => Ok(Cow::Owned(unfold(mesh)?)),
    }
}

/// The sheet a design is made from, with its crease pattern ([`crease_pattern_of`]): the
/// design itself, or for a tube the strip it is cut open to along its seam.
pub fn sheet_of(design: &Mesh, from: PatternFrom) -> Result<Cow<'_, Mesh>, UnfoldError> {
    if design.is_tube() {
        return Ok(Cow::Owned(unfold_tube(design)?.sheet));
    }
    match crease_pattern_of(design, from)? {
        Cow::Borrowed(_) => Ok(Cow::Borrowed(design)),
        Cow::Owned(pattern) => {
            let mut sheet = design.clone();
            sheet.set_crease_pattern(pattern);
            Ok(Cow::Owned(sheet))
        }
    }
}

/// The largest relative difference between an edge's length in `pattern` and in the 3D
/// form: 0 when the pattern is the form's isometric unfolding.
pub fn isometry_error(mesh: &Mesh, pattern: &[Vec2]) -> f64 {
    let x = mesh.positions();
    mesh.edges()
        .iter()
        .map(|e| {
            let [a, b] = e.vertices;
            let l3 = (x[a] - x[b]).norm();
            ((pattern[a] - pattern[b]).norm() - l3).abs() / l3
        })
        .fold(0.0, f64::max)
}

/// The third corner of a counter-clockwise triangle on base p→q with sides |pr|, |qr|.
fn apex(p: Vec2, q: Vec2, pr: f64, qr: f64) -> Vec2 {
    let base = q - p;
    let d = base.norm();
    let along = (pr * pr - qr * qr + d * d) / (2.0 * d);
    let up = (pr * pr - along * along).max(0.0).sqrt();
    let u = base / d;
    p + u * along + Vec2::new(-u.y, u.x) * up
}

/// Rotates and translates `flat` onto `target` in the least-squares sense (2D Procrustes).
fn align(flat: &mut [Vec2], target: &[Vec2]) {
    let n = flat.len() as f64;
    let ca = flat.iter().sum::<Vec2>() / n;
    let cb = target.iter().sum::<Vec2>() / n;
    let (mut s, mut c) = (0.0, 0.0);
    for (p, q) in flat.iter().zip(target) {
        let (u, v) = (p - ca, q - cb);
        c += u.dot(&v);
        s += u.perp(&v);
    }
    let angle = s.atan2(c);
    let (sn, cs) = angle.sin_cos();
    for p in flat.iter_mut() {
        let u = *p - ca;
        *p = cb + Vec2::new(cs * u.x - sn * u.y, sn * u.x + cs * u.y);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Vec3;

    fn design(file: &str) -> Mesh {
        crate::io::fold::parse(file).expect("a bundled pattern parses")
    }

    #[test]
    fn a_crease_pattern_alone_is_the_pattern_whichever_form_is_asked() {
        let cp = design(include_str!("../../patterns/bird-base.fold"));
        assert!(!cp.has_3d());
        for from in [PatternFrom::Stored, PatternFrom::Form] {
            let got = crease_pattern_of(&cp, from).unwrap();
            assert!(
                matches!(got, Cow::Borrowed(_)),
                "{from:?} unfolded a flat file"
            );
            assert_eq!(&*got, cp.crease_pattern().unwrap());
        }
    }

    #[test]
    fn a_stale_stored_pattern_is_kept_only_when_asked_for() {
        // A folded design whose 3D form is then scaled by 10% (still developable): the
        // stored pattern no longer has the form's lengths.
        let mut folded = design(include_str!("../../patterns/miura-bent.fold"));
        assert!(folded.has_3d() && folded.crease_pattern().is_some());
        let stretched: Vec<Vec3> = folded.positions().iter().map(|p| 1.1 * p).collect();
        folded.set_positions(stretched);
        let stored = crease_pattern_of(&folded, PatternFrom::Stored).unwrap();
        assert_eq!(&*stored, folded.crease_pattern().unwrap());
        // Every length grew by 10%: each stored one is 1/11 of the new one short.
        let off = isometry_error(&folded, &stored);
        assert!((off - 1.0 / 11.0).abs() < 1e-9, "stored off by {off}");
        let form = crease_pattern_of(&folded, PatternFrom::Form).unwrap();
        assert!(matches!(form, Cow::Owned(_)));
        let error = isometry_error(&folded, &form);
        assert!(
            error < 1e-9,
            "the unfolded form is off its lengths by {error:e}"
        );
    }

    #[test]
    fn a_tube_has_no_pattern_of_its_own_and_its_sheet_is_its_strip() {
        let tube = design(include_str!("../../patterns/waterbomb-tube.fold"));
        assert!(tube.is_tube());
        assert!(matches!(
            crease_pattern_of(&tube, PatternFrom::Stored),
            Err(UnfoldError::Tube)
        ));
        let sheet = sheet_of(&tube, PatternFrom::Stored).unwrap();
        assert!(!sheet.is_tube());
        let pattern = sheet.crease_pattern().expect("the strip has its pattern");
        // Cut open along the seam: more vertices, every edge at its 3D length.
        assert!(sheet.vertex_count() > tube.vertex_count());
        assert!(isometry_error(&sheet, pattern) < 1e-9);
    }
}
