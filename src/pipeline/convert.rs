//! `convert` as a job: what a design becomes when written in another format. A flat
//! format (SVG, `.cp`) draws a sheet, so a tube becomes its strip and a 3D-only design its
//! unfolding; a crease pattern that folds flat, written as FOLD, carries its layer order;
//! with `assign`, a pattern with unassigned creases is written with the sides a layer
//! order gives them.

use crate::fab::{Budget, LayerConflict, LayerError, LayerOrder, SideSearch};
use crate::geometry::unfold::{sheet_of, PatternFrom, UnfoldError};
use crate::io::Format;
use crate::mesh::Mesh;
use std::borrow::Cow;

/// What to write, and what changed on the way.
#[derive(Debug)]
pub struct Converted {
    /// The design as the output format takes it.
    pub mesh: Mesh,
    /// Its layer order (FOLD `faceOrders`), for a crease pattern that folds flat
    /// written as FOLD.
    pub face_orders: Option<Vec<[i64; 3]>>,
    /// Sentences for the user on what was changed.
    pub notes: Vec<String>,
}

/// Why a design could not be converted.
#[derive(Debug, thiserror::Error)]
pub enum ConvertError {
    /// A tube or 3D-only design written to a flat format that cannot be unfolded.
    #[error("{what}, and it cannot be unfolded: {cause}")]
    Unfold {
        /// What the design is.
        what: &'static str,
        /// Why unfolding failed.
        cause: UnfoldError,
    },
    /// Sides were asked for a design that has no unassigned creases to give them.
    #[error("it has no unassigned creases to assign (its creases already say mountain or valley, or it is a 3D design or folds partly, where unassigned lines are free)")]
    NothingToAssign,
    /// No mountain/valley of the unassigned creases folds flat.
    #[error(
        "no mountain/valley for its {open} unassigned creases gives a layer order: {conflict}"
    )]
    NoAssignment {
        /// The faces no assignment orders.
        conflict: LayerConflict,
        /// How many creases were unassigned.
        open: usize,
    },
    /// The search for the sides stopped before an answer.
    #[error("the search for its creases' sides stopped: {0}")]
    SearchStopped(LayerError),
}

impl ConvertError {
    /// Whether the design itself was judged (no assignment exists) rather than the
    /// question left open (the search stopped) or the input unfit (nothing to assign).
    pub fn exit_code(&self) -> u8 {
        match self {
            // No assignment exists, or (the search's own code) the faces do not close
            // up, a crease cannot fold: each answers the question.
            ConvertError::NoAssignment { .. } => 1,
            ConvertError::SearchStopped(e) => e.exit_code(),
            ConvertError::Unfold { .. } | ConvertError::NothingToAssign => 2,
        }
    }
}

/// A design as FOLD text with frame 0 its crease pattern and its 3D form in the frame
/// after it, as Origami Simulator, Rabbit Ear and ORIPA open it (`convert
/// --crease-pattern-first`); a 3D-only design is unfolded for it first.
pub fn crease_pattern_first(mesh: Mesh) -> Result<String, ConvertError> {
    let mesh = if mesh.is_tube() {
        mesh
    } else {
        into_sheet(mesh).map_err(unfold_3d_only)?
    };
    Ok(crate::io::fold::to_string_crease_pattern_first(&mesh))
}

/// `mesh` as the sheet it is made from ([`sheet_of`], the stored crease pattern kept):
/// itself when it has a crease pattern, a 3D-only design with its form unfolded, a tube
/// its strip.
pub fn into_sheet(mesh: Mesh) -> Result<Mesh, UnfoldError> {
    let made = match sheet_of(&mesh, PatternFrom::Stored)? {
        Cow::Owned(sheet) => Some(sheet),
        Cow::Borrowed(_) => None,
    };
    Ok(made.unwrap_or(mesh))
}

/// Why a 3D-only design could not be written with a crease pattern.
fn unfold_3d_only(cause: UnfoldError) -> ConvertError {
    ConvertError::Unfold {
        what: "a 3D-only design with no crease pattern",
        cause,
    }
}

/// `mesh` made ready to be written as `format`; with `assign`, its unassigned creases
/// given sides first (within `budget`).
pub fn convert(
    mut mesh: Mesh,
    format: Format,
    assign: bool,
    budget: &Budget,
) -> Result<Converted, ConvertError> {
    let mut notes = Vec::new();
    if assign {
        let (assigned, note) = with_sides_found(mesh, budget)?;
        notes.push(note.ok_or(ConvertError::NothingToAssign)?);
        mesh = assigned;
    }
    let flat_format = matches!(format, Format::Svg | Format::Cp);
    if flat_format {
        // A flat format draws a sheet: a tube's strip, its seam's sides cut lines.
        let (what, note) = match (mesh.is_tube(), mesh.crease_pattern()) {
            (true, _) => ("a tube", Some("it is a tube; the file draws the strip it is cut from (its seam's two sides are cut lines)")),
            (false, None) => ("a 3D-only design with no crease pattern", Some("it has only a 3D form; its crease pattern is the form unfolded")),
            (false, Some(_)) => ("", None),
        };
        mesh = into_sheet(mesh).map_err(|cause| ConvertError::Unfold { what, cause })?;
        notes.extend(note.map(String::from));
    }
    let claims_flat = crate::fab::layers::partial_crease(&mesh).is_none();
    let face_orders = if format == Format::Fold && !mesh.has_3d() && claims_flat {
        match crate::fab::layer_order_within(&mesh, budget) {
            Ok(LayerOrder::Found(orders)) => Some(orders),
            _ => None,
        }
    } else {
        None
    };
    Ok(Converted {
        mesh,
        face_orders,
        notes,
    })
}

/// What a pattern's unassigned creases became: the sentence `convert --assign` and
/// `fold --flat` say (`fab`'s report has `verify`'s).
pub(super) fn sides_given(mountains: usize, valleys: usize) -> String {
    format!(
        "its {} unassigned creases were given the sides of a layer order: {mountains} mountain(s), {valleys} valley(s)",
        mountains + valleys
    )
}

/// A crease pattern's unassigned creases with the sides of a layer order found for
/// them, and a sentence saying so; any other design unchanged, with no sentence. Errors
/// when no assignment folds flat or the search stops.
pub fn with_sides_found(
    mesh: Mesh,
    budget: &Budget,
) -> Result<(Mesh, Option<String>), ConvertError> {
    match crate::fab::assign_sides(&mesh, budget) {
        None => Ok((mesh, None)),
        Some(SideSearch::Found {
            mesh: assigned,
            mountains,
            valleys,
        }) => Ok((*assigned, Some(sides_given(mountains, valleys)))),
        Some(SideSearch::NoOrder { conflict, open }) => {
            Err(ConvertError::NoAssignment { conflict, open })
        }
        Some(SideSearch::Stopped(e)) => Err(ConvertError::SearchStopped(e)),
    }
}
