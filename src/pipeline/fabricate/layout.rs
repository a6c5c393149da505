//! Laying a design out: unfolded (a tube as its strip with a glue tab), placed on its
//! media or in a print-and-cut frame at the size asked, tiled when larger than the media,
//! and checked to be cuttable by the machine.

use super::{FabError, FabOptions};
use super::{Rejected, TILE_OVERLAP_MM};
use crate::fab::{Advice, FabOption};
use crate::geometry::unfold::{crease_pattern_of, PatternFrom};
use crate::mesh::Mesh;
use crate::pipeline::tube::TubeStrip;

/// The sheet laid out: the design unfolded and placed on its media or print-and-cut
/// frame, checked to be cuttable.
pub(super) struct Laid {
    pub(super) isometry_error: f64,
    /// The media, as given or the machine's.
    pub(super) page: crate::fab::Media,
    pub(super) margin: f64,
    pub(super) print: Option<crate::fab::print_and_cut::PrintLayout>,
    pub(super) sheet: crate::fab::Sheet,
    /// The sheet is larger than the media and tiled over pages.
    pub(super) tiled: bool,
    /// A tube's seam pairing on the sheet.
    pub(super) seam: Option<crate::pipeline::report_json::SeamReport>,
}

/// Unfolds `mesh` (a tube's strip when `tube` is given) and lays it out for `machine`.
pub(super) fn lay_out_sheet(
    mesh: &Mesh,
    tube: Option<&TubeStrip>,
    machine: &crate::machine::Machine,
    options: &FabOptions,
    sizing: crate::fab::Sizing,
) -> Result<Laid, FabError> {
    let (flat, isometry_error) = flatten(mesh)?;
    let page = match &options.media {
        Some(m) => m.clone(),
        None => crate::fab::Media::parse(&machine.media).map_err(FabError::input)?,
    };
    let margin = options.margin.unwrap_or(machine.margin_mm);
    let print = print_layout(machine, options)?;
    let placing = Placing {
        print: print.as_ref(),
        page: &page,
        margin,
        sizing,
        options,
    };
    let (sheet, tiled) = sheet_of(mesh, &flat, tube, &placing)?;
    // After the layout, whose refusal (media too small) is cheap: on a face of thousands
    // of corners this check is the slow part.
    crate::geometry::unfold::check_overlap(mesh.faces(), &flat)
        .map_err(|e| FabError::rejected(e.to_string()))?;
    let seam = tube.map(|t| t.report(&sheet.vertices));
    check_cuttable(&sheet, machine)?;
    Ok(Laid {
        isometry_error,
        page,
        margin,
        print,
        sheet,
        tiled,
        seam,
    })
}

/// A tube's strip with its glue tab `--tab` wide (range-checked here), `None` for a sheet.
pub(super) fn tube_of(mesh: &Mesh, options: &FabOptions) -> Result<Option<TubeStrip>, FabError> {
    let tab_mm = crate::limits::LENGTH
        .check(
            "tab",
            options
                .tab
                .unwrap_or(crate::pipeline::fab_options::GLUE_TAB_MM),
        )
        .map_err(|e| FabError::Input(Advice::out_of_range(FabOption::Tab, &e)))?;
    let strip = crate::pipeline::tube::tube_strip(mesh, tab_mm).map_err(FabError::rejected)?;
    // A tab asked for on a sheet would be silently dropped: say so instead.
    if strip.is_none() && options.tab.is_some() {
        return Err(FabError::Input(
            Advice::text("")
                .option(FabOption::Tab)
                .then(": the design is a sheet, not a tube, so it has no seam to glue; leave ")
                .option(FabOption::Tab)
                .then(" out"),
        ));
    }
    Ok(strip)
}

/// Where a sheet goes: a print-and-cut frame, else the media within the margin.
struct Placing<'a> {
    print: Option<&'a crate::fab::print_and_cut::PrintLayout>,
    page: &'a crate::fab::Media,
    margin: f64,
    sizing: crate::fab::Sizing,
    options: &'a FabOptions,
}

/// The design's lines laid out as `at` says (a tube's strip with its glue tab and seam
/// numbers), and whether the sheet is tiled over pages.
fn sheet_of(
    mesh: &Mesh,
    flat: &[crate::mesh::Vec2],
    tube: Option<&TubeStrip>,
    at: &Placing,
) -> Result<(crate::fab::Sheet, bool), FabError> {
    let mut lines = crate::fab::crease_lines(mesh, flat);
    // The layout places the points it is given: the tab's corners reach past the strip,
    // and a curved outline bulges past the vertices it runs through (its cubics' control
    // points hold it).
    let mut extent = flat.to_vec();
    extent.extend(
        lines
            .iter()
            .filter(|l| l.kind == crate::fab::LineKind::Cut)
            .filter_map(|l| l.curve.as_ref())
            .flat_map(|c| c.pieces().iter().flat_map(|p| [p.c1, p.c2])),
    );
    if let Some(t) = tube {
        let (tab, with) = t.tab(flat, lines).map_err(FabError::rejected)?;
        lines = with;
        extent.extend(tab.outline);
    }
    let (mut sheet, tiled) = match at.print {
        Some(p) => (
            p.place(&extent, &lines, at.sizing)
                .map_err(FabError::rejected)?,
            false,
        ),
        None => lay_out(&extent, &lines, at.page, at.margin, at.sizing, at.options)?,
    };
    sheet.vertices.truncate(flat.len());
    if let Some(t) = tube {
        sheet.labels = t.labels(&sheet.vertices, sheet.scale, &sheet.lines);
    }
    Ok((sheet, tiled))
}

/// A sheet the machine can cut: at least [`MIN_STEPS_ACROSS`] of its steps across, else
/// every stroke would round to a point or nothing on the job.
fn check_cuttable(
    sheet: &crate::fab::Sheet,
    machine: &crate::machine::Machine,
) -> Result<(), FabError> {
    let across = sheet.size[0].max(sheet.size[1]);
    let step = 1.0 / machine.units_per_mm;
    // NaN (a degenerate sheet) is refused too.
    if across.is_nan() || across < MIN_STEPS_ACROSS * step {
        return Err(FabError::Input(
            Advice::text(format!(
                "the design is {} mm across, under {MIN_STEPS_ACROSS} of the machine's {} mm steps: nothing on it could be cut; scale it with ",
                crate::limits::short(across),
                crate::limits::short(step)
            ))
            .option(FabOption::Width)
            .then(" or ")
            .option(FabOption::Fit),
        ));
    }
    Ok(())
}

/// The fewest machine steps a design may span and still be cut.
const MIN_STEPS_ACROSS: f64 = 20.0;

/// How the options size the sheet; a width too small to cut, or both `--fit` and
/// `--width`, is refused.
pub(super) fn sizing_of(options: &FabOptions) -> Result<crate::fab::Sizing, FabError> {
    use crate::fab::Sizing;
    if let Some(w) = options.width {
        // Below the range's 5 mm every stroke is shorter than a blade's dash.
        crate::limits::SHEET_WIDTH
            .check("width", w)
            .map_err(|e| FabError::Input(Advice::out_of_range(FabOption::Width, &e)))?;
    }
    match (options.fit, options.width) {
        (true, Some(_)) => Err(FabError::Input(
            Advice::text("")
                .option(FabOption::Fit)
                .then(" and ")
                .option(FabOption::Width)
                .then(" both size the sheet: give one"),
        )),
        (true, None) => Ok(Sizing::Fit),
        (false, Some(w)) => Ok(Sizing::Width(w)),
        (false, None) => Ok(Sizing::Natural),
    }
}

/// The design's flat state (unfolded if it has a 3D form) and the largest relative
/// edge-length difference between it and the design; a sheet that overlaps itself is
/// refused.
fn flatten(mesh: &Mesh) -> Result<(Vec<crate::mesh::Vec2>, f64), FabError> {
    // The sheet must fold into exactly the 3D form that was verified.
    let flat = crease_pattern_of(mesh, PatternFrom::Form)
        .map_err(|e| FabError::rejected(e.to_string()))?
        .into_owned();
    let isometry_error = crate::geometry::unfold::isometry_error(mesh, &flat);
    Ok((flat, isometry_error))
}

/// The sheet placed on `media` within `margin` (and, two-sided, the registration band
/// inside it), or tiled on a virtual sheet when it does not fit and `--tile` asks for it;
/// `true` when tiled.
fn lay_out(
    flat: &[crate::mesh::Vec2],
    lines: &[crate::fab::CreaseLine],
    media: &crate::fab::Media,
    margin: f64,
    sizing: crate::fab::Sizing,
    options: &FabOptions,
) -> Result<(crate::fab::Sheet, bool), FabError> {
    use crate::fab::{layout, LayoutError};
    // A two-sided job keeps a band inside the margin for its registration crosses.
    let band = if options.mountains_from_back {
        crate::fab::registration::MARK_BAND_MM
    } else {
        0.0
    };
    match layout(flat, lines, media, margin + band, sizing) {
        Ok(s) => Ok((s, false)),
        // Turned for the fewest pages, on a virtual sheet just large enough; the PDF is
        // tiled.
        Err(LayoutError::TooLarge { .. }) if options.tile => {
            // Each page keeps a band for its label, scale bar and legend.
            let margin = margin.max(crate::output::pdf::TILE_MARGIN_MM);
            crate::fab::layout::layout_tiled(flat, lines, media, margin, TILE_OVERLAP_MM, sizing)
                .map(|s| (s, true))
                .map_err(FabError::Layout)
        }
        Err(e @ LayoutError::TooLarge { .. }) => {
            let why = if band > 0.0 {
                format!(" (a two-sided job keeps {band} mm more inside the margin for its registration crosses)")
            } else {
                String::new()
            };
            Err(FabError::Rejected(Rejected(e.advice().then(why))))
        }
        Err(e) => Err(FabError::Layout(e)),
    }
}

/// Where a print-and-cut run lays the sheet out, if `--print-and-cut` asks for one: the
/// machine's marks on the media asked for (default a4 for Silhouette, letter for Cricut).
/// A machine that finds no marks, or a run also two-sided or tiled, is refused.
fn print_layout(
    machine: &crate::machine::Machine,
    options: &FabOptions,
) -> Result<Option<crate::fab::print_and_cut::PrintLayout>, FabError> {
    use crate::fab::print_and_cut::{MarkFamily, PrintLayout};
    if !options.print_and_cut {
        return Ok(None);
    }
    let family = machine.print_and_cut.ok_or_else(|| {
        FabError::Input(
            Advice::text(format!(
                "{} finds no print-and-cut marks (its profile has no print_and_cut key): use ",
                machine.name
            ))
            .option(FabOption::Machine)
            .then(" silhouette-cameo or cricut-maker"),
        )
    })?;
    if options.mountains_from_back || options.tile {
        return Err(FabError::Input(
            Advice::text("")
                .option(FabOption::PrintAndCut)
                .then(" cuts one printed side in one piece: leave out ")
                .option(FabOption::MountainsFromBack)
                .then(" and ")
                .option(FabOption::Tile),
        ));
    }
    let page = match &options.media {
        Some(m) => m.clone(),
        None => crate::fab::Media::parse(match family {
            MarkFamily::Silhouette => "a4",
            MarkFamily::Cricut => "letter",
        })
        .map_err(FabError::input)?,
    };
    PrintLayout::new(family, &page)
        .map(Some)
        .map_err(FabError::input)
}
