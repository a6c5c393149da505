//! The sheet on the media: `--width` and `--fit` size the laid-out sheet within the
//! margins, a sheet too large is tiled over the fewest pages, and odd sizes neither panic
//! nor cut strokes shorter than the machine's step.

mod common;

use common::fabbing::{a3, output, patterns};
use common::run_crease;
use crease::mesh::Vec2;
use crease::pipeline::{fabricate, FabError, FabOptions};
use crease::plotter::Machine;
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
        let got = doc.pages.len();
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
        let out = std::env::temp_dir().join(format!("crease-fab-small-{}-{k}", std::process::id()));
        args.insert(0, "fab".into());
        args.extend(["--out".into(), out.display().to_string()]);
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, _, err) = run_crease(&refs);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(code, 0, "{args:?}: {err}");
        let hpgl = std::fs::read_to_string(out.join("sheet.hpgl")).unwrap();
        assert!(hpgl.contains("PD"), "{args:?}: the job cuts something");
        let _ = std::fs::remove_dir_all(out);
    }
}

#[test]
fn a_width_too_small_to_cut_is_refused() {
    let miura = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura.fold");
    let out = std::env::temp_dir().join(format!("crease-fab-tiny-{}", std::process::id()));
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
        let options = FabOptions {
            media: Some(crease::fab::Media::parse("a3").unwrap()),
            width: Some(150.0),
            ..Default::default()
        };
        let out = fabricate(&mesh, &machine, &options).unwrap();
        let xs = out.sheet.vertices.iter().map(|p| p.x);
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
            ..Default::default()
        };
        let out = fabricate(&mesh, &machine, &options).unwrap();
        let (w, h) = (out.toolpath.media.width, out.toolpath.media.height);
        let v = &out.sheet.vertices;
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
        let natural = fabricate(&mesh, &machine, &a3()).unwrap();
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
            Err(FabError::Input(_))
        ));
    }
}
