//! Which conditions hold a wished motion back. Eq. (10) keeps dx = dx₀ − Jᵀy with
//! y = (J Jᵀ)⁻¹ J dx₀: the refused part Jᵀy is a sum over the active rows, row i refusing
//! y_i J_iᵀ. Summed per family, the largest share names the condition a fit (or a drag)
//! is pressing against, and the row with the largest |y_i|·‖J_i‖ the element where it
//! presses hardest.

use super::{Solver, SolverError};
use crate::constraints::{Element, Family};
use crate::mesh::Vec3;

/// What refuses a wished motion, and how much of it.
#[derive(Clone, Debug, PartialEq)]
pub struct Resistance {
    /// The family refusing the most motion.
    pub family: Family,
    /// Its row refusing the most.
    pub element: Element,
    /// The share of the wish (by length) the projection refuses: ‖Jᵀy‖ / ‖dx₀‖.
    pub refused: f64,
    /// Each family's refused motion ‖J_fᵀ y_f‖ (mm), largest first.
    pub by_family: Vec<(Family, f64)>,
}

impl Solver {
    /// The conditions refusing `dx0` at the current positions (see the module's doc), or
    /// `None` when no active row refuses anything.
    pub fn resisting(&mut self, dx0: &[Vec3]) -> Result<Option<Resistance>, SolverError> {
        self.refresh_factor(false)?;
        let wish = self.to_free(dx0);
        let y = self.linear.solve(&self.linear.apply(&wish));
        let jacobian = self.linear.jacobian();
        let mut per_family: Vec<(Family, Vec<f64>)> = Vec::new();
        let mut strongest: Option<(f64, Family, Element)> = None;
        for (row, entries) in jacobian.outer_iterator().enumerate() {
            let (family, element) = self.factored[row];
            let norm = entries.iter().map(|(_, v)| v * v).sum::<f64>().sqrt();
            let weight = y[row].abs() * norm;
            if strongest.is_none_or(|(w, _, _)| weight > w) {
                strongest = Some((weight, family, element));
            }
            let slot = match per_family.iter().position(|(f, _)| *f == family) {
                Some(k) => k,
                None => {
                    per_family.push((family, vec![0.0; wish.len()]));
                    per_family.len() - 1
                }
            };
            for (c, v) in entries.iter() {
                per_family[slot].1[c] += v * y[row];
            }
        }
        let total: Vec<f64> = (0..wish.len())
            .map(|c| per_family.iter().map(|(_, r)| r[c]).sum())
            .collect();
        let refused = total.iter().map(|v| v * v).sum::<f64>().sqrt();
        let wished = wish.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut by_family: Vec<(Family, f64)> = per_family
            .into_iter()
            .map(|(f, r)| (f, r.iter().map(|v| v * v).sum::<f64>().sqrt()))
            .collect();
        by_family.sort_by(|a, b| b.1.total_cmp(&a.1));
        Ok(match (strongest, by_family.first()) {
            (Some((w, _, _)), Some(&(family, _))) if w > 0.0 && wished > 0.0 => {
                // The element: the strongest row of the strongest family.
                let element = self
                    .factored
                    .iter()
                    .zip(jacobian.outer_iterator())
                    .zip(&y)
                    .filter(|(((f, _), _), _)| *f == family)
                    .map(|(((_, e), row), yi)| {
                        let norm = row.iter().map(|(_, v)| v * v).sum::<f64>().sqrt();
                        (yi.abs() * norm, *e)
                    })
                    .max_by(|a, b| a.0.total_cmp(&b.0))
                    .map(|(_, e)| e)
                    .expect("the family has rows");
                Some(Resistance {
                    family,
                    element,
                    refused: refused / wished,
                    by_family,
                })
            }
            _ => None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::ConstraintSet;
    use crate::generate::{generate, Params, PatternKind};
    use crate::solver::Options;

    #[test]
    fn a_stretch_is_refused_by_edge_lengths_and_a_rigid_motion_by_nothing() {
        let mut p = Params::defaults(PatternKind::Miura);
        p.nx = 3;
        p.ny = 3;
        let mesh = generate(&p).unwrap();
        let n = mesh.vertex_count();
        let x = mesh.positions().to_vec();
        let set = ConstraintSet::parse("edge-length").unwrap();
        let mut solver = Solver::new(mesh, set, &[], Options::default()).unwrap();
        // Growing the sheet about its middle: every edge longer, which lengths refuse (all
        // but what unfolding the Miura-ori, its one mechanism, can give).
        let c = x.iter().sum::<Vec3>() / n as f64;
        let stretch: Vec<Vec3> = x.iter().map(|p| 0.1 * (p - c)).collect();
        let r = solver.resisting(&stretch).unwrap().unwrap();
        assert_eq!(r.family, Family::EdgeLength);
        assert!(r.refused > 0.5, "{}", r.refused);
        // The refused part plus the kept part is the wish (eq. 10), and the kept part is
        // what null_space_step returns.
        let kept = solver.null_space_step(&stretch).unwrap();
        let kept_norm = kept.iter().map(|v| v.norm_squared()).sum::<f64>().sqrt();
        let wish_norm = stretch.iter().map(|v| v.norm_squared()).sum::<f64>().sqrt();
        let refused = r.refused * wish_norm;
        assert!(
            ((kept_norm.powi(2) + refused.powi(2)).sqrt() - wish_norm).abs() < 1e-6 * wish_norm
        );
        // A translation is a rigid motion: nothing refuses it.
        let shift = vec![Vec3::new(1.0, 2.0, 3.0); n];
        match solver.resisting(&shift).unwrap() {
            None => {}
            Some(r) => assert!(r.refused < 1e-9, "{}", r.refused),
        }
    }
}
