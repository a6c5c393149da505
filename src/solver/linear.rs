//! The linear algebra of eq. (10): solves with J Jᵀ for the minimum-norm projection and the
//! Gauss–Newton correction. J Jᵀ is factorised by sparse Cholesky (faer; AMD ordering, or
//! METIS for large systems, see [`super::ordering`]);
//! its symbolic analysis is kept while the sparsity pattern stays (the active set of
//! inequalities rarely changes between steps). Conjugate gradient on J Jᵀ squares J's
//! condition number and stalls near the flat state, which is where every design starts.

use super::error::LinearError;
use super::ordering::{nested_dissection, NESTED_DISSECTION_ROWS};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, Par, Side};
use sprs::CsMat;

/// Relative Tikhonov shift λ/max(diag J Jᵀ): redundant rows (a flat vertex's Kawasaki and
/// developability rows, say) make J Jᵀ singular; the shift keeps it definite while moving
/// the minimum-norm solution by a relative 1e-12.
const RELATIVE_SHIFT: f64 = 1e-12;

/// Systems of fewer rows are factorised and solved on one thread: handing the small
/// supernodes of a few thousand rows to another thread costs more than it gives (a
/// 961-vertex Miura-ori's folding motion of 60 frames, normal equations of about 2,900
/// rows: 22 s with both cores on every system, 13.6 s with this threshold); the design
/// step's benchmark gains from the second core from 10k vertices (29,000 active rows) up,
/// and was the same on one core and two at 256 vertices.
pub const PARALLEL_ROWS: usize = 10_000;

/// faer's parallelism for a system of `rows` rows ([`PARALLEL_ROWS`]).
fn parallelism(rows: usize) -> Par {
    if rows < PARALLEL_ROWS {
        Par::Seq
    } else {
        faer::get_global_parallelism()
    }
}

/// How the Tikhonov shift λ of J Jᵀ + λI is sized.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shift {
    /// `RELATIVE_SHIFT` times the largest diagonal entry, for every row: rows of one
    /// scale, as the paper's conditions are.
    Largest,
    /// `RELATIVE_SHIFT` times each row's own diagonal entry (Marquardt's scaling): for
    /// rows of very different scales. The layer-order rows' gradients reach along the
    /// whole flat-folded walk, 10⁴ times the angle rows'; a shift sized to them held
    /// Newton on the angle rows to linear convergence (14 iterations where one does, and
    /// none converging on the 8 × 8 waterbomb).
    EachRow,
}

/// The lower triangle of J Jᵀ in compressed columns, sorted within each column.
struct NormalMatrix {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
}

impl NormalMatrix {
    /// Column r holds (J Jᵀ)ᵣ₂ᵣ = Σ_c J_rc J_r₂c for r₂ ≥ r, summed over c ascending (as a
    /// sparse product would), built straight into the form the factorisation reads: a
    /// general product and a triplet sort took a third of a refactorisation.
    fn new(j: &CsMat<f64>) -> NormalMatrix {
        let m = j.rows();
        let jt: CsMat<f64> = j.transpose_view().to_csr();
        let (mut col_ptr, mut row_idx, mut values) =
            (Vec::with_capacity(m + 1), Vec::new(), Vec::new());
        let mut sum = vec![0.0; m];
        let mut touched = vec![false; m];
        let mut rows: Vec<usize> = Vec::new();
        col_ptr.push(0);
        for (r, row) in j.outer_iterator().enumerate() {
            // The diagonal is always stored, so the shift can make an empty row definite.
            touched[r] = true;
            rows.push(r);
            for (c, &v) in row.iter() {
                let column = jt.outer_view(c).expect("column of J");
                for (r2, &w) in column.iter().filter(|(r2, _)| *r2 >= r) {
                    if !touched[r2] {
                        touched[r2] = true;
                        rows.push(r2);
                    }
                    sum[r2] += v * w;
                }
            }
            rows.sort_unstable();
            for &r2 in &rows {
                row_idx.push(r2);
                values.push(sum[r2]);
                sum[r2] = 0.0;
                touched[r2] = false;
            }
            rows.clear();
            col_ptr.push(row_idx.len());
        }
        NormalMatrix {
            col_ptr,
            row_idx,
            values,
        }
    }

    /// Adds `shift` to the diagonal (the first entry of each column).
    fn shift_diagonal(&mut self, shift: f64) {
        for &start in &self.col_ptr[..self.col_ptr.len() - 1] {
            self.values[start] += shift;
        }
    }

    /// Adds `relative` times each diagonal entry to it (Marquardt's scaling); an empty
    /// row (zero diagonal) gets `relative` times the largest, so the matrix stays definite.
    fn shift_each_row(&mut self, relative: f64) {
        let floor = relative * self.max_diagonal().max(f64::MIN_POSITIVE);
        for &start in &self.col_ptr[..self.col_ptr.len() - 1] {
            let d = self.values[start];
            self.values[start] += if d > 0.0 { relative * d } else { floor };
        }
    }

    fn max_diagonal(&self) -> f64 {
        self.col_ptr[..self.col_ptr.len() - 1]
            .iter()
            .map(|&start| self.values[start])
            .fold(0.0, f64::max)
    }
}

/// The symbolic analysis of one sparsity pattern of J Jᵀ and the storage of its factor,
/// both kept while the pattern stays (the active set of inequalities rarely changes).
struct Factor {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
    /// The factor's values, overwritten in place by each refactorisation: allocating
    /// them afresh cost page faults worth half a factorisation.
    values: Vec<f64>,
    /// A single-precision copy of `values`, made at the first single-precision solve
    /// after a factorisation (see [`NormalSolver::set_single_precision`]); empty until then.
    single: Vec<f32>,
    factor_scratch: MemBuffer,
    solve_scratch: MemBuffer,
    ready: bool,
}

/// A factorised J Jᵀ + λI for one Jacobian.
pub struct NormalSolver {
    factor: Option<Factor>,
    jacobian: CsMat<f64>,
    /// Systems of at least this many rows are ordered by nested dissection
    /// ([`NESTED_DISSECTION_ROWS`]; lowered by tests to reach that path on small systems).
    nested_dissection_rows: usize,
    /// Whether solves read the factor in single precision.
    single_precision: bool,
}

impl Default for NormalSolver {
    fn default() -> Self {
        NormalSolver {
            factor: None,
            jacobian: CsMat::zero((0, 0)),
            nested_dissection_rows: NESTED_DISSECTION_ROWS,
            single_precision: false,
        }
    }
}

impl NormalSolver {
    /// Factorises J Jᵀ + λI for a new Jacobian (CSR, rows × free variables).
    pub fn factorise(&mut self, jacobian: CsMat<f64>) -> Result<(), LinearError> {
        self.factorise_shifted(jacobian, Shift::Largest)
    }

    /// [`NormalSolver::factorise`] with the shift chosen: λ = `RELATIVE_SHIFT` times
    /// the largest diagonal entry for every row, or times each row's own.
    pub fn factorise_shifted(
        &mut self,
        jacobian: CsMat<f64>,
        shift: Shift,
    ) -> Result<(), LinearError> {
        let m = jacobian.rows();
        self.jacobian = jacobian;
        if let Some(f) = &mut self.factor {
            f.ready = false;
            f.single.clear();
        }
        if m == 0 {
            return Ok(());
        }
        let mut a = NormalMatrix::new(&self.jacobian);
        match shift {
            Shift::Largest => {
                a.shift_diagonal(RELATIVE_SHIFT * a.max_diagonal().max(f64::MIN_POSITIVE))
            }
            Shift::EachRow => a.shift_each_row(RELATIVE_SHIFT),
        }
        let par = parallelism(m);
        let reuse =
            matches!(&self.factor, Some(f) if f.col_ptr == a.col_ptr && f.row_idx == a.row_idx);
        if !reuse {
            let dissect = m >= self.nested_dissection_rows;
            self.factor = Some(Factor::analyse(&a, dissect, par)?);
        }
        let f = self.factor.as_mut().expect("set above");
        let mat = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(m, m, &f.col_ptr, None, &f.row_idx),
            &a.values,
        );
        f.values.fill(0.0);
        f.symbolic
            .factorize_numeric_llt::<f64>(
                &mut f.values,
                mat,
                Side::Lower,
                Default::default(),
                par,
                MemStack::new(&mut f.factor_scratch),
                Default::default(),
            )
            .map_err(|e| LinearError(format!("{e:?}")))?;
        f.ready = true;
        Ok(())
    }

    /// The Jacobian last factorised.
    pub fn jacobian(&self) -> &CsMat<f64> {
        &self.jacobian
    }

    /// Whether the solves that follow read a single-precision copy of the factor: half
    /// the bytes a solve streams from memory, which is what bounds it. Its rounding (a
    /// relative 1e-7 or so of each solution) is for Newton corrections that stop well
    /// above it (a pointer drag's, see `LIVE_RESIDUAL`): the chord iteration removes it
    /// with the rest of the residual. Projections and corrections to the solver's own
    /// tolerance solve in double precision.
    pub fn set_single_precision(&mut self, on: bool) {
        self.single_precision = on;
    }

    /// y = (J Jᵀ + λI)⁻¹ b.
    pub fn solve(&mut self, b: &[f64]) -> Vec<f64> {
        match &mut self.factor {
            Some(f) if f.ready && self.single_precision => {
                if f.single.is_empty() {
                    f.single.extend(f.values.iter().map(|&v| v as f32));
                }
                solve_column(
                    &f.symbolic,
                    &f.single,
                    &mut f.solve_scratch,
                    b,
                    |v| v as f32,
                    f64::from,
                )
            }
            // Not ready: no rows (nothing to solve) or a failed factorisation.
            Some(f) if f.ready => solve_column(
                &f.symbolic,
                &f.values,
                &mut f.solve_scratch,
                b,
                |v| v,
                |v| v,
            ),
            _ => vec![0.0; b.len()],
        }
    }

    /// J v.
    pub fn apply(&self, v: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.jacobian.rows()];
        for (row, vec) in self.jacobian.outer_iterator().enumerate() {
            out[row] = vec.iter().map(|(c, &x)| x * v[c]).sum();
        }
        out
    }

    /// Jᵀ y.
    pub fn apply_transpose(&self, y: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.jacobian.cols()];
        for (row, vec) in self.jacobian.outer_iterator().enumerate() {
            for (c, &x) in vec.iter() {
                out[c] += x * y[row];
            }
        }
        out
    }

    /// The projection of eq. (10): dx = (I − J⁺J) dx₀ = dx₀ − Jᵀ (J Jᵀ)⁻¹ J dx₀.
    pub fn project(&mut self, dx0: &[f64]) -> Vec<f64> {
        let y = self.solve(&self.apply(dx0));
        let correction = self.apply_transpose(&y);
        dx0.iter().zip(correction).map(|(a, b)| a - b).collect()
    }

    /// The minimum-norm Gauss–Newton step for J dx = −F: dx = −Jᵀ (J Jᵀ)⁻¹ F.
    pub fn newton_step(&mut self, residuals: &[f64]) -> Vec<f64> {
        let y = self.solve(residuals);
        self.apply_transpose(&y).into_iter().map(|v| -v).collect()
    }
}

/// Solves with the factor of `symbolic` whose values, in the precision `T`, are
/// `values`: `b` turned into `T` by `into`, the solution back by `back`.
fn solve_column<T: faer::traits::ComplexField + Copy>(
    symbolic: &SymbolicCholesky<usize>,
    values: &[T],
    scratch: &mut MemBuffer,
    b: &[f64],
    into: impl Fn(f64) -> T,
    back: impl Fn(T) -> f64,
) -> Vec<f64> {
    let mut rhs = Mat::<T>::from_fn(b.len(), 1, |i, _| into(b[i]));
    LltRef::new(symbolic, values).solve_in_place_with_conj(
        Conj::No,
        rhs.as_mut(),
        parallelism(b.len()),
        MemStack::new(scratch),
    );
    (0..b.len()).map(|i| back(rhs[(i, 0)])).collect()
}

impl Factor {
    /// The symbolic analysis (fill-reducing ordering, supernodes) of a new pattern: AMD,
    /// or METIS nested dissection when `dissect`.
    fn analyse(a: &NormalMatrix, dissect: bool, par: Par) -> Result<Factor, LinearError> {
        let m = a.col_ptr.len() - 1;
        let pattern = SymbolicSparseColMatRef::new_checked(m, m, &a.col_ptr, None, &a.row_idx);
        let dissection = dissect
            .then(|| nested_dissection(&a.col_ptr, &a.row_idx))
            .transpose()?;
        let ordering = match &dissection {
            Some(p) => SymmetricOrdering::Custom(PermRef::new_checked(&p.forward, &p.inverse, m)),
            None => SymmetricOrdering::Amd,
        };
        let symbolic =
            factorize_symbolic_cholesky(pattern, Side::Lower, ordering, Default::default())
                .map_err(|e| LinearError(format!("{e:?}")))?;
        let factor_scratch = MemBuffer::try_new(
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        )
        .map_err(|e| LinearError(format!("{e:?}")))?;
        // Either precision's solve (see `NormalSolver::set_single_precision`).
        let solve_scratch = MemBuffer::try_new(
            symbolic
                .solve_in_place_scratch::<f64>(1, par)
                .or(symbolic.solve_in_place_scratch::<f32>(1, par)),
        )
        .map_err(|e| LinearError(format!("{e:?}")))?;
        Ok(Factor {
            col_ptr: a.col_ptr.clone(),
            row_idx: a.row_idx.clone(),
            values: vec![0.0; symbolic.len_val()],
            single: Vec::new(),
            symbolic,
            factor_scratch,
            solve_scratch,
            ready: false,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sprs::TriMat;

    fn matrix(rows: &[&[f64]]) -> CsMat<f64> {
        let mut t = TriMat::new((rows.len(), rows[0].len()));
        for (i, r) in rows.iter().enumerate() {
            for (j, &v) in r.iter().enumerate() {
                if v != 0.0 {
                    t.add_triplet(i, j, v);
                }
            }
        }
        t.to_csr()
    }

    #[test]
    fn projection_lands_in_the_null_space_and_is_idempotent() {
        let j = matrix(&[&[1.0, 2.0, 0.0, -1.0], &[0.0, 1.0, 1.0, 3.0]]);
        let mut s = NormalSolver::default();
        s.factorise(j).unwrap();
        let dx0 = [0.3, -1.0, 2.0, 0.5];
        let dx = s.project(&dx0);
        // Exact but for the relative shift λ = 1e-12·max diag(J Jᵀ).
        for r in s.apply(&dx) {
            assert!(r.abs() < 1e-10, "J dx = {r}");
        }
        let again = s.project(&dx);
        for (a, b) in dx.iter().zip(&again) {
            assert!((a - b).abs() < 1e-10);
        }
        // dx0 − dx lies in the row space: orthogonal to dx.
        let dot: f64 = dx0.iter().zip(&dx).map(|(a, b)| (a - b) * b).sum();
        assert!(dot.abs() < 1e-10);
    }

    #[test]
    fn newton_step_solves_the_linearised_system_with_minimum_norm() {
        let j = matrix(&[&[2.0, 0.0, 1.0], &[0.0, 1.0, 1.0]]);
        let mut s = NormalSolver::default();
        s.factorise(j).unwrap();
        let f = [1.0, -2.0];
        let dx = s.newton_step(&f);
        let jdx = s.apply(&dx);
        assert!((jdx[0] + 1.0).abs() < 1e-10 && (jdx[1] - 2.0).abs() < 1e-10);
        // Minimum norm: dx is in the row space, so projecting it removes everything.
        assert!(s.project(&dx).iter().all(|v| v.abs() < 1e-10));
    }

    /// A well-conditioned J on a `k` × `k` grid: each row its cell and the cells beside.
    fn grid_jacobian(k: usize) -> CsMat<f64> {
        let mut t = TriMat::new((k * k, k * k));
        for c in 0..k * k {
            t.add_triplet(c, c, 4.0);
            for d in [1, k] {
                if c + d < k * k && (d == k || c % k + 1 < k) {
                    t.add_triplet(c, c + d, -1.0 + 0.01 * (c % 7) as f64);
                }
            }
        }
        t.to_csr()
    }

    #[test]
    fn a_factor_ordered_by_nested_dissection_solves_as_the_amd_one_does() {
        let k = 30;
        let j = grid_jacobian(k);
        let mut amd = NormalSolver::default();
        amd.factorise(j.clone()).unwrap();
        let mut dissected = NormalSolver {
            nested_dissection_rows: 0,
            ..NormalSolver::default()
        };
        dissected.factorise(j).unwrap();
        let order = |s: &NormalSolver| {
            let f = s.factor.as_ref().unwrap();
            f.symbolic.perm().unwrap().arrays().0.to_vec()
        };
        assert_ne!(order(&amd), order(&dissected), "both ordered by AMD");
        let b: Vec<f64> = (0..k * k).map(|i| (i as f64 * 0.37).sin()).collect();
        let (ya, yd) = (amd.solve(&b), dissected.solve(&b));
        // J Jᵀ y = b holds for both but for the shift λ ≈ 2e-11 times |y| < 1.
        let residual = |y: &[f64]| {
            let jjt_y = dissected.apply(&dissected.apply_transpose(y));
            jjt_y
                .iter()
                .zip(&b)
                .map(|(l, r)| (l - r).abs())
                .fold(0.0, f64::max)
        };
        assert!(residual(&yd) < 1e-10 && residual(&ya) < 1e-10);
        let gap = ya
            .iter()
            .zip(&yd)
            .map(|(a, d)| (a - d).abs())
            .fold(0.0, f64::max);
        assert!(gap < 1e-13, "solutions differ by {gap}");
    }

    #[test]
    fn single_precision_solves_are_accurate_to_single_precision_and_refine_to_double() {
        let k = 30;
        let mut s = NormalSolver::default();
        s.factorise(grid_jacobian(k)).unwrap();
        let b: Vec<f64> = (0..k * k).map(|i| (i as f64 * 0.37).sin()).collect();
        let exact = s.solve(&b);
        let error = |y: &[f64]| {
            let scale = exact.iter().fold(0.0, |a: f64, v| a.max(v.abs()));
            y.iter()
                .zip(&exact)
                .map(|(a, e)| (a - e).abs())
                .fold(0.0, f64::max)
                / scale
        };
        s.set_single_precision(true);
        let once = s.solve(&b);
        // Single precision's rounding, no more: a relative 6e-8 per operation.
        assert!(
            error(&once) > 1e-12 && error(&once) < 1e-5,
            "{:e}",
            error(&once)
        );
        // What a chord iteration does with it: each solve removes all but that rounding
        // of what is left, so a few reach double precision.
        let mut y = vec![0.0; b.len()];
        for _ in 0..4 {
            let jjt_y = s.apply(&s.apply_transpose(&y));
            let r: Vec<f64> = b.iter().zip(&jjt_y).map(|(b, a)| b - a).collect();
            for (yi, d) in y.iter_mut().zip(s.solve(&r)) {
                *yi += d;
            }
        }
        assert!(error(&y) < 1e-10, "{:e}", error(&y));
        s.set_single_precision(false);
        assert_eq!(s.solve(&b), exact);
    }

    #[test]
    fn redundant_rows_are_tolerated() {
        let j = matrix(&[&[1.0, 1.0, 0.0], &[2.0, 2.0, 0.0]]);
        let mut s = NormalSolver::default();
        s.factorise(j).unwrap();
        let dx = s.project(&[1.0, 0.0, 1.0]);
        assert!((dx[0] + dx[1]).abs() < 1e-9);
        assert!((dx[2] - 1.0).abs() < 1e-12);
    }
}
