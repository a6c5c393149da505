//! `crease fold`: a pattern folded in simulation mode toward a fraction of its targets,
//! or (`--flat`) its flat-folded state with the layer order.

use super::{design_failure, progress_bar, Remedy};
use crease::fab::{flat_folded, layer_order, LayerOrder};
use crease::io;
use crease::mesh::{Mesh, Vec3};
use crease::pipeline::{run_design, DesignJob};
use crease::solver::Mode;
use std::path::PathBuf;

#[derive(clap::Args)]
// One of --amount and --flat, so that a fold without either names both.
#[command(group(clap::ArgGroup::new("how").required(true).args(["amount", "flat"])))]
pub struct FoldArgs {
    /// Pattern file.
    file: PathBuf,
    /// Fraction of each crease's target angle, in [0, 1]: every crease is driven toward
    /// it and the rigid panels let them reach it on average (as `generate --fold`).
    #[arg(long)]
    amount: Option<f64>,
    /// Write the flat-folded state instead: every ±180° crease folded completely, faces
    /// reflected through the creases into the plane, with the layer order as FOLD
    /// `faceOrders` (exit 1, naming the faces, when there is none).
    #[arg(long)]
    flat: bool,
    /// Write the folded state even when faces pass through each other in it.
    #[arg(long)]
    force: bool,
    /// Vertices held still, separated by spaces or commas (default: the face nearest the
    /// middle).
    #[arg(long, num_args = 1.., value_delimiter = ',')]
    fix: Vec<usize>,
    /// Output FOLD file.
    #[arg(short, long)]
    output: PathBuf,
}

pub fn fold(args: FoldArgs) -> Result<u8, String> {
    let FoldArgs {
        file,
        amount,
        flat,
        force,
        fix,
        output,
    } = args;
    let mesh = io::read(&file).map_err(|e| e.to_string())?;
    if flat {
        return fold_flat(mesh, &file, &output);
    }
    let amount = amount.expect("clap requires --amount without --flat");
    let mut job = DesignJob::new(mesh);
    job.fold = Some(amount);
    let fixed_given = !fix.is_empty();
    job.fold_fixed = fixed_given.then_some(fix);
    job.mode = Mode::Simulation;
    let outcome = match run_design(job, &mut progress_bar()) {
        Ok(o) => o,
        Err(e) => {
            let remedies = [
                Remedy::new("folding less far (a smaller --amount)", false),
                Remedy::new("holding other vertices (--fix)", fixed_given),
            ];
            return design_failure(e, &file, &remedies);
        }
    };
    // A fold that reached almost none of what was asked is a failure, not a file: a
    // pattern without folded creases, or one held flat by its --fix vertices.
    if let Some(f) = outcome
        .fold
        .as_ref()
        .filter(|f| amount > 0.0 && f.mean_fraction < 0.01 * amount)
    {
        eprintln!(
            "error: the fold got nowhere: {:.1}% of the target angles where {:.0}% was asked (no crease with a target to fold, or --fix holds it flat); nothing was written",
            100.0 * f.mean_fraction,
            100.0 * amount
        );
        return Ok(1);
    }
    // Rigid panels keep neighbours from swinging through each other (§2.4), not a sheet
    // rolled far enough to close through itself elsewhere: that state cannot be folded.
    let crossings = crease::fab::self_intersections(&outcome.mesh);
    if let (Some(first), false) = (crossings.first(), force) {
        eprintln!(
            "error: at this amount the sheet passes through itself: {} pairs of faces cross (faces {} and {} first); fold less, or --force to write it anyway; nothing was written",
            crossings.len(),
            first.faces.0,
            first.faces.1
        );
        return Ok(1);
    }
    io::write(&outcome.mesh, &output).map_err(|e| e.to_string())?;
    if let Some(f) = outcome.fold {
        eprintln!(
            "folded in {} steps to {:.1}% of the target angles on average (largest miss {:.3} rad); wrote {}",
            f.steps,
            100.0 * f.mean_fraction,
            f.error,
            output.display()
        );
    }
    Ok(0)
}

/// The flat-folded state as a FOLD folded form (z = 0, layers in `faceOrders`) beside
/// the crease pattern.
fn fold_flat(
    mut mesh: Mesh,
    file: &std::path::Path,
    output: &std::path::Path,
) -> Result<u8, String> {
    let name = file.display();
    // A pattern of unassigned creases folds flat with the sides a layer order gives them.
    let budget = crease::fab::Budget::search(crease::limits::DEFAULT_SEARCH_TIME);
    match crease::pipeline::with_sides_found(mesh, &budget) {
        Ok((assigned, note)) => {
            if let Some(note) = note {
                eprintln!("note: {name}: {note}");
            }
            mesh = assigned;
        }
        Err(e) => {
            eprintln!("error: {name}: {e}; nothing was written");
            return Ok(e.exit_code());
        }
    }
    let folded = flat_folded(&mesh, None).map_err(|e| format!("{name}: {e}"))?;
    let orders = match layer_order(&mesh).map_err(|e| format!("{name}: {e}"))? {
        LayerOrder::Found(orders) => orders,
        LayerOrder::Conflict(c) => {
            eprintln!("error: {name} has no layer order: {c}; nothing was written");
            return Ok(1);
        }
    };
    mesh.crease_pattern()
        .ok_or(format!("{name}: no crease pattern"))?;
    let positions = folded
        .vertex_images(mesh.faces(), mesh.vertex_count())
        .into_iter()
        .map(|p| Vec3::new(p.x, p.y, 0.0))
        .collect();
    mesh.set_positions(positions);
    // Folded flat, each crease that reaches ±π is at it and every other line is flat:
    // the file's angles describe the state it draws, not the design it came from.
    for edge in mesh.edges_mut() {
        let folded = crease::fab::layers::folds_completely(edge);
        edge.fold_angle = if folded { edge.target } else { 0.0 };
    }
    mesh.source = None;
    let text = io::fold::to_string_with_orders(&mesh, Some(&orders));
    io::write_atomic(output, text.as_bytes()).map_err(|e| e.to_string())?;
    eprintln!(
        "folded flat: {} faces, {} overlapping pairs ordered; wrote {}",
        mesh.faces().len(),
        orders.len(),
        output.display()
    );
    Ok(0)
}
