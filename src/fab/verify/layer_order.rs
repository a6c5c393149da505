//! The layer-order family: the flat-folded state's layer order judged, or the proof
//! that a tube's strip does not close, or the faces that admit no order.

use super::report::{summarise, FamilyReport};
use crate::constraints::Element;
use crate::fab::budget::Budget;
use crate::mesh::Mesh;

/// The layer-order problem's cap (bytes, as [`crate::fab::budget::layer_bytes`] counts
/// them) when only reported, for a freeform 3D design.
const FREEFORM_LAYER_CAP: usize = 300_000_000;

/// The time the freeform report may take within a deadline (the studio's live analysis).
const FREEFORM_LIVE: std::time::Duration = std::time::Duration::from_millis(150);

/// Layer order of the flat-folded state ([`crate::fab::layers`]), judged when every crease
/// folds to ±π and the faces close up around every vertex (else the local conditions
/// already say why it cannot fold flat): one row, failing with the faces in conflict.
pub(super) fn layer_order_report(
    mesh: &Mesh,
    budget: &Budget,
    freeform: bool,
    only_reported: bool,
    claimed: bool,
) -> Option<FamilyReport> {
    use crate::fab::layers::{
        layer_order_naming_within, LayerError, LayerOrder, ADVISORY_SHRINK_WORK, SHRINK_WORK,
    };
    let folded = crate::fab::flat_folded(mesh, None).ok()?;
    let closes = folded.layers_close();
    let creases = mesh.edges().iter().any(|e| e.assignment.is_folded());
    if !creases {
        return None;
    }
    // Faces that do not close up leave no flat-folded state to order. The local
    // conditions usually fail there and say why; where they hold within the drawing's
    // allowances, nothing about the layers was shown, and a claim to fold flat is
    // undecided, not passed.
    if !closes && folded.open_seam {
        return Some(open_tube_report(&folded, only_reported));
    }
    if !closes {
        let why = format!(
            "folded flat, the faces around vertex {} leave a gap of {:.1e} mm, past the {:.1e} mm \
             the drawing explains: there is no flat-folded state to order",
            folded.worst_vertex.unwrap_or(0),
            folded.mismatch,
            folded.tolerance
        );
        let undecided = (!only_reported && !freeform).then(|| why.clone());
        return Some(unjudged(format!("not judged: {why}"), undecided));
    }
    // A pattern drawn at partial folds (Origami Simulator's 90°) does not claim to fold
    // flat: reported, not judged, as Maekawa there. A freeform design's creases stand
    // at partial folds by design; its targets (all ±π, or there is no flat state) are
    // its claim.
    if let Some(e) = crate::fab::layers::partial_crease(mesh).filter(|_| !freeform) {
        let edge = &mesh.edges()[e];
        let why = format!(
            "crease {e} is drawn at {:.0}°, a partial fold: the pattern does not say it folds flat",
            crate::io::fold::angle_to_fold(edge.fold_angle)
        );
        let undecided = claimed.then(|| why.clone());
        return Some(unjudged(format!("not judged: {why}"), undecided));
    }
    let reported = reported_budget(budget);
    let (budget, naming) = if only_reported {
        (&reported, ADVISORY_SHRINK_WORK)
    } else {
        (budget, SHRINK_WORK)
    };
    let mut report = match layer_order_naming_within(mesh, budget, naming) {
        Ok(LayerOrder::Found(orders)) => FamilyReport {
            rows: orders.len(),
            ..summarise("layer-order", &[], 0.0)
        },
        Ok(LayerOrder::Conflict(c)) => conflict_report(&c),
        Err(LayerError::OverBudget(e)) => unjudged(
            format!("not judged: {e}"),
            (!only_reported).then(|| e.to_string()),
        ),
        // The search stopped, or the folded state could not be set up: nothing was
        // shown either way, so a claim of folding flat is left undecided.
        Err(e) => {
            let why = format!("not decided: {e}");
            unjudged(why.clone(), (!only_reported).then_some(why))
        }
    };
    if report.basis.is_empty() {
        report.basis = "one order of every overlapping pair of faces once folded flat, or the faces that admit none".into();
    }
    if only_reported {
        report.gating = false;
        report.basis = format!(
            "{}; the crease pattern folded flat, reported: a freeform design folds to its own form",
            report.basis
        );
    }
    Some(report)
}

/// The layer-order row of a state that was not judged: `basis` says why for the table,
/// `undecided` why the verdict is left undecided (when the design claims to fold flat).
fn unjudged(basis: String, undecided: Option<String>) -> FamilyReport {
    FamilyReport {
        gating: false,
        basis,
        undecided,
        ..summarise("layer-order", &[], 0.0)
    }
}

/// The budget of a layer order only reported, not gating (a freeform design's): at most
/// [`FREEFORM_LAYER_CAP`], and under a deadline (the studio's) at most [`FREEFORM_LIVE`]
/// of it, so verifying a large 3D design costs little more than it did before its flat
/// state was judged and the studio's verdict is not held up by it.
fn reported_budget(budget: &Budget) -> Budget {
    let now = std::time::Instant::now();
    Budget {
        max_layer_bytes: budget.max_layer_bytes.min(FREEFORM_LAYER_CAP),
        // Only a live analysis (one that can be cancelled: the studio's) holds the
        // report to FREEFORM_LIVE; the command line's deadline stands as given.
        deadline: budget.deadline.map(|(at, given)| match budget.cancel {
            Some(_) => (at.min(now + FREEFORM_LIVE), given.min(FREEFORM_LIVE)),
            None => (at, given),
        }),
        ..budget.clone()
    }
}

/// The failing layer-order row of a tube whose seam does not close once folded flat: the
/// reflections of the creases round the tube do not compose to the identity, so no flat
/// state exists (a proof, not a search), though every vertex may fold flat on its own.
fn open_tube_report(folded: &crate::fab::FlatFolded, only_reported: bool) -> FamilyReport {
    let vertex = folded.worst_vertex.unwrap_or(0);
    let mut r = summarise(
        "layer-order",
        &[(folded.mismatch, Element::Vertex(vertex))],
        folded.tolerance,
    );
    r.violators = vec![format!(
        "folded flat, the tube does not close: its seam's two sides land {:.3} mm apart at vertex \
         {vertex}, though every vertex folds flat on its own",
        folded.mismatch
    )];
    r.basis = format!(
        "the tube's strip folded flat closes round the tube within {:.1e} mm",
        folded.tolerance
    );
    r.gating = !only_reported;
    r
}

/// The failing layer-order row of faces that admit no order.
pub(super) fn conflict_report(c: &crate::fab::layers::LayerConflict) -> FamilyReport {
    let faces = &c.faces;
    let element = Element::Faces(faces[0], *faces.get(1).unwrap_or(&faces[0]));
    let mut r = summarise("layer-order", &[(1.0, element)], 0.0);
    r.measured = false;
    let names: Vec<String> = faces.iter().map(|f| f.to_string()).collect();
    // A vertex of 2,000 creases names 2,000 faces: the table shows the first few.
    r.worst = Some(if names.len() > 12 {
        format!(
            "faces {}, … ({} in all)",
            names[..12].join(", "),
            names.len()
        )
    } else {
        format!("faces {}", names.join(", "))
    });
    r.violators = vec![c.to_string()];
    r.basis =
        "one order of every overlapping pair of faces once folded flat, or the faces that admit none"
            .into();
    r
}
