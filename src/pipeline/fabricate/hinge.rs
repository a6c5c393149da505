//! Living hinges: the gaps cut along the folds of a thick material
//! ([`crate::fab::hinge`]), the panel files, and their report.

use super::{FabError, Files};
use crate::mesh::Mesh;

/// The hinge gaps of a material that takes them ([`crate::fab::hinge`]); none on a tiled
/// sheet, which no machine cuts.
pub(super) fn hinge_of(
    mesh: &Mesh,
    sheet: &crate::fab::Sheet,
    machine: &crate::machine::Machine,
    tiled: bool,
) -> Result<Option<crate::fab::hinge::HingeGaps>, FabError> {
    match machine.hinge_thickness_mm {
        Some(h) if !tiled => crate::fab::hinge::hinge_gaps(mesh, sheet, h)
            .map(Some)
            .map_err(FabError::rejected),
        _ => Ok(None),
    }
}

/// `panels.svg` and `panels.dxf`: every panel's outline, set back from its folds, as a
/// cut on the sheet's media (the panels go back on the membrane where they were cut).
pub(super) fn panel_files(gaps: &crate::fab::hinge::HingeGaps, media: &crate::fab::Media) -> Files {
    use crate::fab::{LineKind, Stroke, Toolpath};
    let strokes = gaps
        .panels
        .iter()
        .enumerate()
        .flat_map(|(n, p)| {
            let k = p.outline.len();
            (0..k).map(move |i| Stroke {
                kind: LineKind::Cut,
                from: p.outline[i],
                to: p.outline[(i + 1) % k],
                line: n,
                bend: None,
            })
        })
        .collect();
    let path = Toolpath {
        media: media.clone(),
        strokes,
    };
    vec![
        (
            "panels.svg".to_string(),
            crate::output::svg::sheet_to_string(&path, crate::output::svg::Layers::ByKind)
                .into_bytes(),
        ),
        (
            "panels.dxf".to_string(),
            crate::output::dxf::to_string(&path).into_bytes(),
        ),
    ]
}

/// report.json's `hinge`: the formula, the thickness, each fold's angle and gap, the
/// panels, and the valleys folded too far for a gap.
pub(super) fn hinge_report(
    gaps: &crate::fab::hinge::HingeGaps,
    mesh: &Mesh,
) -> crate::pipeline::report_json::HingeReport {
    use crate::pipeline::report_json::{HingeFold, HingeReport};
    HingeReport {
        formula: "gap = 2 * thickness * tan(fold / 2) at every valley (panels on the front, membrane under them); mountains take none".to_string(),
        thickness_mm: gaps.thickness,
        largest_gap_fold_deg: crate::fab::hinge::MAX_GAP_FOLD.to_degrees(),
        panels: gaps.panels.len(),
        folds: gaps
            .folds
            .iter()
            .map(|&(e, rho, g)| HingeFold {
                edge: e,
                vertices: mesh.edges()[e].vertices,
                fold_deg: rho.to_degrees(),
                gap_mm: g,
            })
            .collect(),
        too_far: gaps.too_far.clone(),
    }
}

/// The warning for valleys folded past the largest fold a gap is laid out for.
pub(super) fn too_far_warning(gaps: &crate::fab::hinge::HingeGaps) -> Option<String> {
    (!gaps.too_far.is_empty()).then(|| {
        format!(
            "{} valley(s) fold past {:.0}°, beyond what a hinge gap in {} mm sheet allows without a gap over four times the thickness: they got that gap; fold them on a second hinge or use thinner sheet (report.json: hinge.too_far)",
            gaps.too_far.len(),
            crate::fab::hinge::MAX_GAP_FOLD.to_degrees(),
            gaps.thickness
        )
    })
}
