//! The sheet on the media: `--width` and `--fit` size the laid-out sheet within the
//! margins, a sheet too large is tiled over the fewest pages, and odd sizes neither panic
//! nor cut strokes shorter than the machine's step.

use crate::common;

use common::fabbing::{a3, output, patterns};
use common::run_crease;
use crease::fab::RouteSearch;
use crease::machine::Machine;
use crease::mesh::Vec2;
use crease::pipeline::{fabricate, FabError, FabOptions};
use std::path::Path;

#[test]
fn an_oversized_sheet_is_tiled_over_media_pages_when_asked() {
    let machine = Machine::load("generic-hpgl").unwrap();
    let mesh = crease::io::read(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/plane-crumpled.fold"),
    )
    .unwrap();
    let a5 = crease::fab::Media::parse("148x210mm").unwrap();
    let refused = fabricate(
        &mesh,
        &machine,
        &FabOptions {
            media: Some(a5.clone()),
            ..Default::default()
        },
    );
    assert!(matches!(refused, Err(FabError::Rejected(_))));
    let out = fabricate(
        &mesh,
        &machine,
        &FabOptions {
            media: Some(a5.clone()),
            tile: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        out.files.iter().all(|f| !f.0.ends_with(".hpgl")),
        "no cutter job for a sheet larger than the media"
    );
    let pdf = output(&out, "sheet.pdf");
    let doc = printpdf::PdfDocument::parse(pdf, &Default::default(), &mut Vec::new()).unwrap();
    // The sheet (with margins) is wider or taller than A5, so at least two pages, each A5.
    assert!(out.sheet.media.width > 148.0 || out.sheet.media.height > 210.0);
    assert!(doc.pages.len() >= 2);
    for page in &doc.pages {
        let w = page.media_box.width.0 as f64 * 25.4 / 72.0;
        let h = page.media_box.height.0 as f64 * 25.4 / 72.0;
        assert!((w - 148.0).abs() < 0.05 && (h - 210.0).abs() < 0.05);
    }
}

#[test]
fn a_tiled_sheet_is_turned_to_print_on_the_fewest_pages() {
    // resch.fold on 105 × 148 mm pages took 6 pages upright where 4 do turned a quarter.
    // The test counts pages with its own formula: a page shows its size less the margins,
    // and neighbours overlap by 10 mm.
    let machine = Machine::load("generic-hpgl").unwrap();
    let pages_for = |w: f64, h: f64, page: (f64, f64), m: f64| {
        let count = |total: f64, usable: f64| {
            let mut n = 1;
            while usable + (n - 1) as f64 * (usable - 10.0) < total - 1e-6 {
                n += 1;
            }
            n
        };
        count(w + 2.0 * m, page.0 - 2.0 * m) * count(h + 2.0 * m, page.1 - 2.0 * m)
    };
    let mut fewer = 0;
    for (design, page) in [
        ("resch.fold", (105.0, 148.0)),
        ("plane.fold", (80.0, 100.0)),
        ("waterbomb-curved.fold", (60.0, 90.0)),
        ("miura-bent.fold", (148.0, 210.0)),
    ] {
        let mesh = crease::io::read(
            &Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("patterns")
                .join(design),
        )
        .unwrap();
        let media = crease::fab::Media::parse(&format!("{}x{}mm", page.0, page.1)).unwrap();
        let out = fabricate(
            &mesh,
            &machine,
            &FabOptions {
                media: Some(media),
                tile: true,
                // Every page a tile or the notes (the guide's page has its own test).
                guide: crease::pipeline::Guide::Never,
                ..Default::default()
            },
        )
        .unwrap();
        let pdf = output(&out, "sheet.pdf");
        let doc = printpdf::PdfDocument::parse(pdf, &Default::default(), &mut Vec::new()).unwrap();
        // The design as drawn, turned back upright: its box upright and turned a quarter.
        let t = -out.sheet.rotation;
        let upright: Vec<Vec2> = out
            .sheet
            .vertices
            .iter()
            .map(|v| Vec2::new(v.x * t.cos() - v.y * t.sin(), v.x * t.sin() + v.y * t.cos()))
            .collect();
        let lo = upright
            .iter()
            .fold(Vec2::repeat(f64::INFINITY), |a, p| a.inf(p));
        let hi = upright
            .iter()
            .fold(Vec2::repeat(f64::NEG_INFINITY), |a, p| a.sup(p));
        let m = out.sheet.margin;
        let (up, quarter) = (
            pages_for(hi.x - lo.x, hi.y - lo.y, page, m),
            pages_for(hi.y - lo.y, hi.x - lo.x, page, m),
        );
        // The last page holds the title, summary and legend, not a window of the sheet.
        let got = doc.pages.len() - 1;
        assert!(
            got <= up && got <= quarter,
            "{design}: {got} pages, upright {up}, turned {quarter}"
        );
        fewer += usize::from(got < up);
    }
    assert!(fewer >= 2, "turning saved pages on {fewer} designs");
}

#[test]
fn small_sheets_and_huge_media_fabricate_without_a_panic() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let anchors = root.join("tests/data/fold");
    let cases: Vec<Vec<String>> = vec![
        vec![
            root.join("patterns/miura.fold").display().to_string(),
            "--width".into(),
            "60".into(),
        ],
        // The smallest sheet allowed, thousands of the router's grid cells from the pen:
        // its ring search once swept every cell of every ring out to it.
        vec![
            root.join("patterns/miura.fold").display().to_string(),
            "--width".into(),
            crease::pipeline::MIN_WIDTH_MM.to_string(),
        ],
        vec![
            root.join("patterns/miura.fold").display().to_string(),
            "--media".into(),
            "2000x2000mm".into(),
        ],
        vec![
            anchors.join("simple.fold").display().to_string(),
            "--force".into(),
        ],
        vec![
            anchors.join("squaretwist.fold").display().to_string(),
            "--force".into(),
        ],
        vec![
            anchors.join("cube-folded.fold").display().to_string(),
            "--force".into(),
        ],
    ];
    for (k, mut args) in cases.into_iter().enumerate() {
        let out = common::Scratch::new(&format!("fab-small-{k}"));
        args.insert(0, "fab".into());
        args.extend(["--out".into(), out.display().to_string()]);
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, _, err) = run_crease(&refs);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(code, 0, "{args:?}: {err}");
        let hpgl = std::fs::read_to_string(out.join("sheet.hpgl")).unwrap();
        assert!(hpgl.contains("PD"), "{args:?}: the job cuts something");
    }
}

#[test]
fn a_width_too_small_to_cut_is_refused() {
    let miura = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura.fold");
    let folder = common::Scratch::new("fab-tiny");
    let out = folder.join("job");
    for w in ["0.01", "0", "NaN"] {
        let (code, _, err) = run_crease(&[
            "fab",
            miura.to_str().unwrap(),
            "--width",
            w,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{w}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains("--width"), "{err}");
        assert!(!out.exists());
    }
}

#[test]
fn width_is_the_laid_out_width_and_fit_fills_the_media_within_the_margin() {
    let machine = Machine::load("generic-hpgl").unwrap();
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let name = path.display();
        // --width 150: the sheet as placed (after any turn) is 150 mm wide.
        // Layouts only: a draft route (the cutting order is not what is checked here).
        let options = FabOptions {
            media: Some(crease::fab::Media::parse("a3").unwrap()),
            width: Some(150.0),
            route: RouteSearch::Draft,
            guide: crease::pipeline::Guide::Never,
            ..Default::default()
        };
        let out = fabricate(&mesh, &machine, &options).unwrap();
        // The sheet is what its lines reach: the paper's vertices, and a tube's glue tab.
        let reach = |out: &crease::pipeline::FabOutput| -> Vec<Vec2> {
            out.sheet.lines.iter().flat_map(|l| [l.a, l.b]).collect()
        };
        let xs = reach(&out).into_iter().map(|p| p.x);
        let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
        assert!(
            (hi - lo - 150.0).abs() < 1e-6,
            "{name}: {} mm wide",
            hi - lo
        );
        // --fit with a 25 mm margin: every vertex within it, touching it on one axis.
        let options = FabOptions {
            media: Some(crease::fab::Media::parse("a4").unwrap()),
            fit: true,
            margin: Some(25.0),
            route: RouteSearch::Draft,
            guide: crease::pipeline::Guide::Never,
            ..Default::default()
        };
        let out = fabricate(&mesh, &machine, &options).unwrap();
        let (w, h) = (out.toolpath.media.width, out.toolpath.media.height);
        let v = &reach(&out);
        let lo = v
            .iter()
            .fold(Vec2::new(f64::INFINITY, f64::INFINITY), |a, p| a.inf(p));
        let hi = v
            .iter()
            .fold(Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY), |a, p| {
                a.sup(p)
            });
        assert!(lo.x >= 25.0 - 1e-6 && lo.y >= 25.0 - 1e-6, "{name}: {lo:?}");
        assert!(
            hi.x <= w - 25.0 + 1e-6 && hi.y <= h - 25.0 + 1e-6,
            "{name}: {hi:?}"
        );
        let fill = ((hi.x - lo.x) / (w - 50.0)).max((hi.y - lo.y) / (h - 50.0));
        assert!((fill - 1.0).abs() < 1e-6, "{name}: fills {fill}");
        // Fitted is at least as large as the design laid out upright at the same fill.
        let draft = FabOptions {
            route: RouteSearch::Draft,
            ..a3()
        };
        let natural = fabricate(&mesh, &machine, &draft).unwrap();
        let upright = ((w - 50.0) / natural.sheet.size[0]).min((h - 50.0) / natural.sheet.size[1]);
        assert!(
            out.sheet.scale >= upright - 1e-9,
            "{name}: {} < {upright}",
            out.sheet.scale
        );
    }
    let mesh = crease::io::read(&patterns()[0]).unwrap();
    for options in [
        FabOptions {
            fit: true,
            width: Some(100.0),
            ..Default::default()
        },
        FabOptions {
            margin: Some(-1.0),
            ..Default::default()
        },
        FabOptions {
            margin: Some(200.0),
            ..Default::default()
        },
    ] {
        assert!(matches!(
            fabricate(&mesh, &machine, &options),
            Err(e) if e.is_input()
        ));
    }
}

/// What a PDF page prints, read back by printpdf's parser: stroked segments with their
/// colour (RGB bytes), and text runs (start, size in points, text); all mm, y up.
struct PrintedPage {
    size: Vec2,
    lines: Vec<([u8; 3], Vec2, Vec2)>,
    texts: Vec<(Vec2, f64, String)>,
}

fn printed_pages(pdf: &[u8]) -> Vec<PrintedPage> {
    let doc = printpdf::PdfDocument::parse(pdf, &Default::default(), &mut Vec::new()).unwrap();
    let mm = |pt: f32| f64::from(pt) * 25.4 / 72.0;
    doc.pages
        .iter()
        .map(|page| {
            let mut out = PrintedPage {
                size: Vec2::new(mm(page.media_box.width.0), mm(page.media_box.height.0)),
                lines: Vec::new(),
                texts: Vec::new(),
            };
            let (mut colour, mut cursor, mut size) = ([0u8; 3], Vec2::zeros(), 0.0);
            for op in &page.ops {
                match op {
                    printpdf::Op::SetOutlineColor {
                        col: printpdf::Color::Rgb(c),
                    } => colour = [c.r, c.g, c.b].map(|v| (v * 255.0).round() as u8),
                    printpdf::Op::DrawLine { line } => {
                        let p = |i: usize| {
                            Vec2::new(mm(line.points[i].p.x.0), mm(line.points[i].p.y.0))
                        };
                        if line.points.len() == 4 && line.points[1].bezier {
                            // A cubic: its points at sixteenths, as pieces (its control
                            // points may lie beyond what it draws).
                            let at = |t: f64| {
                                let u = 1.0 - t;
                                p(0) * (u * u * u)
                                    + p(1) * (3.0 * u * u * t)
                                    + p(2) * (3.0 * u * t * t)
                                    + p(3) * (t * t * t)
                            };
                            for k in 0..16 {
                                let (a, b) = (at(k as f64 / 16.0), at((k + 1) as f64 / 16.0));
                                out.lines.push((colour, a, b));
                            }
                        } else {
                            out.lines.push((colour, p(0), p(1)));
                        }
                    }
                    printpdf::Op::SetTextCursor { pos } => {
                        cursor = Vec2::new(mm(pos.x.0), mm(pos.y.0))
                    }
                    printpdf::Op::SetFont { size: s, .. } => size = f64::from(s.0),
                    printpdf::Op::ShowText { items } => {
                        let text: String = items
                            .iter()
                            .map(|i| match i {
                                printpdf::TextItem::Text(t) => t.clone(),
                                _ => String::new(),
                            })
                            .collect();
                        out.texts.push((cursor, size, text));
                    }
                    _ => {}
                }
            }
            out
        })
        .collect()
}

#[test]
fn the_template_prints_inside_a_10_mm_margin_on_paper_and_its_text_clears_the_pattern() {
    // The bundled designs, on the cutter's mat (Cameo), a laser bed (300 × 200 mm), A4
    // and A3 paper, --fit or natural size, flat lines shown or hidden: every page of
    // sheet.pdf is a paper size (A5, A4, letter, legal, A3, either way up); everything
    // drawn or written lies 10 mm inside its edges (text measured at 0.6 em a character
    // and its full point size tall, more than Helvetica takes); no text on the page to
    // fold by comes within 1 mm of the pattern; its legend names exactly the kinds of line
    // drawn, flat included only when flat lines are shown.
    let papers = [
        (148.0, 210.0),
        (210.0, 297.0),
        (215.9, 279.4),
        (215.9, 355.6),
        (297.0, 420.0),
    ];
    let is_paper = |s: Vec2| {
        papers.iter().any(|&(w, h)| {
            ((s.x - w).abs() < 0.1 && (s.y - h).abs() < 0.1)
                || ((s.x - h).abs() < 0.1 && (s.y - w).abs() < 0.1)
        })
    };
    let colour_of = |k: &str| match k {
        "mountain" => [255, 0, 0],
        "valley" => [0, 0, 255],
        "cut" => [0, 0, 0],
        "flat" => [192, 192, 192],
        other => panic!("{other}"),
    };
    let mut with_notes = 0;
    let mut runs = 0;
    let configs = [
        ("silhouette-cameo", None, false, false),
        ("laser-dxf", None, true, true),
        ("generic-hpgl", Some("a4"), true, false),
        ("generic-hpgl", Some("a3"), false, false),
    ];
    for (i, design) in patterns().iter().enumerate() {
        let mesh = crease::io::read(design).unwrap();
        let name = design.file_name().unwrap().to_string_lossy().into_owned();
        // Two of the four set-ups per design, each set-up on half of the designs.
        for &(machine, media, fit, hide_flat) in [configs[i % 4], configs[(i + 1) % 4]].iter() {
            let options = FabOptions {
                media: media.map(|m| crease::fab::Media::parse(m).unwrap()),
                fit,
                hide_flat,
                route: RouteSearch::Draft,
                // The folding guide's page is checked in its own test (design/animate.rs).
                guide: crease::pipeline::Guide::Never,
                ..Default::default()
            };
            let Ok(out) = fabricate(&mesh, &Machine::load(machine).unwrap(), &options) else {
                continue; // too large for the media at natural size
            };
            runs += 1;
            let what = format!("{name} on {machine} {media:?} fit {fit}");
            let pages = printed_pages(output(&out, "sheet.pdf"));
            // A mat or bed a home printer does not take is tiled over its pages (no page
            // to fold by): checked for paper and margins here, as tiles elsewhere.
            let tiled = out.template_note.is_some();
            with_notes += usize::from(pages.len() > 2 && !tiled);
            for (i, page) in pages.iter().enumerate() {
                let (w, h) = (page.size.x, page.size.y);
                assert!(is_paper(page.size), "{what}: page {i} is {w} × {h} mm");
                let inside = |p: Vec2| {
                    p.x >= 10.0 - 1e-3
                        && p.x <= w - 10.0 + 1e-3
                        && p.y >= 10.0 - 1e-3
                        && p.y <= h - 10.0 + 1e-3
                };
                for (_, a, b) in &page.lines {
                    assert!(
                        inside(*a) && inside(*b),
                        "{what}: page {i} draws {a:?}-{b:?}"
                    );
                }
                for (at, size, t) in &page.texts {
                    let end = *at
                        + Vec2::new(
                            t.len() as f64 * size * 0.6 * 25.4 / 72.0,
                            size * 25.4 / 72.0,
                        );
                    assert!(
                        inside(*at) && inside(end),
                        "{what}: page {i} writes \"{t}\" at {at:?} to {end:?}"
                    );
                }
            }
            if tiled {
                continue;
            }
            // The page to fold by: text clear of the pattern, which the page shifts by
            // the paper's shift (checked: every coloured line lies within it).
            let fold = &pages[0];
            let shift = crease::output::pdf::paper_for(&out.sheet).shift;
            let (plo, phi) = out.sheet.bounds();
            let (plo, phi) = (plo + shift, phi + shift);
            // A legend's sample line has its kind's name written 9 mm to its right.
            let sample = |a: &Vec2| {
                fold.texts
                    .iter()
                    .any(|(at, _, t)| (at - a - Vec2::new(9.0, -1.0)).norm() < 1e-3 && t.len() < 10)
            };
            for (c, a, b) in &fold.lines {
                if *c != [0, 0, 0] && !sample(a) {
                    for p in [a, b] {
                        assert!(
                            p.x >= plo.x - 1e-3
                                && p.y >= plo.y - 1e-3
                                && p.x <= phi.x + 1e-3
                                && p.y <= phi.y + 1e-3,
                            "{what}: a crease line at {p:?} outside the pattern's box"
                        );
                    }
                }
            }
            // Words the sheet itself carries (a tube's seam numbers) are printed on it.
            let on_sheet = |at: &Vec2, t: &str| {
                out.sheet
                    .labels
                    .iter()
                    .any(|l| l.text == t && (l.at + shift - at).norm() < 5.0)
            };
            for (at, size, t) in fold.texts.iter().filter(|(at, _, t)| !on_sheet(at, t)) {
                let top = at.y + size * 25.4 / 72.0;
                let bottom = at.y - size * 0.25 * 25.4 / 72.0;
                assert!(
                    top < plo.y - 1.0 || bottom > phi.y + 1.0,
                    "{what}: \"{t}\" ({bottom:.1}–{top:.1} mm) meets the pattern ({:.1}–{:.1} mm)",
                    plo.y,
                    phi.y
                );
            }
            // The legend (on page 1, or on the notes page) names every colour of crease
            // drawn and the cut; flat only when flat lines are drawn.
            let drawn: std::collections::BTreeSet<[u8; 3]> =
                fold.lines.iter().map(|l| l.0).collect();
            let legend_page = if pages.len() > 2 { &pages[1] } else { fold };
            let named: std::collections::BTreeSet<[u8; 3]> = legend_page
                .texts
                .iter()
                .filter(|(_, _, t)| ["mountain", "valley", "cut", "flat"].contains(&t.as_str()))
                .map(|(_, _, t)| colour_of(t))
                .collect();
            assert_eq!(drawn, named, "{what}: drawn {drawn:?}, legend {named:?}");
            assert!(
                !hide_flat || !drawn.contains(&[192, 192, 192]),
                "{what}: flat lines hidden"
            );
        }
    }
    assert!(runs >= 20, "{runs} runs");
    assert!(
        with_notes >= 1,
        "some pattern fills its page and sends the text to a notes page"
    );
}

/// Issue 47, item 9: a pattern fitted to a 12 × 12 in mat went onto one A3 page, which no
/// home printer takes; its template is Letter pages to tape together (A4 for a mat given
/// in millimetres; the tiling itself is `--tile`'s, tested with it), and the cutter's
/// job is still written. Paper media, A3 included, keeps its one page.
#[test]
fn a_mat_sized_pattern_prints_over_home_printer_pages() {
    let design = crease::io::read(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura-bent.fold"),
    )
    .unwrap();
    let machine = crease::machine::Machine::load("silhouette-cameo").unwrap();
    for (media, paper_pt) in [("12x12in", (612.0, 792.0)), ("300x300mm", (595.3, 841.9))] {
        let options = crease::pipeline::FabOptions {
            media: Some(crease::fab::Media::parse(media).unwrap()),
            fit: true,
            route: crease::fab::RouteSearch::Draft,
            ..Default::default()
        };
        let out = crease::pipeline::fabricate(&design, &machine, &options).unwrap();
        let note = out.template_note.as_deref().expect("the template is tiled");
        assert!(note.contains("pages to tape together"), "{note}");
        assert!(out.files.iter().any(|(n, _)| n == "sheet.gpgl"), "{media}");
        let pdf = common::fabbing::output(&out, "sheet.pdf");
        let doc = printpdf::PdfDocument::parse(pdf, &Default::default(), &mut Vec::new()).unwrap();
        assert!(doc.pages.len() >= 4, "{media}: {} pages", doc.pages.len());
        for page in &doc.pages {
            let (w, h) = (page.media_box.width.0, page.media_box.height.0);
            let (w, h) = (w.min(h), w.max(h));
            assert!(
                (f64::from(w) - paper_pt.0).abs() < 1.0 && (f64::from(h) - paper_pt.1).abs() < 1.0,
                "{media}: a page of {w} × {h} pt"
            );
        }
    }
    // A3 paper chosen by the maker stays one A3 page.
    let out = crease::pipeline::fabricate(&design, &machine, &common::fabbing::a3_draft()).unwrap();
    assert!(out.template_note.is_none());
    let pdf = common::fabbing::output(&out, "sheet.pdf");
    let doc = printpdf::PdfDocument::parse(pdf, &Default::default(), &mut Vec::new()).unwrap();
    let (w, h) = (
        doc.pages[0].media_box.width.0,
        doc.pages[0].media_box.height.0,
    );
    assert!((f64::from(w.max(h)) - 1190.55).abs() < 1.0, "{w} × {h}");
}
