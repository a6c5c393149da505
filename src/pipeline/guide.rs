//! The folding motion a fabrication run draws: `motion.png` when asked (`fab --motion`)
//! and the folding guide that ends `sheet.pdf` ([`Guide`]), both from one motion, the
//! path `verify --path` checks.

use super::fab_options::{
    FabOptions, Guide, GUIDE_MAX_VERTICES, GUIDE_PICTURES, MOTION_PREVIEW_FRAMES,
};
use super::{fold_motion, FabError, Motion};
use crate::mesh::Mesh;
use crate::output::pdf::FoldingGuide;

/// What a run knows of the design's folding motion.
pub(super) struct RunMotion {
    /// The motion, when `motion.png` or the guide needs it.
    pub motion: Option<Motion>,
    /// Whether the guide is drawn from it (its path is clear).
    pub guide: bool,
    /// One line for the run's summary: the guide drawn, or why it is not. None when the
    /// design has no 3D form (nothing to fold) or the guide was turned off.
    pub guide_line: Option<String>,
}

/// The motion `options` ask for on `mesh` (see [`Guide`]). A path that is not clear
/// leaves the guide out and says why; it does not stop the run, whose verdict is
/// verification's.
pub(super) fn run_motion(mesh: &Mesh, options: &FabOptions) -> Result<RunMotion, FabError> {
    let n = mesh.vertex_count();
    let folded = mesh.has_3d();
    let guide_wanted = folded
        && match options.guide {
            Guide::Never => false,
            Guide::Always => true,
            Guide::Auto => n <= GUIDE_MAX_VERTICES,
        };
    let mut run = RunMotion {
        motion: None,
        guide: false,
        guide_line: (folded && options.guide == Guide::Auto && !guide_wanted).then(|| {
            format!(
                "sheet.pdf has no folding guide: the path from flat of a design of {n} vertices (over {GUIDE_MAX_VERTICES}) takes minutes; ask for it with --guide"
            )
        }),
    };
    if !options.motion && !guide_wanted {
        return Ok(run);
    }
    let motion = match fold_motion(mesh, MOTION_PREVIEW_FRAMES, &mut |_, _, _| {}) {
        Ok(m) => m,
        Err(e) if options.motion => return Err(FabError::input(format!("motion.png: {e}"))),
        Err(e) => {
            run.guide_line = Some(format!("sheet.pdf has no folding guide: {e}"));
            return Ok(run);
        }
    };
    if guide_wanted {
        let clear = motion.report.as_ref().is_ok_and(|r| r.is_clear());
        run.guide = clear;
        run.guide_line = Some(if clear {
            format!(
                "sheet.pdf ends with a folding guide: {GUIDE_PICTURES} pictures of the folding motion from the flat sheet to the design ({})",
                if motion.bending.is_rigid() {
                    "rigid-foldable".to_string()
                } else {
                    format!("the paper bends {:.2} mm on the way", motion.bending.deviation_mm)
                }
            )
        } else {
            let path = motion.summary();
            let first = path.lines().next().unwrap_or_default();
            format!("sheet.pdf has no folding guide, the path from flat is not clear: {first}")
        });
    }
    run.motion = Some(motion);
    Ok(run)
}

/// `motion.png` when `fab --motion` asked for it, and what the previews say of the
/// motion and the guide.
pub(super) fn motion_png(
    run: &RunMotion,
    options: &FabOptions,
    previews: &mut super::PreviewsReport,
) -> Result<Option<(String, Vec<u8>)>, FabError> {
    previews.guide.clone_from(&run.guide_line);
    let Some(m) = run.motion.as_ref().filter(|_| options.motion) else {
        return Ok(None);
    };
    let picture = crate::output::png::motion(&m.sheet, &m.frames).map_err(FabError::input)?;
    previews.motion = Some(m.summary());
    Ok(Some(("motion.png".to_string(), picture)))
}

/// The folding guide of a clear `motion`: [`GUIDE_PICTURES`] of its frames evenly along
/// the path, the flat sheet first and the design last, each captioned with how far it
/// is folded (every crease is driven in step, so k/n of the way is each crease at that
/// share of its design angle).
pub(super) fn folding_guide(motion: &Motion) -> FoldingGuide<'_> {
    let steps = motion.frames.len().saturating_sub(1);
    let pictures = GUIDE_PICTURES.min(steps + 1).max(1);
    let mut picked: Vec<usize> = (0..pictures)
        .map(|i| (i * steps + (pictures - 1) / 2) / (pictures - 1).max(1))
        .collect();
    picked.dedup();
    let frames = picked
        .into_iter()
        .map(|k| {
            let percent = 100.0 * k as f64 / steps.max(1) as f64;
            let caption = match k {
                0 => "the flat sheet (0%)".to_string(),
                k if k == steps => "the design (100%)".to_string(),
                _ => format!("{percent:.0}% folded"),
            };
            (motion.frames[k].as_slice(), caption)
        })
        .collect();
    FoldingGuide {
        sheet: &motion.sheet,
        frames,
        note: format!(
            "Folded from the flat sheet with every crease in step: each caption gives the share of its angle in the design that every crease has turned. Panels: {}.",
            motion.bending
        ),
    }
}
