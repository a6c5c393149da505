//! The origami conditions of the paper (§2) as residuals with exact sparse Jacobians
//! (§3, eq. 11–18). Each family lives in its own module and appends rows to a [`Rows`]
//! block; a [`ConstraintSet`] picks families by name (the paper's "sets of active
//! conditions"). Inequalities `g ≤ 0` contribute `max(g, 0)` (§3).

mod angles;
mod chains;
mod contacts;
mod context;
mod lengths;
mod smoothness;

pub use angles::{tracked_fold_angle, FoldAngles};
pub use chains::{crease_chains, has_curved_creases, CreaseChain};
pub use contacts::{flat_contacts, Contact, MAX_CONTACT_FACES};
pub use context::{flips, folds_flat, mirrored_edges, Reference};
pub use smoothness::{largest_second_differences, MAX_SECOND_DIFFERENCE};

use crate::mesh::{Mesh, Vec3};
use sprs::CsMat;

/// Meshes with at least this many faces evaluate their conditions on every core (when
/// there is more than one); below it handing work to another thread costs more than it
/// saves.
const PARALLEL_FACES: usize = 4096;

/// Whether `mesh` is large enough to evaluate on every core, and there is more than one.
fn evaluate_in_parallel(mesh: &Mesh) -> bool {
    mesh.faces().len() >= PARALLEL_FACES && rayon::current_num_threads() > 1
}

/// A family of conditions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Family {
    /// Eq. (1): sector angles sum to 2π at every interior vertex.
    Developability,
    /// Eq. (2): boundary vertices keep their sector-angle sums.
    BoundaryAngle,
    /// Eq. (3): straight pieces of the perimeter keep their lengths.
    BoundaryLength,
    /// Eq. (4), optional: the paper's boundary stays convex.
    Convexity,
    /// Eq. (5): Kawasaki's condition Σ σθ = 0 at flat-foldable vertices.
    FlatFoldability,
    /// Eq. (6)–(8): angular inequalities against local layer intersections.
    AngularInequality,
    /// §2.4 (1–2): a mountain stays in [0, π], a valley in [−π, 0].
    FoldAngleRange,
    /// §2.4 (3): a target-0 crease twists at most |ρ| ≤ απ; with α = 0 it stays flat
    /// (an equality, ρ = 0).
    TwistRange,
    /// §5 simulation mode: every edge keeps its length (relative residual).
    EdgeLength,
    /// §6.4: vertices that meet in the folded form stay together (Resch's tucks closed
    /// behind the tiles); relative to the mean crease length.
    Coincidence,
    /// §2.3: the crease pattern folded flat keeps a layer order (flat-foldability is
    /// coordinates *and* an order of the layers). As rows, the contacts of the starting
    /// flat-folded state stay contacts ([`Reference::contacts`]; relative to the mean
    /// crease length); besides, a drag step that would lose the order is halved, then
    /// refused ([`crate::solver::run_stage`]), and verification judges the order on the
    /// design's flat state.
    LayerOrder,
    /// §6.6 and §7's future work (issue 30): along each curved crease, drawn as a chain of
    /// straight creases, the turning angle varies smoothly in the crease pattern and in
    /// space (second differences at most [`MAX_SECOND_DIFFERENCE`]).
    Smoothness,
}

impl Family {
    /// Every family, in report order.
    pub const ALL: [Family; 12] = [
        Family::Developability,
        Family::BoundaryAngle,
        Family::BoundaryLength,
        Family::Convexity,
        Family::FlatFoldability,
        Family::AngularInequality,
        Family::FoldAngleRange,
        Family::TwistRange,
        Family::EdgeLength,
        Family::Coincidence,
        Family::LayerOrder,
        Family::Smoothness,
    ];

    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Family::Developability => "developability",
            Family::BoundaryAngle => "boundary-angle",
            Family::BoundaryLength => "boundary-length",
            Family::Convexity => "convexity",
            Family::FlatFoldability => "flat-foldability",
            Family::AngularInequality => "angular-inequality",
            Family::FoldAngleRange => "fold-angle-range",
            Family::TwistRange => "twist-range",
            Family::EdgeLength => "edge-length",
            Family::Coincidence => "coincidence",
            Family::LayerOrder => "layer-order",
            Family::Smoothness => "smoothness",
        }
    }

    /// Looks a family up by name.
    pub fn from_name(name: &str) -> Option<Family> {
        Family::ALL.into_iter().find(|f| f.name() == name)
    }

    /// Whether the family is an inequality `g ≤ 0`, whose rows are `max(g, 0)` and carry
    /// no Jacobian entries while inactive.
    pub fn is_inequality(self) -> bool {
        matches!(
            self,
            Family::Convexity
                | Family::AngularInequality
                | Family::FoldAngleRange
                | Family::TwistRange
                | Family::Smoothness
        )
    }

    /// Whether the family sums sector angles (eq. 1, 2, 4–8), which an evaluation then
    /// computes once for all of them.
    pub fn uses_sector_angles(self) -> bool {
        matches!(
            self,
            Family::Developability
                | Family::BoundaryAngle
                | Family::Convexity
                | Family::FlatFoldability
                | Family::AngularInequality
                | Family::Smoothness
        )
    }

    /// Whether the family measures fold angles (§2.4), which need every face's normal.
    pub fn uses_fold_angles(self) -> bool {
        matches!(self, Family::FoldAngleRange | Family::TwistRange)
    }

    /// Whether the residual is a relative length (else an angle in radians).
    pub fn is_length(self) -> bool {
        matches!(
            self,
            Family::BoundaryLength | Family::EdgeLength | Family::Coincidence | Family::LayerOrder
        )
    }
}

impl Element {
    /// Whether the row is one of the paper's empirical inequalities (7, 8): "an empirical
    /// condition applicable to finding a locally closed vertex", which designs keep but
    /// which no flat-folded state requires (the traditional Kabuto breaks it).
    pub fn is_empirical(&self) -> bool {
        matches!(self, Element::Sector(_, _, _, 7 | 8))
    }
}

/// What a residual row is about, so reports can name it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Element {
    /// A vertex.
    Vertex(usize),
    /// An edge.
    Edge(usize),
    /// A pair of consecutive creases at a vertex (angular inequalities): vertex, edges,
    /// and which of the paper's equations the row is: 6, Kawasaki's necessary condition
    /// (the big-little-big lemma), or 7 and 8, its empirical condition for a locally
    /// closed vertex ([`Element::is_empirical`]).
    Sector(usize, usize, usize, u8),
    /// Two faces (self-intersection: they pass through each other).
    Faces(usize, usize),
}

impl std::fmt::Display for Element {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Element::Vertex(v) => write!(f, "vertex {v}"),
            Element::Edge(e) => write!(f, "edge {e}"),
            Element::Sector(v, a, b, eq) => {
                write!(f, "vertex {v} between edges {a} and {b} (eq. {eq})")
            }
            Element::Faces(a, b) => write!(f, "faces {a} and {b}"),
        }
    }
}

/// Residual rows with their Jacobian entries, as triplets over columns `3·vertex + axis`.
#[derive(Clone, Debug, Default)]
pub struct Rows {
    /// Residual values.
    pub residuals: Vec<f64>,
    /// The family and element of each row.
    pub labels: Vec<(Family, Element)>,
    /// Whether each row is `max(g, 0)` of an inequality (no Jacobian entries while 0).
    pub inequality: Vec<bool>,
    /// Jacobian triplets (row, column, value).
    pub triplets: Vec<(usize, usize, f64)>,
    /// Leave out satisfied inequality rows (their pushes return [`Rows::SKIPPED`]).
    pub active_only: bool,
    /// Residuals and labels only, no Jacobian (a solver reusing its factor needs no more).
    pub values_only: bool,
    /// Every edge's tracked fold angle at the evaluated positions, when a family read them.
    pub fold_angles: Option<FoldAngles>,
    /// Each row's [`HeldRow`] key (inequality rows; equalities carry their family and
    /// `u32::MAX`), when `track_keys` asks for them: a solver's active rows, not a
    /// verification's full set, whose memory they would grow by 8 bytes a row.
    pub keys: Vec<HeldRow>,
    /// Record `keys`.
    pub track_keys: bool,
    /// Satisfied inequality rows still wanted (see [`HeldRows`]), while within `held_band`
    /// of their bound.
    pub held: Option<std::sync::Arc<HeldRows>>,
    /// How far inside its bound (`g ≥ −held_band`) a held row is still kept.
    pub held_band: f64,
    /// Inequality rows pushed so far, per family: the next one's [`HeldRow`] ordinal.
    ordinals: [u32; Family::ALL.len()],
}

/// An inequality row's identity across evaluations of one mesh: its family and its
/// ordinal among that family's inequality rows, active or not (labels are not unique:
/// smoothness writes a crease-pattern and a space row at each vertex).
pub type HeldRow = (Family, u32);

/// Inequality rows a Newton correction keeps as equalities `g = 0` even where satisfied
/// (an active set that only grows within one correction). Two coupled inequalities, as
/// neighbouring smoothness rows on a crease chain, otherwise take turns: correcting the
/// one active row alone pushes its neighbour past its bound, the next iteration corrects
/// that one alone, and the residual falls only linearly (on the concentric bowl pulled
/// with a twist allowance, by 0.75 an iteration, 20 iterations short of 1e-8). Holding
/// both corrects them together, quadratically again; a held row ends on its bound,
/// which the inequality allows. A row the correction has carried farther inside than the
/// violation it is correcting is let go: pulling it back to its bound would be a step of
/// its own, not part of this correction.
pub type HeldRows = std::collections::HashSet<HeldRow>;

impl Rows {
    /// The index a left-out row gets; gradients added to it are dropped.
    pub const SKIPPED: usize = usize::MAX;

    /// Starts a row; returns its index.
    pub fn push(&mut self, family: Family, element: Element, residual: f64) -> usize {
        self.push_row(family, element, residual, family.is_inequality())
    }

    /// Starts the row of an inequality `g ≤ 0`: `max(g, 0)`, or `g` itself when the row is
    /// held ([`HeldRows`]). Returns the row when it is active or held, the rows whose
    /// Jacobian entries the family then adds; `None` for a satisfied row (left out of an
    /// active-only evaluation, a 0 in a full one).
    pub fn push_inequality(&mut self, family: Family, element: Element, g: f64) -> Option<usize> {
        let counter = &mut self.ordinals[family as usize];
        let key = (family, *counter);
        *counter += 1;
        let held = g <= 0.0
            && g >= -self.held_band
            && self.held.as_ref().is_some_and(|h| h.contains(&key));
        let active = g > 0.0 || held;
        if self.active_only && !active {
            return None;
        }
        self.inequality.push(true);
        self.residuals.push(if active { g } else { 0.0 });
        self.labels.push((family, element));
        if self.track_keys {
            self.keys.push(key);
        }
        active.then_some(self.residuals.len() - 1)
    }

    /// The largest violation among the rows: |r| of an equality, `max(r, 0)` of an
    /// inequality (a held row below its bound is satisfied).
    pub fn largest_violation(&self) -> f64 {
        self.residuals
            .iter()
            .zip(&self.inequality)
            .fold(0.0, |a: f64, (&r, &ineq)| {
                a.max(if ineq { r.max(0.0) } else { r.abs() })
            })
    }

    /// Starts a row, saying whether it is an inequality's `max(g, 0)`.
    pub fn push_row(
        &mut self,
        family: Family,
        element: Element,
        residual: f64,
        inequality: bool,
    ) -> usize {
        if self.active_only && inequality && residual <= 0.0 {
            return Self::SKIPPED;
        }
        self.inequality.push(inequality);
        self.residuals.push(residual);
        self.labels.push((family, element));
        if self.track_keys {
            self.keys.push((family, u32::MAX));
        }
        self.residuals.len() - 1
    }

    /// Adds `scale · g` to the derivative of `row` with respect to vertex `v`.
    pub fn add_gradient(&mut self, row: usize, v: usize, g: Vec3, scale: f64) {
        if row == Self::SKIPPED || self.values_only {
            return;
        }
        for k in 0..3 {
            let value = scale * g[k];
            if value != 0.0 {
                self.triplets.push((row, 3 * v + k, value));
            }
        }
    }

    /// Appends another block of rows after these.
    pub fn append(&mut self, other: Rows) {
        let offset = self.residuals.len();
        self.residuals.extend(other.residuals);
        self.labels.extend(other.labels);
        self.inequality.extend(other.inequality);
        self.keys.extend(other.keys);
        self.triplets.extend(
            other
                .triplets
                .into_iter()
                .map(|(r, c, v)| (r + offset, c, v)),
        );
    }

    /// The Jacobian as a compressed sparse row matrix with `3 · vertices` columns.
    pub fn jacobian(&self, vertices: usize) -> CsMat<f64> {
        self.jacobian_mapped(3 * vertices, Some)
    }

    /// The Jacobian over a subset of columns: `column(c)` gives the new index of column
    /// `c`, or `None` to drop it (fixed vertices). Built row by row in linear time;
    /// repeated entries are summed.
    pub fn jacobian_mapped(
        &self,
        columns: usize,
        column: impl Fn(usize) -> Option<usize>,
    ) -> CsMat<f64> {
        let m = self.residuals.len();
        let mut count = vec![0usize; m + 1];
        for &(r, c, _) in &self.triplets {
            if column(c).is_some() {
                count[r + 1] += 1;
            }
        }
        for r in 0..m {
            count[r + 1] += count[r];
        }
        let mut fill = count.clone();
        let mut entries = vec![(0usize, 0.0f64); count[m]];
        for &(r, c, v) in &self.triplets {
            if let Some(c) = column(c) {
                entries[fill[r]] = (c, v);
                fill[r] += 1;
            }
        }
        let (mut indptr, mut indices, mut data) = (
            Vec::with_capacity(m + 1),
            Vec::with_capacity(entries.len()),
            Vec::with_capacity(entries.len()),
        );
        indptr.push(0);
        for r in 0..m {
            let row = &mut entries[count[r]..count[r + 1]];
            row.sort_unstable_by_key(|e| e.0);
            for &(c, v) in row.iter() {
                if indices.len() > indptr[r] && *indices.last().unwrap() == c {
                    *data.last_mut().unwrap() += v;
                } else {
                    indices.push(c);
                    data.push(v);
                }
            }
            indptr.push(indices.len());
        }
        CsMat::new((m, columns), indptr, indices, data)
    }
}

/// A chosen set of families, evaluated against a reference state.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstraintSet {
    /// Families in evaluation order.
    pub families: Vec<Family>,
}

impl ConstraintSet {
    /// Parses a comma-separated list of family names.
    pub fn parse(list: &str) -> Result<ConstraintSet, String> {
        let names: Vec<&str> = list.split(',').map(str::trim).collect();
        if names.iter().any(|n| n.is_empty()) && names.len() > 1 {
            return Err(format!(
                "empty entry in the condition list \"{list}\" (names separated by single commas)"
            ));
        }
        for (i, n) in names.iter().enumerate() {
            if names[..i].contains(n) {
                return Err(format!("condition \"{n}\" is listed twice"));
            }
        }
        let families = names
            .into_iter()
            .filter(|s| !s.is_empty())
            .map(|n| {
                Family::from_name(n).ok_or_else(|| {
                    let names: Vec<&str> = Family::ALL.iter().map(|f| f.name()).collect();
                    format!(
                        "unknown condition \"{n}\" (choose from: {})",
                        names.join(", ")
                    )
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        if families.is_empty() {
            return Err("no conditions given".into());
        }
        Ok(ConstraintSet { families })
    }

    /// What a design's own crease assignment calls for: developability and fold-angle
    /// ranges always, flat-foldability and its inequalities when every interior vertex
    /// with folds has an even number of them (a necessary condition for folding flat).
    pub fn default_for(reference: &Reference) -> ConstraintSet {
        let mut families = vec![Family::Developability];
        if reference.is_flat_foldable() {
            families.extend([Family::FlatFoldability, Family::AngularInequality]);
        }
        families.extend([Family::FoldAngleRange, Family::TwistRange]);
        if reference.closed_groups {
            families.push(Family::Coincidence);
        }
        if reference.curved_creases {
            families.push(Family::Smoothness);
        }
        ConstraintSet { families }
    }

    /// Residuals and Jacobian rows of every family at `positions`.
    pub fn evaluate(&self, mesh: &Mesh, reference: &Reference, positions: &[Vec3]) -> Rows {
        self.evaluate_into(mesh, reference, positions, Rows::default())
    }

    /// Every row's residual and label at `positions`, without the Jacobian: what a
    /// verification reads. On a 90k-vertex Miura-ori the Jacobian's triplets are most of
    /// an evaluation's memory.
    pub fn evaluate_values(&self, mesh: &Mesh, reference: &Reference, positions: &[Vec3]) -> Rows {
        let rows = Rows {
            values_only: true,
            ..Rows::default()
        };
        self.evaluate_into(mesh, reference, positions, rows)
    }

    /// Like [`ConstraintSet::evaluate`] but without the satisfied inequality rows: what a
    /// solver factorises, built without copying the full set first.
    /// With `values_only` the Jacobian is left out.
    pub fn evaluate_active(
        &self,
        mesh: &Mesh,
        reference: &Reference,
        positions: &[Vec3],
        values_only: bool,
    ) -> Rows {
        self.evaluate_holding(mesh, reference, positions, values_only, None)
    }

    /// [`ConstraintSet::evaluate_active`] with the `held` inequality rows kept, as `g`
    /// itself, where satisfied by at most the band given with them (see [`HeldRows`]).
    pub fn evaluate_holding(
        &self,
        mesh: &Mesh,
        reference: &Reference,
        positions: &[Vec3],
        values_only: bool,
        held: Option<(std::sync::Arc<HeldRows>, f64)>,
    ) -> Rows {
        let (held, held_band) = held.map_or((None, 0.0), |(h, band)| (Some(h), band));
        let rows = Rows {
            active_only: true,
            values_only,
            track_keys: true,
            held,
            held_band,
            ..Rows::default()
        };
        self.evaluate_into(mesh, reference, positions, rows)
    }

    fn evaluate_into(
        &self,
        mesh: &Mesh,
        reference: &Reference,
        positions: &[Vec3],
        mut rows: Rows,
    ) -> Rows {
        use rayon::prelude::*;
        let uses_sectors = self.families.iter().any(|f| f.uses_sector_angles());
        let uses_fold_angles = self.families.iter().any(|f| f.uses_fold_angles());
        let parallel = evaluate_in_parallel(mesh);
        let corners = uses_sectors.then(|| angles::Corners::new(mesh, positions, parallel));
        let folds = uses_fold_angles.then(|| {
            let normals = angles::FaceNormals::new(mesh, positions, parallel);
            angles::FoldAngles::new(mesh, reference, &normals, positions, parallel)
        });
        let fill = |f: Family, out: &mut Rows| {
            let c = || corners.as_ref().expect("sector angles computed");
            let n = || folds.as_ref().expect("fold angles computed");
            let x = positions;
            match f {
                Family::Developability => angles::developability(mesh, c(), out),
                Family::BoundaryAngle => angles::boundary_angle(mesh, reference, c(), out),
                Family::Convexity => angles::convexity(mesh, c(), out),
                Family::FlatFoldability => angles::flat_foldability(mesh, reference, c(), out),
                Family::AngularInequality => angles::angular_inequality(mesh, reference, c(), out),
                Family::TwistRange => angles::twist_range(mesh, n(), x, out),
                Family::FoldAngleRange => angles::fold_angle_range(mesh, n(), x, out),
                Family::BoundaryLength => lengths::boundary_length(mesh, reference, x, out),
                Family::EdgeLength => lengths::edge_length(mesh, reference, x, out),
                Family::Coincidence => lengths::coincidence(mesh, reference, x, out),
                Family::Smoothness => smoothness::smoothness(mesh, reference, c(), x, out),
                Family::LayerOrder => contacts::layer_contacts(mesh, reference, x, out),
            }
        };
        if parallel {
            // Families fill their own blocks, appended in the set's order: the same rows,
            // values and Jacobian on any number of cores.
            let parts: Vec<Rows> = self
                .families
                .par_iter()
                .map(|&f| {
                    let mut part = Rows {
                        active_only: rows.active_only,
                        values_only: rows.values_only,
                        track_keys: rows.track_keys,
                        held: rows.held.clone(),
                        held_band: rows.held_band,
                        ..Rows::default()
                    };
                    fill(f, &mut part);
                    part
                })
                .collect();
            for part in parts {
                rows.append(part);
            }
        } else {
            // One after another straight into `rows`: no blocks to copy.
            for &f in &self.families {
                fill(f, &mut rows);
            }
        }
        rows.fold_angles = folds;
        rows
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three inequality rows of one family: −0.02, 0.5 and −0.3. Plain, only the violated
    /// one is a row; holding the first and third keeps the first (0.02 inside, within the
    /// band of 0.1) as `g` itself, but not the third (0.3 inside); the largest violation
    /// ignores a held row's negative value.
    #[test]
    fn held_rows_stay_as_their_own_value_within_the_band_and_count_as_satisfied() {
        let push_all = |rows: &mut Rows| -> Vec<Option<usize>> {
            [-0.02, 0.5, -0.3]
                .iter()
                .enumerate()
                .map(|(v, &g)| rows.push_inequality(Family::Smoothness, Element::Vertex(v), g))
                .collect()
        };
        let mut plain = Rows {
            active_only: true,
            track_keys: true,
            ..Rows::default()
        };
        assert_eq!(push_all(&mut plain), [None, Some(0), None]);
        assert_eq!(plain.residuals, [0.5]);
        assert_eq!(plain.keys, [(Family::Smoothness, 1)]);

        let held: HeldRows = [(Family::Smoothness, 0), (Family::Smoothness, 2)].into();
        let mut holding = Rows {
            active_only: true,
            track_keys: true,
            held: Some(std::sync::Arc::new(held)),
            held_band: 0.1,
            ..Rows::default()
        };
        assert_eq!(push_all(&mut holding), [Some(0), Some(1), None]);
        assert_eq!(holding.residuals, [-0.02, 0.5]);
        assert_eq!(holding.largest_violation(), 0.5);
        holding.residuals[1] = -1e-3;
        assert_eq!(holding.largest_violation(), 0.0);

        // A full evaluation keeps every row, satisfied ones as 0.
        let mut full = Rows::default();
        assert_eq!(push_all(&mut full), [None, Some(1), None]);
        assert_eq!(full.residuals, [0.0, 0.5, 0.0]);
    }
}
