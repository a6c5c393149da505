//! The folding motion in the studio (issue 49): the design folded from flat along the
//! path `verify --path` checks ([`crate::pipeline::fold_motion`]), kept until the design
//! changes, sent to the page to play and written as a file to download.

use super::{MotionRequest, Refusal, Reply, Session};
use crate::pipeline::{fold_motion, motion_files, MotionFormat};
use std::path::Path;

/// Steps of a motion the page plays unless asked otherwise: as `crease animate`'s, four
/// seconds at 15 frames a second.
pub const PLAYED_FRAMES: usize = 60;

/// Most vertex positions the page is sent for a motion (frames × vertices): about 27 MB
/// of JSON; a larger design is sent fewer frames.
pub const MAX_PLAYED_POSITIONS: usize = 1_000_000;

impl Session {
    /// `POST /api/motion`: folds the design from flat (or takes the motion kept for it)
    /// and sends every frame.
    pub(super) fn motion(&mut self, r: MotionRequest) -> Result<Reply, Refusal> {
        let n = self.design.mesh.vertex_count().max(1);
        let most = (MAX_PLAYED_POSITIONS / n).saturating_sub(1);
        let steps = match r.frames {
            Some(f) => {
                crate::limits::FRAMES
                    .check_count("frames", f as u64)
                    .map_err(|e| Refusal::bad(e.to_string()))?;
                if f > most {
                    return Err(Refusal::bad(format!(
                        "frames {f}: {} frames of {n} vertices is more than the page is sent ({MAX_PLAYED_POSITIONS} positions); ask for {} or fewer",
                        f + 1,
                        most.max(1)
                    )));
                }
                f
            }
            None => PLAYED_FRAMES.min(most).max(1),
        };
        let motion = self.kept_motion(steps)?;
        let value = super::super::frame::motion_value(motion);
        let summary = value["summary"].as_str().unwrap_or_default();
        self.message = summary.lines().next().unwrap_or_default().to_string();
        Ok(Reply::Json(value))
    }

    /// `GET /api/motion/export?format=`: the motion kept (or [`PLAYED_FRAMES`] steps of
    /// it, folded now) as a `.glb`, `.fold` or animated `.png` named after the design.
    pub(super) fn motion_file(&mut self, format: &str) -> Result<Reply, Refusal> {
        let name = crate::pipeline::names::motion_file(&self.title, format);
        let kind = MotionFormat::of(Path::new(&name)).map_err(|_| {
            Refusal::bad(format!(
                "format \"{}\": the studio exports a motion as glb, fold or png",
                crate::limits::short_text(format)
            ))
        })?;
        if kind == MotionFormat::Gltf {
            return Err(Refusal::bad(
                "format \"gltf\" is two files (.gltf and .bin): export glb, the same in one file",
            ));
        }
        let steps = self
            .motion
            .as_ref()
            .map_or(PLAYED_FRAMES, |m| m.frames.len() - 1);
        let motion = self.kept_motion(steps)?;
        let mut files =
            motion_files(motion, Path::new(&name)).map_err(|e| Refusal::failed(e.to_string()))?;
        let (_, bytes) = files.pop().expect("one file for glb, fold and png");
        Ok(Reply::File { name, bytes })
    }

    /// The motion of the design as it is now in `steps` steps, folded unless kept.
    fn kept_motion(&mut self, steps: usize) -> Result<&crate::pipeline::Motion, Refusal> {
        let kept = self.motion.as_ref().is_some_and(|m| {
            m.frames.len() == steps + 1 || m.report.as_ref().is_ok_and(|r| r.of == steps)
        });
        if !kept {
            let design = self.finished()?;
            let motion = fold_motion(&design, steps, &mut |_, _, _| {}).map_err(|e| {
                if e.is_input_error() {
                    Refusal::bad(e.to_string())
                } else {
                    Refusal::failed(format!("the folding motion: {e}"))
                }
            })?;
            self.motion = Some(motion);
        }
        Ok(self.motion.as_ref().expect("just kept"))
    }
}
