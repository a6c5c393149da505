//! Fabrication: verify → unfold → lay out → score → route → SVG, PDF, HP-GL, report.

use crate::fab::unfold;
use crate::mesh::Mesh;
use std::collections::BTreeMap;

/// Options of a fabrication run.
#[derive(Clone, Debug, Default)]
pub struct FabOptions {
    /// Media; default the machine's.
    pub media: Option<crate::fab::Media>,
    /// Scale the pattern so the laid-out sheet is this wide (mm).
    pub width: Option<f64>,
    /// Scale the pattern to the largest size the media takes within its margins.
    pub fit: bool,
    /// Margin kept free on every side (mm); default the machine's.
    pub margin: Option<f64>,
    /// Fabricate even if verification fails.
    pub force: bool,
    /// Score mountains from the back: a second, mirrored job.
    pub mountains_from_back: bool,
    /// When the pattern does not fit the media, split the PDF over pages instead of
    /// refusing (no cutter job is written then).
    pub tile: bool,
}

/// Narrowest sheet `--width` may ask for, mm: a cutter's step is 0.025–0.05 mm, and a
/// pattern much smaller than this leaves strokes that round to nothing.
pub const MIN_WIDTH_MM: f64 = 5.0;

/// Overlap between tiled PDF pages (mm).
pub const TILE_OVERLAP_MM: f64 = 10.0;

/// Everything a fabrication run produced, ready to write.
pub struct FabOutput {
    /// File name and bytes, in writing order.
    pub files: Vec<(String, Vec<u8>)>,
    /// The report written as report.json.
    pub report: serde_json::Value,
    /// The summary's line on the cutter job (as on the PDF): its size and time, or why
    /// there is none.
    pub job_line: String,
    /// What the maker must do by hand (as on the PDF), e.g. folds too short to score.
    pub warnings: Vec<String>,
    /// For a two-sided job, what the maker does in order: which job first, how to turn
    /// the sheet, how to check the registration (as on the PDF's second page).
    pub steps: Vec<String>,
    /// The verification report.
    pub verification: crate::fab::Report,
    /// The placed sheet.
    pub sheet: crate::fab::Sheet,
    /// The front job's toolpath.
    pub toolpath: crate::fab::Toolpath,
    /// The mirrored back job, if asked for.
    pub back: Option<crate::fab::Toolpath>,
    /// Largest relative edge-length difference between the sheet and the 3D design.
    pub isometry_error: f64,
}

/// Why fabrication stopped: the design fails verification, does not fit, overlaps itself.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Rejected(pub String);

/// Verify → unfold → lay out → score → route → SVG, PDF, HP-GL and a report (§ the
/// fabrication half of the brief). Nothing is written here; see [`crate::io::write_all_atomic`].
pub fn fabricate(
    mesh: &Mesh,
    machine: &crate::plotter::Machine,
    options: &FabOptions,
) -> Result<FabOutput, FabError> {
    use crate::fab::{
        check_overlap, crease_lines, layout, score_lines, verify, LayoutError, Media, Sizing,
        Tolerances, Toolpath,
    };
    if let Some(w) = options.width {
        if !(w.is_finite() && w >= MIN_WIDTH_MM) {
            return Err(FabError::Input(format!(
                "--width {w}: a sheet must be at least {MIN_WIDTH_MM} mm wide to be cut (below that every stroke is shorter than the machine's step)"
            )));
        }
    }
    let verification = verify(mesh, None, Tolerances::default());
    if !verification.pass() && !options.force {
        return Err(FabError::Rejected(Rejected(format!(
            "the design fails verification (use --force to cut it anyway):\n{verification}"
        ))));
    }
    let flat = if mesh.has_3d() {
        unfold(mesh).map_err(|e| FabError::Rejected(Rejected(e.to_string())))?
    } else {
        mesh.flat()
            .map(<[_]>::to_vec)
            .unwrap_or_else(|| mesh.positions().iter().map(|p| p.xy()).collect())
    };
    let isometry_error = mesh
        .edges()
        .iter()
        .map(|e| {
            let [a, b] = e.vertices;
            let l3 = (mesh.positions()[a] - mesh.positions()[b]).norm();
            ((flat[a] - flat[b]).norm() - l3).abs() / l3
        })
        .fold(0.0, f64::max);
    check_overlap(mesh.faces(), &flat).map_err(|e| FabError::Rejected(Rejected(e.to_string())))?;
    let media = match &options.media {
        Some(m) => m.clone(),
        None => Media::parse(&machine.media).map_err(FabError::Input)?,
    };
    let lines = crease_lines(mesh, &flat);
    let mut tiled = false;
    let margin = options.margin.unwrap_or(machine.margin_mm);
    let sizing = match (options.fit, options.width) {
        (true, Some(_)) => {
            return Err(FabError::Input(
                "--fit and --width both size the sheet: give one".into(),
            ))
        }
        (true, None) => Sizing::Fit,
        (false, Some(w)) => Sizing::Width(w),
        (false, None) => Sizing::Natural,
    };
    // A two-sided job keeps a band inside the margin for its registration crosses.
    let band = if options.mountains_from_back {
        crate::fab::registration::MARK_BAND_MM
    } else {
        0.0
    };
    let sheet = match layout(&flat, &lines, &media, margin + band, sizing) {
        Ok(s) => s,
        Err(LayoutError::TooLarge { .. }) if options.tile => {
            // Turned for the fewest pages, on a virtual sheet just large enough; the PDF
            // is tiled below.
            tiled = true;
            crate::fab::layout::layout_tiled(&flat, &lines, &media, margin, TILE_OVERLAP_MM, sizing)
                .map_err(|e| FabError::Input(e.to_string()))?
        }
        Err(e @ LayoutError::TooLarge { .. }) => {
            let why = if band > 0.0 {
                format!(" (a two-sided job keeps {band} mm more inside the margin for its registration crosses)")
            } else {
                String::new()
            };
            return Err(FabError::Rejected(Rejected(format!("{e}{why}"))));
        }
        Err(LayoutError::Bad(m)) => return Err(FabError::Input(m)),
    };
    let page = media.clone();
    let media = sheet.media.clone();
    let settings = machine.score_settings();
    let (strokes, unscored) = score_lines(&sheet, &settings);
    let tools = machine.hpgl_settings().tools;
    let (toolpath, back) = sides(strokes, &media, margin, &tools, options, tiled);
    // A tiled sheet is larger than the media: a cutter cannot take it, only pages print.
    let jobs_written = if tiled {
        Vec::new()
    } else {
        cutter_jobs(machine, &toolpath, back.as_ref())?
    };
    let job_bytes: usize = jobs_written.iter().map(|(_, b)| b.len()).sum();
    let mut files = vec![(
        "sheet.svg".to_string(),
        crate::output::svg::sheet_to_string(&toolpath).into_bytes(),
    )];
    files.extend(jobs_written.iter().take(1).cloned());
    files.push((
        "sheet.dxf".to_string(),
        crate::output::dxf::to_string(&toolpath).into_bytes(),
    ));
    files.extend(jobs_written.iter().skip(1).cloned());
    if let Some(b) = &back {
        files.push((
            "sheet-back.svg".to_string(),
            crate::output::svg::sheet_to_string(b).into_bytes(),
        ));
        files.push((
            "sheet-back.dxf".to_string(),
            crate::output::dxf::to_string(b).into_bytes(),
        ));
    }
    let steps = match (&back, tiled) {
        (Some(_), false) => {
            let (front_file, back_file) = match jobs_written.as_slice() {
                [f, b] => (f.0.as_str(), b.0.as_str()),
                _ => (
                    "sheet.svg (or sheet.dxf)",
                    "sheet-back.svg (or sheet-back.dxf)",
                ),
            };
            crate::fab::registration::steps(front_file, back_file)
        }
        _ => Vec::new(),
    };
    let mut placed = mesh.clone();
    placed.set_flat(sheet.vertices.clone());
    let cp = crate::io::to_string(&placed, crate::io::Format::Svg).map_err(FabError::Input)?;
    files.push(("crease-pattern.svg".to_string(), cp.into_bytes()));
    files.push((
        "crease-pattern.fold".to_string(),
        crate::io::fold::to_string_with_orders(&placed, layer_order_of(mesh, &placed).as_deref())
            .into_bytes(),
    ));

    // Figures for the report.
    let mut line_length: BTreeMap<&str, f64> = BTreeMap::new();
    for l in &sheet.lines {
        *line_length.entry(l.kind.name()).or_default() += l.length();
    }
    let jobs: Vec<&Toolpath> = std::iter::once(&toolpath).chain(back.as_ref()).collect();
    let mut cut_length: BTreeMap<&str, f64> = BTreeMap::new();
    let mut motion = 0.0;
    let mut travel = 0.0;
    for job in &jobs {
        for (k, len) in job.cut_length() {
            *cut_length.entry(k.name()).or_default() += len;
            motion += len / machine.speed(k);
        }
        travel += job.travel();
    }
    motion += travel / machine.pen_up_speed_mm_s;
    let line = machine.serial_line();
    let transfer = line
        .as_ref()
        .map_or(0.0, |l| job_bytes as f64 * 10.0 / l.baud as f64);
    let estimate = motion.max(transfer);
    let sheet_json = serde_json::json!({
        "machine": machine.name,
        // What `crease plot` needs to stream this job to the machine it was made for.
        "plotter": line.as_ref().filter(|_| !jobs_written.is_empty()).map(|l| serde_json::json!({
            "protocol": machine.protocol,
            "baud": l.baud,
            "flow_control": l.flow_control,
            "buffer_bytes": l.buffer_bytes,
        })),
        "media": {"name": media.name, "width_mm": media.width, "height_mm": media.height},
        "size_mm": sheet.size,
        "scale": sheet.scale,
        "rotation_deg": sheet.rotation.to_degrees(),
        "line_length_mm": line_length,
        "cut_length_mm": cut_length,
        "strokes": jobs.iter().map(|j| j.strokes.len()).sum::<usize>(),
        "pen_up_travel_mm": travel,
        "job_files": jobs_written.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>(),
        "job_bytes": job_bytes,
        "estimated_plot_time_s": estimate,
        "motion_time_s": motion,
        "transfer_time_s": transfer,
        "isometry_max_relative_error": isometry_error,
        "mountains_from_back": options.mountains_from_back,
        // How the two sides register: the crosses each job cuts first, and what to do.
        "two_sided": (!steps.is_empty()).then(|| serde_json::json!({
            "front_marks_mm": crate::fab::registration::front_centres(&media, margin).map(|p| [p.x, p.y]),
            "back_marks_mm": crate::fab::registration::back_centres(&media, margin).map(|p| [p.x, p.y]),
            "steps": steps,
        })),
        "tiled": tiled,
        // Folds with no room for a dash (shorter than the clearance the junctions at
        // their ends need), and what the profile's `short_folds` gave them: with
        // "nothing" the maker has to score these by hand.
        "unscored_creases": unscored.iter().map(|&i| {
            let l = &sheet.lines[i];
            serde_json::json!({
                "given": settings.short_folds.name(),
                "kind": l.kind.name(),
                "length_mm": l.length(),
                "from_mm": [l.a.x, l.a.y],
                "to_mm": [l.b.x, l.b.y],
            })
        }).collect::<Vec<_>>(),
    });
    let report = serde_json::json!({"verification": verification.to_json(), "sheet": sheet_json});
    let title = if mesh.title.is_empty() {
        "crease pattern".to_string()
    } else {
        mesh.title.clone()
    };
    let job_line = job_summary(
        &jobs_written,
        cut_length.values().sum(),
        travel,
        estimate,
        tiled,
    );
    let warnings = unscored_warning(&sheet, &unscored, settings.short_folds)
        .into_iter()
        .collect::<Vec<_>>();
    let mut summary =
        vec![
            format!(
            "{} on {} ({:.0} x {:.0} mm), pattern {:.1} x {:.1} mm at scale {:.3}; verification {}",
            machine.name,
            media.name,
            media.width,
            media.height,
            sheet.size[0],
            sheet.size[1],
            sheet.scale,
            if verification.pass() { "passed" } else { "FAILED (forced)" }
        ),
            job_line.clone(),
        ];
    if !steps.is_empty() {
        summary.push(
            "two-sided: the front job first, then turn the sheet over left to right; page 2 says how".into(),
        );
    }
    summary.extend(warnings.iter().cloned());
    let pdf = if tiled {
        crate::output::pdf::to_bytes_tiled(&sheet, &page, margin, TILE_OVERLAP_MM, &title, &summary)
    } else if !steps.is_empty() {
        let marks = crate::fab::registration::front_centres(&media, margin);
        crate::output::pdf::to_bytes_two_sided(&sheet, &title, &summary, &marks, &steps)
    } else {
        crate::output::pdf::to_bytes(&sheet, &title, &summary)
    };
    files.push(("sheet.pdf".to_string(), pdf));
    files.push((
        "report.json".to_string(),
        (serde_json::to_string_pretty(&report).expect("json") + "\n").into_bytes(),
    ));
    Ok(FabOutput {
        files,
        report,
        job_line,
        warnings,
        steps,
        verification,
        sheet,
        toolpath,
        back,
        isometry_error,
    })
}

/// Why fabrication failed: bad input (exit 2) or a design that cannot be made as asked
/// (exit 1).
#[derive(Debug, thiserror::Error)]
pub enum FabError {
    /// Bad option or profile.
    #[error("{0}")]
    Input(String),
    /// The design was refused.
    #[error(transparent)]
    Rejected(#[from] Rejected),
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
/// ([`crate::fab::registration`]) unless the sheet is tiled (no machine takes it).
fn sides(
    strokes: Vec<crate::fab::Stroke>,
    media: &crate::fab::Media,
    margin: f64,
    tools: &BTreeMap<crate::fab::LineKind, crate::output::ToolSetting>,
    options: &FabOptions,
    tiled: bool,
) -> (crate::fab::Toolpath, Option<crate::fab::Toolpath>) {
    use crate::fab::{registration, route, LineKind, Toolpath};
    let (front, back): (Vec<_>, Vec<_>) = strokes.into_iter().partition(|s| {
        !(options.mountains_from_back && matches!(s.kind, LineKind::Mountain | LineKind::Cut))
    });
    let marks = |centres: [crate::mesh::Vec2; 3]| {
        if options.mountains_from_back && !tiled {
            registration::cross_strokes(&centres)
        } else {
            Vec::new()
        }
    };
    let mut front_strokes = marks(registration::front_centres(media, margin));
    front_strokes.extend(route(&front, tools));
    let front = Toolpath {
        media: media.clone(),
        strokes: front_strokes,
    };
    let back = options.mountains_from_back.then(|| {
        let mirrored: Vec<_> = back
            .iter()
            .map(|s| crate::fab::Stroke {
                from: registration::mirrored(media.width, s.from),
                to: registration::mirrored(media.width, s.to),
                ..*s
            })
            .collect();
        let mut strokes = marks(registration::back_centres(media, margin));
        strokes.extend(route(&mirrored, tools));
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
    machine: &crate::plotter::Machine,
    front: &crate::fab::Toolpath,
    back: Option<&crate::fab::Toolpath>,
) -> Result<Vec<(String, Vec<u8>)>, FabError> {
    let mut files = Vec::new();
    for (side, path) in [("sheet", Some(front)), ("sheet-back", back)] {
        let (Some(path), Some(name)) = (path, machine.job_file(side)) else {
            continue;
        };
        let text = match machine.protocol.as_str() {
            "gpgl" => crate::output::gpgl::to_string(path, &machine.gpgl_settings()),
            _ => crate::output::hpgl::to_string(path, &machine.hpgl_settings()),
        }
        .map_err(FabError::Input)?;
        files.push((name, text.into_bytes()));
    }
    Ok(files)
}

/// The summary's line on the cutter job: its size and time, or why there is none.
fn job_summary(
    jobs: &[(String, Vec<u8>)],
    cut_mm: f64,
    travel_mm: f64,
    seconds: f64,
    tiled: bool,
) -> String {
    if tiled {
        return format!(
            "cut {cut_mm:.0} mm; tiled over pages to print and cut by hand, so no cutter job"
        );
    }
    if jobs.is_empty() {
        return format!(
            "cut {cut_mm:.0} mm, pen-up travel {travel_mm:.0} mm, about {seconds:.0} s of motion; no cutter job: sheet.dxf or sheet.svg goes to the laser's software"
        );
    }
    let names: Vec<&str> = jobs.iter().map(|(n, _)| n.as_str()).collect();
    let bytes: usize = jobs.iter().map(|(_, b)| b.len()).sum();
    format!(
        "cut {cut_mm:.0} mm, pen-up travel {travel_mm:.0} mm, {bytes} bytes in {}, about {seconds:.0} s to plot",
        names.join(" and ")
    )
}

/// The note naming folds too short to score, if there are any, and what they got.
fn unscored_warning(
    sheet: &crate::fab::Sheet,
    unscored: &[usize],
    given: crate::fab::ShortFolds,
) -> Option<String> {
    if unscored.is_empty() {
        return None;
    }
    let lengths: Vec<String> = unscored
        .iter()
        .map(|&i| {
            format!(
                "{} {:.1} mm",
                sheet.lines[i].kind.name(),
                sheet.lines[i].length()
            )
        })
        .collect();
    let what = match given {
        crate::fab::ShortFolds::Nothing => "crease by hand".to_string(),
        other => format!("given {} (the profile's short_folds)", other.name()),
    };
    Some(format!(
        "{} fold(s) too short to score, {what}: {} (report.json has their ends)",
        unscored.len(),
        lengths.join(", ")
    ))
}

/// Every file a fabrication run can write, and the journals `plot` keeps beside the jobs.
pub const OUTPUT_FILES: [&str; 16] = [
    "sheet.svg",
    "sheet.hpgl",
    "sheet.gpgl",
    "sheet.dxf",
    "sheet-back.hpgl",
    "sheet-back.gpgl",
    "sheet-back.svg",
    "sheet-back.dxf",
    "crease-pattern.svg",
    "crease-pattern.fold",
    "sheet.pdf",
    "report.json",
    "sheet.hpgl.journal",
    "sheet-back.hpgl.journal",
    "sheet.gpgl.journal",
    "sheet-back.gpgl.journal",
];

/// Files an earlier run left in `dir` that this run's `written` files do not replace (a
/// back job the new run has none of, with its journal; a sheet.hpgl when the machine now
/// takes sheet.gpgl): removed once
/// the new files are in, so the folder holds one run, never a mix of two.
pub fn remove_stale_outputs(dir: &std::path::Path, written: &[(String, Vec<u8>)]) -> Vec<String> {
    let mut removed = Vec::new();
    for name in OUTPUT_FILES {
        // A journal stays while its job is written again: for the same bytes it still
        // resumes, for others its hash tells `plot` it is not theirs.
        let owner = name.strip_suffix(".journal").unwrap_or(name);
        let fresh = written.iter().any(|(n, _)| n == owner);
        if !fresh && dir.join(name).is_file() && std::fs::remove_file(dir.join(name)).is_ok() {
            removed.push(name.to_string());
        }
    }
    removed
}
