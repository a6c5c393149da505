//! `crease animate`: the folding motion from the flat sheet to the design, written as
//! glTF, a multi-frame FOLD or an animated PNG (issue 49).

use super::out;
use crease::{io, pipeline};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct AnimateArgs {
    /// Design file (.fold, .cp, .opx, .svg, .obj; a 3D-only form is unfolded, a tube
    /// cut open along its seam).
    file: PathBuf,
    /// Output, its format chosen by extension: .glb or .gltf (glTF 2.0, with a .bin
    /// beside a .gltf), .fold (frame 0 the crease pattern, the motion's states after it),
    /// .png (an animated PNG).
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,
    /// Steps from flat to the design; the motion has these frames and the flat sheet.
    #[arg(long, default_value_t = 60, value_name = "N")]
    frames: usize,
    /// Go on from the design to the flat-folded state (every mountain and valley crease
    /// at 180°) in half as many steps again, checked for faces passing through each other.
    #[arg(long)]
    flat: bool,
}

/// `crease animate`: writes the motion as far as it goes; exit 0 when the path is clear,
/// 1 when faces pass through each other (the motion ends there), 3 when it stops short
/// of the design or the solver cannot follow it (as `verify --path`).
pub fn animate(args: AnimateArgs) -> Result<u8, String> {
    pipeline::MotionFormat::of(&args.output).map_err(|e| e.to_string())?;
    let imported = io::read_with_notes(&args.file).map_err(|e| e.to_string())?;
    for note in &imported.notes {
        eprintln!("note: {note}");
    }
    let flat_steps = if args.flat {
        args.frames.div_ceil(2)
    } else {
        0
    };
    let motion = pipeline::fold_motion_on(
        &imported.mesh,
        args.frames,
        flat_steps,
        &mut super::progress_bar(),
    )
    .map_err(|e| e.to_string())?;
    for (path, bytes) in pipeline::motion_files(&motion, &args.output).map_err(|e| e.to_string())? {
        io::write_atomic(&path, &bytes).map_err(|e| e.to_string())?;
        out(&format!(
            "wrote {} ({} bytes)\n",
            path.display(),
            bytes.len()
        ));
    }
    out(&format!("{}\n", motion.summary()));
    Ok(motion.exit_code())
}
