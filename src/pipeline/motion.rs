//! The folding motion from the flat sheet to the design, kept frame by frame (issue 49):
//! the path `verify --path` checks ([`super::path`]), every state it reaches, placed so
//! that its last frame lies on the design, with how far the panels bend on the way.
//!
//! The frames are what [`crate::output::gltf`], the multi-frame FOLD and the animated
//! preview write; nothing here formats bytes.

use super::path::{foldable_sheet, on_to_flat, walk, PathReport};
use super::{PipelineError, Progress};
use crate::fit::kabsch;
use crate::geometry::out_of_plane;
use crate::mesh::{Assignment, Mesh, UnionFind, Vec3};
use crate::output::gltf::{self, MotionFrames};
use crate::output::png;
use std::path::{Path, PathBuf};

/// How many states a motion may keep: frames × vertices (24 bytes each), 480 MB at most.
pub const MAX_FRAME_VERTICES: usize = 20_000_000;

/// A panel bends less than this (mm, out of its plane) on a rigid path: the solver's
/// residual in lengths and angles leaves panels flat to far better than a micrometre.
pub const RIGID_PANEL_MM: f64 = 1e-3;

/// The folding motion of a design.
#[derive(Clone, Debug)]
pub struct Motion {
    /// The sheet the frames move: the design with its crease pattern (a tube's strip,
    /// a 3D-only form's unfolding; see [`foldable_sheet`]), at the design's 3D form.
    pub sheet: Mesh,
    /// Every vertex's position in each frame (mm). Frame 0 is the flat sheet; on a clear
    /// path the last is the design's own positions. All frames share one rigid placement,
    /// the one that lays the path's last state on the design.
    pub frames: Vec<Vec<Vec3>>,
    /// What the path found (clear, where faces first cross, or short of the design), or
    /// why the solver stopped (the frames end where it did).
    pub report: Result<PathReport, String>,
    /// The most any panel bends out of its plane over the motion.
    pub bending: PanelBending,
    /// When asked to go on to the flat-folded state ([`fold_motion_on`]): the first
    /// collision on the way (the frames end there), none when it folds flat, or why the
    /// solver stopped.
    pub flat: Option<Result<Option<super::PathCollision>, String>>,
}

/// The largest out-of-plane deviation of a panel (faces joined by flat lines) over a
/// motion: zero for a rigid-foldable path.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PanelBending {
    /// The largest distance of a panel's vertex from the panel's least-squares plane (mm).
    pub deviation_mm: f64,
    /// A face of that panel.
    pub face: usize,
    /// The frame where it is largest.
    pub frame: usize,
}

impl PanelBending {
    /// Every panel stays flat (to [`RIGID_PANEL_MM`]).
    pub fn is_rigid(&self) -> bool {
        self.deviation_mm <= RIGID_PANEL_MM
    }
}

impl std::fmt::Display for PanelBending {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.is_rigid() {
            let d = self.deviation_mm.max(0.0);
            let mm = if d == 0.0 {
                "0".to_string()
            } else {
                format!("{d:.0e}")
            };
            write!(
                f,
                "rigid-foldable: every panel stays flat along the path (out of its plane by {mm} mm at most)"
            )
        } else {
            write!(
                f,
                "not rigid-foldable: the paper bends {:.2} mm out of its plane in the panel of face {} (frame {})",
                self.deviation_mm, self.face, self.frame
            )
        }
    }
}

/// The folding motion of `design` from flat in `steps` even steps (frames `0..=steps`),
/// ending early where faces first cross.
pub fn fold_motion(
    design: &Mesh,
    steps: usize,
    progress: Progress,
) -> Result<Motion, PipelineError> {
    fold_motion_on(design, steps, 0, progress)
}

/// [`fold_motion`], then, when its path is clear and `flat_steps` is not 0, on from the
/// design to the flat-folded state (every mountain and valley crease at ±180°) in
/// `flat_steps` more steps (`animate --flat`); [`Motion::flat`] says how that went.
pub fn fold_motion_on(
    design: &Mesh,
    steps: usize,
    flat_steps: usize,
    progress: Progress,
) -> Result<Motion, PipelineError> {
    crate::limits::FRAMES.check_count("--frames", steps as u64)?;
    let kept = (steps + flat_steps + 1).saturating_mul(design.vertex_count());
    if kept > MAX_FRAME_VERTICES {
        return Err(PipelineError::Input(format!(
            "--frames {steps}: {} frames of {} vertices is more than crease keeps ({} vertex positions); ask for fewer frames",
            steps + flat_steps + 1,
            design.vertex_count(),
            MAX_FRAME_VERTICES
        )));
    }
    let design = foldable_sheet(design)?.into_owned();
    let mut frames = Vec::with_capacity(steps + 1);
    let walked = walk(&design, steps, progress, &mut |fraction, x| {
        if fraction == 0.0 {
            // The path starts again from flat (with bending panels).
            frames.clear();
        }
        frames.push(x.to_vec());
    });
    let report = walked.map_err(|e| format!("the solver stopped: {e}"));
    let clear = report.as_ref().is_ok_and(PathReport::is_clear);
    let design_frame = frames.len() - 1;
    let mut flat = None;
    if clear && flat_steps > 0 {
        let at_design = frames[design_frame].clone();
        let on = on_to_flat(&design, &at_design, flat_steps, progress, &mut |x| {
            frames.push(x.to_vec());
        });
        flat = Some(on.map_err(|e| format!("the solver stopped: {e}")));
    }
    let last = &frames[design_frame];
    if clear && design.has_3d() {
        let placement = kabsch(last, design.positions());
        for frame in &mut frames {
            for p in frame.iter_mut() {
                *p = placement.apply(*p);
            }
        }
    }
    let bending = panel_bending(&design, &frames);
    Ok(Motion {
        sheet: design,
        frames,
        report,
        bending,
        flat,
    })
}

impl Motion {
    /// The exit status `crease animate` gives, as `verify --path`'s: 0 clear, 1 faces
    /// pass through each other, 3 short of the design or the solver stopped.
    /// With [`Motion::flat`], the way on to the flat-folded state counts the same.
    pub fn exit_code(&self) -> u8 {
        match (&self.report, &self.flat) {
            (Ok(r), None | Some(Ok(None))) if r.is_clear() => 0,
            (Ok(r), _) if r.collision.is_some() => 1,
            (Ok(_), Some(Ok(Some(_)))) => 1,
            _ => 3,
        }
    }

    /// What the motion shows, one line each: the path and the panels.
    pub fn summary(&self) -> String {
        let mut path = match &self.report {
            Ok(r) => r.to_string(),
            Err(why) => format!("path from flat: UNDECIDED — {why}"),
        };
        match &self.flat {
            None => {}
            Some(Ok(None)) => path.push_str(
                "\non to flat: folded flat (every mountain and valley at 180°), no faces passing through each other",
            ),
            Some(Ok(Some(c))) => path.push_str(&format!(
                "\non to flat: faces {} and {} pass through each other ({:.2} mm deep) at step {} ({:.0}% of the way to flat)",
                c.faces.0,
                c.faces.1,
                c.depth,
                c.step,
                100.0 * c.fraction
            )),
            Some(Err(why)) => path.push_str(&format!("\non to flat: UNDECIDED — {why}")),
        }
        format!(
            "{path}\n{}\nframes: {} (the flat sheet and {} steps)",
            self.bending,
            self.frames.len(),
            self.frames.len().saturating_sub(1)
        )
    }
}

/// The file formats a motion is written in, by the output's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionFormat {
    /// Binary glTF 2.0.
    Glb,
    /// glTF 2.0 text with its buffer in a `.bin` beside it.
    Gltf,
    /// Multi-frame FOLD: frame 0 the crease pattern, the states after it.
    Fold,
    /// Animated PNG.
    Png,
}

impl MotionFormat {
    /// The format `path`'s extension names.
    pub fn of(path: &Path) -> Result<MotionFormat, PipelineError> {
        match crate::io::extension_of(path).as_str() {
            "glb" => Ok(MotionFormat::Glb),
            "gltf" => Ok(MotionFormat::Gltf),
            "fold" => Ok(MotionFormat::Fold),
            "png" => Ok(MotionFormat::Png),
            _ => Err(PipelineError::Input(format!(
                "{}: a motion is written as .glb, .gltf, .fold or .png (animated); give one of these extensions",
                path.display()
            ))),
        }
    }
}

/// The files that hold `motion` at `path` (a `.gltf` has its `.bin` beside it, written
/// first), each with its bytes.
pub fn motion_files(
    motion: &Motion,
    path: &Path,
) -> Result<Vec<(PathBuf, Vec<u8>)>, PipelineError> {
    let frames = MotionFrames {
        sheet: &motion.sheet,
        frames: &motion.frames,
    };
    let failed = |e: String| PipelineError::Input(format!("{}: {e}", path.display()));
    Ok(match MotionFormat::of(path)? {
        MotionFormat::Glb => vec![(path.to_path_buf(), gltf::glb(&frames).map_err(failed)?)],
        MotionFormat::Gltf => {
            let bin = path.with_extension("bin");
            let name = bin
                .file_name()
                .and_then(|n| n.to_str())
                .ok_or_else(|| failed("the name is not UTF-8".into()))?
                .to_string();
            let (text, bytes) = gltf::gltf(&frames, &name).map_err(failed)?;
            vec![(bin, bytes), (path.to_path_buf(), text.into_bytes())]
        }
        MotionFormat::Fold => vec![(
            path.to_path_buf(),
            crate::io::fold::motion_to_string(&motion.sheet, &motion.frames).into_bytes(),
        )],
        MotionFormat::Png => vec![(
            path.to_path_buf(),
            png::motion(&motion.sheet, &motion.frames).map_err(failed)?,
        )],
    })
}

/// The panels of `mesh`: its faces grouped across flat lines (the triangulation of a
/// polygon, a flat crease), each as its vertices and one face.
pub fn panels(mesh: &Mesh) -> Vec<(usize, Vec<usize>)> {
    let topo = mesh.topology();
    let mut groups = UnionFind::new(mesh.faces().len());
    for (e, edge) in mesh.edges().iter().enumerate() {
        if edge.assignment == Assignment::Flat {
            if let [Some(f), Some(g)] = topo.edge_faces[e] {
                groups.union(f, g);
            }
        }
    }
    let mut by_root: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for (f, tri) in mesh.faces().iter().enumerate() {
        by_root.entry(groups.find(f)).or_default().extend(tri);
    }
    by_root
        .into_iter()
        .filter_map(|(face, mut vertices)| {
            vertices.sort_unstable();
            vertices.dedup();
            (vertices.len() > 3).then_some((face, vertices))
        })
        .collect()
}

/// The most any panel of `mesh` leaves its least-squares plane over `frames`.
fn panel_bending(mesh: &Mesh, frames: &[Vec<Vec3>]) -> PanelBending {
    let mut worst = PanelBending {
        deviation_mm: 0.0,
        face: 0,
        frame: 0,
    };
    for (face, vertices) in panels(mesh) {
        for (k, x) in frames.iter().enumerate() {
            let d = out_of_plane(vertices.iter().map(|&v| x[v]));
            if d > worst.deviation_mm {
                worst = PanelBending {
                    deviation_mm: d,
                    face,
                    frame: k,
                };
            }
        }
    }
    worst
}
