//! `crease fold`: a pattern folded in simulation mode toward a fraction of its targets,
//! or (`--flat`) its flat-folded state with the layer order.

use super::{design_failure, progress_bar, Remedy};
use crease::io;
use crease::mesh::Mesh;
use crease::pipeline::{run_design, DesignJob, FoldRefusal};
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
    /// The layer search's time and memory (with --flat).
    #[command(flatten)]
    search: super::SearchArgs,
}

pub fn fold(args: FoldArgs) -> Result<u8, String> {
    let FoldArgs {
        file,
        amount,
        flat,
        force,
        fix,
        output,
        search,
    } = args;
    let (time, memory) = search.checked()?;
    let mesh = io::read(&file).map_err(|e| e.to_string())?;
    if flat {
        let budget = crease::fab::Budget::search(time, memory);
        return fold_flat(mesh, &file, &output, &budget);
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
    match crease::pipeline::fold_refusal(&outcome, amount) {
        Some(why @ FoldRefusal::GotNowhere { .. }) => {
            eprintln!("error: {why} (no crease with a target to fold, or --fix holds it flat); nothing was written");
            return Ok(1);
        }
        Some(why @ FoldRefusal::PassesThrough { .. }) if !force => {
            eprintln!(
                "error: {why}; fold less, or --force to write it anyway; nothing was written"
            );
            return Ok(1);
        }
        _ => {}
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
/// the crease pattern ([`crease::pipeline::flat_folded_file`]).
fn fold_flat(
    mesh: Mesh,
    file: &std::path::Path,
    output: &std::path::Path,
    budget: &crease::fab::Budget,
) -> Result<u8, String> {
    let name = file.display();
    let flat = match crease::pipeline::flat_folded_file(mesh, budget) {
        Ok(flat) => flat,
        Err(e) => {
            eprintln!("error: {name}: {e}; nothing was written");
            return Ok(e.exit_code());
        }
    };
    if let Some(note) = &flat.note {
        eprintln!("note: {name}: {note}");
    }
    let text = io::fold::to_string_with_orders(&flat.mesh, Some(&flat.orders));
    io::write_atomic(output, text.as_bytes()).map_err(|e| e.to_string())?;
    eprintln!(
        "folded flat: {} faces, {} overlapping pairs ordered; wrote {}",
        flat.mesh.faces().len(),
        flat.orders.len(),
        output.display()
    );
    Ok(0)
}
