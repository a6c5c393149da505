//! What the machine receives: the sheet's lines scored, split over the front and the
//! back, routed, and written as the cutter's jobs and the sheet's drawings.

use super::layout::Laid;
use super::{FabError, FabOptions, Files};
use crate::fab::{Advice, FabOption};
use crate::mesh::Mesh;
use std::collections::BTreeMap;

/// The laid-out sheet scored and routed for the machine: the jobs it receives.
pub(super) struct Cut {
    pub(super) front: crate::fab::Toolpath,
    /// The mirrored back job, if asked for.
    pub(super) back: Option<crate::fab::Toolpath>,
    /// The cutter's job files (none for a tiled sheet).
    pub(super) jobs_written: Files,
    /// A two-sided job's steps for the maker, else empty.
    pub(super) steps: Vec<String>,
    /// Sheet lines of folds too short to score.
    pub(super) unscored: Vec<usize>,
    pub(super) short_folds: crate::fab::ShortFolds,
}

/// Scores the sheet's lines, splits them over the front and back, routes them and
/// writes the cutter's jobs.
pub(super) fn cut_sheet(
    laid: &Laid,
    machine: &crate::machine::Machine,
    options: &FabOptions,
) -> Result<Cut, FabError> {
    let settings = machine.score_settings();
    let (strokes, unscored) = crate::fab::score_lines(&laid.sheet, &settings);
    check_stroke_count(strokes.len())?;
    let tools = machine.hpgl_settings().tools;
    // Two-sided jobs register by crosses, unless tiled (no machine takes the sheet).
    let registered = options.mountains_from_back && !laid.tiled;
    let (front, back) = sides(
        strokes,
        &laid.sheet.media,
        laid.margin,
        &tools,
        options,
        registered,
    );
    // A tiled sheet is larger than the media: a cutter cannot take it, only pages print.
    let jobs_written = if laid.tiled {
        Vec::new()
    } else {
        let frame = laid.print.as_ref().and_then(|p| p.frame.as_ref());
        cutter_jobs(machine, &front, back.as_ref(), frame)?
    };
    let steps = two_sided_steps(registered, &jobs_written);
    Ok(Cut {
        front,
        back,
        jobs_written,
        steps,
        unscored,
        short_folds: settings.short_folds,
    })
}

/// The drawings and jobs of a run: the sheet's SVG (Design Space's print-then-cut image
/// for a Cricut), DXF, the cutter's jobs and the crease pattern's files.
pub(super) fn job_files(
    mesh: &Mesh,
    laid: &Laid,
    cut: &Cut,
    machine: &crate::machine::Machine,
    options: &FabOptions,
) -> Result<Files, FabError> {
    let mut files = sheet_files(
        &cut.front,
        cut.back.as_ref(),
        &cut.jobs_written,
        svg_layers(machine),
    );
    let family = laid.print.as_ref().map(|p| p.family);
    if family == Some(crate::fab::print_and_cut::MarkFamily::Cricut) {
        // Design Space's print-then-cut file: the image to print with the cut and scores.
        files[0].1 = crate::output::svg::print_then_cut_to_string(
            &cut.front,
            &laid.sheet,
            mesh.faces(),
            options.print_fill,
        )
        .into_bytes();
    }
    files.extend(pattern_files(mesh, &laid.sheet)?);
    Ok(files)
}

/// The sheet would need `count` strokes: more than a job may have is refused, saying
/// what to change.
fn check_stroke_count(count: usize) -> Result<(), FabError> {
    if crate::limits::STROKES
        .check_count("strokes", count as u64)
        .is_err()
    {
        return Err(FabError::Input(
            Advice::text(format!(
                "the sheet would need {} strokes, more than {} a job may have: use a smaller ",
                crate::limits::short(count as f64),
                crate::limits::STROKES.max
            ))
            .option(FabOption::Width)
            .then(" or ")
            .option(FabOption::Media)
            .then(", or a longer dash in the machine's profile"),
        ));
    }
    Ok(())
}

/// A machine driven by its design software (Cricut) takes sheet.svg as its job, layered
/// by operation; the others get a layer per line kind.
fn svg_layers(machine: &crate::machine::Machine) -> crate::output::svg::Layers {
    if machine.protocol == crate::machine::Protocol::Svg {
        crate::output::svg::Layers::ByOperation
    } else {
        crate::output::svg::Layers::ByKind
    }
}

/// A two-sided job's steps for the maker (see [`crate::fab::registration::steps`]),
/// naming the cutter's files, or for a laser its SVG and DXF; nothing for one side.
fn two_sided_steps(two_sided: bool, jobs_written: &[(String, Vec<u8>)]) -> Vec<String> {
    if !two_sided {
        return Vec::new();
    }
    let (front, back) = match jobs_written {
        [f, b] => (f.0.as_str(), b.0.as_str()),
        _ => (
            "sheet.svg (or sheet.dxf)",
            "sheet-back.svg (or sheet-back.dxf)",
        ),
    };
    crate::fab::registration::steps(front, back)
}

/// The jobs as files: sheet.svg, the cutter's job, sheet.dxf, then the back job's.
fn sheet_files(
    front: &crate::fab::Toolpath,
    back: Option<&crate::fab::Toolpath>,
    jobs_written: &[(String, Vec<u8>)],
    layers: crate::output::svg::Layers,
) -> Files {
    use crate::output::{dxf, svg};
    let mut files = vec![(
        "sheet.svg".to_string(),
        svg::sheet_to_string(front, layers).into_bytes(),
    )];
    files.extend(jobs_written.iter().take(1).cloned());
    files.push(("sheet.dxf".to_string(), dxf::to_string(front).into_bytes()));
    files.extend(jobs_written.iter().skip(1).cloned());
    if let Some(b) = back {
        files.push((
            "sheet-back.svg".to_string(),
            svg::sheet_to_string(b, layers).into_bytes(),
        ));
        files.push(("sheet-back.dxf".to_string(), dxf::to_string(b).into_bytes()));
    }
    files
}

/// The crease pattern as laid out on the sheet, as SVG and as FOLD (with the layer order
/// of a flat-folding pattern).
fn pattern_files(mesh: &Mesh, sheet: &crate::fab::Sheet) -> Result<Files, FabError> {
    let mut placed = mesh.clone();
    placed.set_crease_pattern(sheet.vertices.clone());
    let cp = crate::io::to_string(&placed, crate::io::Format::Svg).map_err(FabError::input)?;
    let orders = layer_order_of(mesh, &placed);
    Ok(vec![
        ("crease-pattern.svg".to_string(), cp.into_bytes()),
        (
            "crease-pattern.fold".to_string(),
            crate::io::fold::to_string_with_orders(&placed, orders.as_deref()).into_bytes(),
        ),
    ])
}

/// The layer order FOLD tools expect beside a crease pattern that folds flat (every crease
/// ±180° and no 3D form): `faceOrders` of the laid-out faces, or nothing.
fn layer_order_of(design: &Mesh, placed: &Mesh) -> Option<Vec<[i64; 3]>> {
    if design.has_3d() || crate::fab::layers::partial_crease(design).is_some() {
        return None;
    }
    match crate::fab::layer_order(placed) {
        Ok(crate::fab::LayerOrder::Found(orders)) => Some(orders),
        _ => None,
    }
}

/// The front job and, for a two-sided run, the mirrored back job. Two-sided: the front
/// scores the valleys, the back the mountains and then the outline, so the piece stays in
/// the sheet until both sides are scored; each job starts with the registration crosses
/// ([`crate::fab::registration`]) when `registered`.
fn sides(
    strokes: Vec<crate::fab::Stroke>,
    media: &crate::fab::Media,
    margin: f64,
    tools: &BTreeMap<crate::fab::LineKind, crate::fab::ToolSetting>,
    options: &FabOptions,
    registered: bool,
) -> (crate::fab::Toolpath, Option<crate::fab::Toolpath>) {
    use crate::fab::{registration, route_with, LineKind, Toolpath};
    let (front, back): (Vec<_>, Vec<_>) = strokes.into_iter().partition(|s| {
        !(options.mountains_from_back && matches!(s.kind, LineKind::Mountain | LineKind::Cut))
    });
    let marks = |centres: [crate::mesh::Vec2; 3]| {
        if registered {
            registration::cross_strokes(&centres)
        } else {
            Vec::new()
        }
    };
    let mut front_strokes = marks(registration::front_centres(media, margin));
    front_strokes.extend(route_with(&front, tools, options.route));
    let front = Toolpath {
        media: media.clone(),
        strokes: front_strokes,
    };
    let back = options.mountains_from_back.then(|| {
        let mirrored: Vec<_> = back
            .iter()
            .map(|s| s.mapped(|p| registration::mirrored(media.width, p)))
            .collect();
        let mut strokes = marks(registration::back_centres(media, margin));
        strokes.extend(route_with(&mirrored, tools, options.route));
        Toolpath {
            media: media.clone(),
            strokes,
        }
    });
    (front, back)
}

/// The cutter's own job (sheet.hpgl or sheet.gpgl, and its `-back` twin for a two-sided
/// job) in the machine's protocol; nothing for a laser, which takes sheet.dxf or sheet.svg.
fn cutter_jobs(
    machine: &crate::machine::Machine,
    front: &crate::fab::Toolpath,
    back: Option<&crate::fab::Toolpath>,
    marks: Option<&crate::fab::print_and_cut::MarkFrame>,
) -> Result<Files, FabError> {
    let mut gpgl = machine.gpgl_settings();
    gpgl.registration = marks.map(|m| crate::output::gpgl::Registration {
        origin: m.origin,
        size: m.size,
    });
    let mut files = Vec::new();
    for (side, path) in [("sheet", Some(front)), ("sheet-back", back)] {
        let (Some(path), Some(name)) = (path, machine.job_file(side)) else {
            continue;
        };
        let text = match machine.protocol {
            crate::machine::Protocol::Gpgl => crate::output::gpgl::to_string(path, &gpgl),
            _ => crate::output::hpgl::to_string(path, &machine.hpgl_settings()),
        }
        .map_err(FabError::input)?;
        files.push((name, text.into_bytes()));
    }
    Ok(files)
}
