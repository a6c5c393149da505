//! The linear algebra of eq. (10): solves with J Jᵀ for the minimum-norm projection and the
//! Gauss–Newton correction. J Jᵀ is factorised by sparse Cholesky (faer, AMD ordering);
//! its symbolic analysis is kept while the sparsity pattern stays (the active set of
//! inequalities rarely changes between steps). Conjugate gradient on J Jᵀ squares J's
//! condition number and stalls near the flat state, which is where every design starts.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use sprs::CsMat;

/// Relative Tikhonov shift λ/max(diag J Jᵀ): redundant rows (a flat vertex's Kawasaki and
/// developability rows, say) make J Jᵀ singular; the shift keeps it definite while moving
/// the minimum-norm solution by a relative 1e-12.
const RELATIVE_SHIFT: f64 = 1e-12;

/// A factorised J Jᵀ + λI for one Jacobian.
pub struct NormalSolver {
    symbolic: Option<(Vec<usize>, Vec<usize>, SymbolicLlt<usize>)>,
    factor: Option<Llt<usize, f64>>,
    jacobian: CsMat<f64>,
}

/// Why a linear solve failed.
#[derive(Debug, thiserror::Error)]
#[error("the normal equations J Jᵀ could not be factorised: {0}")]
pub struct LinearError(String);

impl Default for NormalSolver {
    fn default() -> Self {
        NormalSolver {
            symbolic: None,
            factor: None,
            jacobian: CsMat::zero((0, 0)),
        }
    }
}

impl NormalSolver {
    /// Factorises J Jᵀ + λI for a new Jacobian (CSR, rows × free variables).
    pub fn factorise(&mut self, jacobian: CsMat<f64>) -> Result<(), LinearError> {
        let m = jacobian.rows();
        self.jacobian = jacobian;
        if m == 0 {
            self.factor = None;
            return Ok(());
        }
        let jt: CsMat<f64> = self.jacobian.transpose_view().to_csr();
        let a: CsMat<f64> = &self.jacobian * &jt;
        let max_diag = (0..m)
            .map(|i| a.get(i, i).copied().unwrap_or(0.0))
            .fold(0.0, f64::max);
        let shift = RELATIVE_SHIFT * max_diag.max(f64::MIN_POSITIVE);
        let mut triplets = Vec::with_capacity(a.nnz() / 2 + m);
        for (row, vec) in a.outer_iterator().enumerate() {
            for (col, &v) in vec.iter() {
                if row > col {
                    triplets.push(Triplet::new(row, col, v));
                }
            }
            triplets.push(Triplet::new(
                row,
                row,
                a.get(row, row).copied().unwrap_or(0.0) + shift,
            ));
        }
        let mat = SparseColMat::<usize, f64>::try_new_from_triplets(m, m, &triplets)
            .map_err(|e| LinearError(format!("{e:?}")))?;
        let pattern = (
            mat.symbolic().col_ptr().to_vec(),
            mat.symbolic().row_idx().to_vec(),
        );
        let reuse = matches!(&self.symbolic, Some((p, i, _)) if *p == pattern.0 && *i == pattern.1);
        if !reuse {
            let sym = SymbolicLlt::try_new(mat.symbolic(), Side::Lower)
                .map_err(|e| LinearError(format!("{e:?}")))?;
            self.symbolic = Some((pattern.0, pattern.1, sym));
        }
        let sym = self.symbolic.as_ref().expect("set above").2.clone();
        let llt = Llt::try_new_with_symbolic(sym, mat.as_ref(), Side::Lower)
            .map_err(|e| LinearError(format!("{e:?}")))?;
        self.factor = Some(llt);
        Ok(())
    }

    /// The Jacobian last factorised.
    pub fn jacobian(&self) -> &CsMat<f64> {
        &self.jacobian
    }

    /// y = (J Jᵀ + λI)⁻¹ b.
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        match &self.factor {
            None => vec![0.0; b.len()],
            Some(llt) => {
                let mut rhs = Mat::<f64>::from_fn(b.len(), 1, |i, _| b[i]);
                llt.solve_in_place(rhs.as_mut());
                (0..b.len()).map(|i| rhs[(i, 0)]).collect()
            }
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
    pub fn project(&self, dx0: &[f64]) -> Vec<f64> {
        let y = self.solve(&self.apply(dx0));
        let correction = self.apply_transpose(&y);
        dx0.iter().zip(correction).map(|(a, b)| a - b).collect()
    }

    /// The minimum-norm Gauss–Newton step for J dx = −F: dx = −Jᵀ (J Jᵀ)⁻¹ F.
    pub fn newton_step(&self, residuals: &[f64]) -> Vec<f64> {
        let y = self.solve(residuals);
        self.apply_transpose(&y).into_iter().map(|v| -v).collect()
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
