//! Fabrication end to end: every design in `patterns/` becomes a scored sheet whose
//! layout is isometric to the design, whose dashes keep clear of crease junctions, whose
//! HP-GL draws exactly the toolpath, and whose PDF is 1:1 with a true 100 mm scale bar.

mod common;

use common::run_crease;
use crease::fab::{LineKind, Stroke};
use crease::mesh::{Mesh, Vec2};
use crease::output::hpgl;
use crease::pipeline::{fabricate, FabError, FabOptions};
use crease::plotter::Machine;
use std::path::{Path, PathBuf};

fn patterns() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns");
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "fold"))
        .collect();
    v.sort();
    assert!(v.len() >= 10);
    v
}

fn a3() -> FabOptions {
    FabOptions {
        media: Some(crease::fab::Media::parse("a3").unwrap()),
        ..Default::default()
    }
}

/// The bytes of one file a fabrication run produced.
fn output<'a>(out: &'a crease::pipeline::FabOutput, name: &str) -> &'a [u8] {
    &out.files
        .iter()
        .find(|f| f.0 == name)
        .unwrap_or_else(|| panic!("fab wrote no {name}"))
        .1
}

/// One text file a fabrication run produced.
fn output_text<'a>(out: &'a crease::pipeline::FabOutput, name: &str) -> &'a str {
    std::str::from_utf8(output(out, name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn distance_to_segment(p: Vec2, s: &Stroke) -> f64 {
    let d = s.to - s.from;
    let t = ((p - s.from).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (s.from + d * t - p).norm()
}

/// Vertices where three or more scored creases or cuts meet, on the sheet.
fn junctions(mesh: &Mesh, placed: &[Vec2]) -> Vec<Vec2> {
    let mut degree = vec![0; placed.len()];
    for e in mesh.edges() {
        if LineKind::of_edge(e) != LineKind::Flat {
            degree[e.vertices[0]] += 1;
            degree[e.vertices[1]] += 1;
        }
    }
    (0..placed.len())
        .filter(|&v| degree[v] >= 3)
        .map(|v| placed[v])
        .collect()
}

#[test]
fn every_design_fabricates_isometric_clear_of_junctions_and_hpgl_faithful() {
    let machine = Machine::load("generic-hpgl").unwrap();
    let clearance = machine.clearance_mm;
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out =
            fabricate(&mesh, &machine, &a3()).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(
            out.isometry_error <= 1e-9,
            "{}: isometry {}",
            path.display(),
            out.isometry_error
        );
        // Independently: sheet edge lengths against the 3D design, scale 1.
        for e in mesh.edges() {
            let [a, b] = e.vertices;
            let l3 = (mesh.positions()[a] - mesh.positions()[b]).norm();
            let l2 = (out.sheet.vertices[a] - out.sheet.vertices[b]).norm();
            assert!(
                (l2 - l3).abs() <= 1e-9 * l3,
                "{}: edge {a}-{b}",
                path.display()
            );
        }
        let js = junctions(&mesh, &out.sheet.vertices);
        let mut scored = 0;
        for s in out
            .toolpath
            .strokes
            .iter()
            .filter(|s| matches!(s.kind, LineKind::Mountain | LineKind::Valley))
        {
            scored += 1;
            for j in &js {
                let d = distance_to_segment(*j, s);
                assert!(
                    d >= clearance - 1e-6,
                    "{}: a dash passes {d:.3} mm from a junction",
                    path.display()
                );
            }
        }
        if mesh.edges().iter().any(|e| e.assignment.is_folded()) {
            assert!(scored > 0, "{} has folds to score", path.display());
        }
        // The HP-GL, interpreted, draws exactly the toolpath (to the plotter unit).
        let drawn = hpgl::interpret(output_text(&out, "sheet.hpgl")).unwrap();
        let expected = hpgl::expected_segments(&out.toolpath, &machine.hpgl_settings());
        assert_eq!(drawn.segments.len(), expected.len(), "{}", path.display());
        for (d, e) in drawn.segments.iter().zip(&expected) {
            assert_eq!(d.0, e.0);
            for k in 0..2 {
                assert!(
                    (d.1[k] - e.1[k]).abs() <= 1 && (d.2[k] - e.2[k]).abs() <= 1,
                    "{}",
                    path.display()
                );
            }
        }
        assert!(
            drawn.pen_up_at_end && drawn.end == [0, 0],
            "pen up and parked"
        );
        // Everything lies within the media's margins.
        for s in &out.toolpath.strokes {
            for p in [s.from, s.to] {
                assert!(
                    p.x >= machine.margin_mm - 1e-6
                        && p.x <= out.sheet.media.width - machine.margin_mm + 1e-6
                );
                assert!(
                    p.y >= machine.margin_mm - 1e-6
                        && p.y <= out.sheet.media.height - machine.margin_mm + 1e-6
                );
            }
        }
    }
}

#[test]
fn unassigned_creases_a_design_folds_are_scored_by_the_way_they_fold() {
    // Resch's tuck sides are unassigned and flat in the regular pattern; the dome turns
    // some of them by tens of degrees, and a sheet without them would not take its shape.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/resch-dome.fold");
    let mesh = crease::io::read(&path).unwrap();
    let machine = Machine::load("generic-hpgl").unwrap();
    let out = fabricate(&mesh, &machine, &a3()).unwrap();
    let placed = &out.sheet.vertices;
    let on_line = |p: Vec2, l: &crease::fab::CreaseLine| {
        let d = l.b - l.a;
        let t = ((p - l.a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
        (l.a + d * t - p).norm() < 1e-6
    };
    let mut folded = 0;
    for e in mesh.edges() {
        if e.assignment != crease::mesh::Assignment::Unassigned {
            continue;
        }
        let [a, b] = e.vertices.map(|v| placed[v]);
        let kind = if e.fold_angle.abs() <= 1f64.to_radians() {
            LineKind::Flat
        } else if e.fold_angle > 0.0 {
            LineKind::Mountain
        } else {
            LineKind::Valley
        };
        if kind != LineKind::Flat {
            folded += 1;
        }
        assert!(
            out.sheet
                .lines
                .iter()
                .any(|l| l.kind == kind && on_line(a, l) && on_line(b, l)),
            "edge {:?} folded {:.1}° is not on a {} line",
            e.vertices,
            e.fold_angle.to_degrees(),
            kind.name()
        );
    }
    assert!(folded > 20, "only {folded} unassigned creases fold");
}

#[test]
fn the_crease_pattern_svg_reimports_to_the_same_graph() {
    let machine = Machine::load("generic-hpgl").unwrap();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura-bent.fold");
    let mesh = crease::io::read(&path).unwrap();
    let out = fabricate(&mesh, &machine, &a3()).unwrap();
    let svg = output(&out, "crease-pattern.svg");
    let dir = std::env::temp_dir().join(format!("crease-fab-cp-{}", std::process::id()));
    crease::io::write_atomic(&dir.join("cp.svg"), svg).unwrap();
    let back = crease::io::read(&dir.join("cp.svg")).unwrap();
    assert_eq!(back.vertex_count(), mesh.vertex_count());
    assert_eq!(back.edges().len(), mesh.edges().len());
    let count = |m: &Mesh, a| m.edges().iter().filter(|e| e.assignment == a).count();
    for a in [
        crease::mesh::Assignment::Mountain,
        crease::mesh::Assignment::Valley,
        crease::mesh::Assignment::Boundary,
    ] {
        assert_eq!(count(&back, a), count(&mesh, a));
    }
}

#[test]
fn the_crease_pattern_fold_carries_the_layer_order_of_a_flat_pattern() {
    // The bird base folds flat: fab writes its laid-out crease pattern with the same
    // faceOrders `convert` finds for the file itself (an order depends on the faces, not
    // on where the layout puts them). A 3D design gets its crease pattern without one.
    let machine = Machine::load("generic-hpgl").unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let file = |out: &crease::pipeline::FabOutput, name: &str| -> serde_json::Value {
        serde_json::from_slice(output(out, name)).unwrap()
    };
    let bird = crease::io::read(&root.join("patterns/bird-base.fold")).unwrap();
    let out = fabricate(&bird, &machine, &a3()).unwrap();
    let written = file(&out, "crease-pattern.fold");
    let crease::fab::LayerOrder::Found(orders) = crease::fab::layer_order(&bird).unwrap() else {
        panic!("the bird base folds flat");
    };
    let written_orders: Vec<[i64; 3]> =
        serde_json::from_value(written["faceOrders"].clone()).unwrap();
    assert!(!orders.is_empty());
    assert_eq!(written_orders, orders);
    let reread = crease::io::fold::parse(&written.to_string()).unwrap();
    assert_eq!(reread.faces().len(), bird.faces().len());
    let bent = crease::io::read(&root.join("patterns/miura-bent.fold")).unwrap();
    let out = fabricate(&bent, &machine, &a3()).unwrap();
    assert!(file(&out, "crease-pattern.fold")
        .get("faceOrders")
        .is_none());
}

#[test]
fn the_pdf_page_is_the_media_and_its_scale_bar_is_100_mm() {
    let machine = Machine::load("generic-hpgl").unwrap();
    let mesh = crease::io::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura.fold"))
        .unwrap();
    for media in ["a4", "letter"] {
        let options = FabOptions {
            media: Some(crease::fab::Media::parse(media).unwrap()),
            ..Default::default()
        };
        let out = fabricate(&mesh, &machine, &options).unwrap();
        let pdf = output(&out, "sheet.pdf");
        let doc = printpdf::PdfDocument::parse(pdf, &Default::default(), &mut Vec::new()).unwrap();
        assert_eq!(doc.pages.len(), 1);
        let page = &doc.pages[0];
        let mm = |pt: f32| pt as f64 * 25.4 / 72.0;
        let (w, h) = (mm(page.media_box.width.0), mm(page.media_box.height.0));
        assert!(
            (w - out.sheet.media.width).abs() < 0.05 && (h - out.sheet.media.height).abs() < 0.05,
            "{media}: {w} × {h}"
        );
        // Among the drawn lines, a horizontal one of 100 mm in page units: the scale bar.
        let bars = page
            .ops
            .iter()
            .filter_map(|op| match op {
                printpdf::Op::DrawLine { line } if line.points.len() == 2 => {
                    let (a, b) = (line.points[0].p, line.points[1].p);
                    Some((mm(b.x.0 - a.x.0), mm(b.y.0 - a.y.0)))
                }
                _ => None,
            })
            .filter(|(dx, dy)| dy.abs() < 1e-3 && (dx.abs() - 100.0).abs() < 0.01)
            .count();
        assert_eq!(bars, 1, "{media}: one 100 mm scale bar");
    }
}

#[test]
fn bad_fabrication_input_is_refused_and_leaves_nothing() {
    let root = env!("CARGO_MANIFEST_DIR");
    let out = std::env::temp_dir().join(format!("crease-fab-bad-{}", std::process::id()));
    let miura = format!("{root}/patterns/miura.fold");
    let (code, _, err) = run_crease(&[
        "fab",
        &miura,
        "--machine",
        "laser-9000",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("unknown machine") && err.contains("generic-hpgl"),
        "{err}"
    );
    let (code, _, err) = run_crease(&[
        "fab",
        &miura,
        "--media",
        "100x100mm",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("needs") && err.contains("mm"), "{err}");
    // A Miura-ori with one vertex pushed off: not developable.
    let mut m = crease::io::read(Path::new(&miura)).unwrap();
    let mut x = m.positions().to_vec();
    let v = (0..m.vertex_count())
        .filter(|&v| m.is_interior(v))
        .nth(20)
        .unwrap();
    x[v].z += 0.5;
    m.set_positions(x);
    let broken = out.with_extension("fold");
    crease::io::write(&m, &broken).unwrap();
    let (code, _, err) = run_crease(&[
        "fab",
        broken.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("fails verification") && err.contains(&format!("vertex {v}")),
        "{err}"
    );
    assert!(!out.exists(), "nothing written for refused designs");
    // With --force it is cut anyway, and every file lands.
    let (code, _, err) = run_crease(&[
        "fab",
        broken.to_str().unwrap(),
        "--force",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    for f in [
        "sheet.svg",
        "sheet.pdf",
        "sheet.hpgl",
        "crease-pattern.svg",
        "report.json",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["verification"]["pass"], false);
    assert!(report["sheet"]["pen_up_travel_mm"].as_f64().unwrap() > 0.0);
    assert!(std::fs::read_dir(&out).unwrap().all(|e| !e
        .unwrap()
        .file_name()
        .to_string_lossy()
        .ends_with(".tmp")));
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn machine_profiles_load_and_unknown_keys_are_errors() {
    for name in ["generic-hpgl", "hp7475a", "roland-cutter"] {
        let m = Machine::load(name).unwrap();
        assert!(m.tools.contains_key("cut"));
    }
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/generic-hpgl.toml"),
    )
    .unwrap();
    let typo = text.replace("clearance_mm", "clearence_mm");
    assert!(Machine::parse(&typo).unwrap_err().contains("clearence_mm"));
}

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

/// The router searched rings of grid cells around the pen, bounded by the grid's size, so
/// a small design far from the pen's origin ran out of rings ("an undone stroke remains").
/// Now it starts at the grid and visits only cells in it, in the order a full sweep would.
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
fn routing_a_small_design_far_from_the_pen_keeps_every_stroke() {
    let mut strokes = Vec::new();
    for i in 0..40 {
        let x = 1000.0 + (i % 8) as f64 * 0.7;
        let y = 800.0 + (i / 8) as f64 * 0.9;
        strokes.push(Stroke {
            kind: if i % 3 == 0 {
                LineKind::Valley
            } else {
                LineKind::Mountain
            },
            from: Vec2::new(x, y),
            to: Vec2::new(x + 0.5, y + 0.2),
            line: i,
        });
    }
    let tools = Machine::load("generic-hpgl").unwrap().hpgl_settings().tools;
    let routed = crease::fab::route(&strokes, &tools);
    assert_eq!(routed.len(), strokes.len());
    for s in &strokes {
        let found = routed.iter().any(|r| {
            r.kind == s.kind
                && ((r.from == s.from && r.to == s.to) || (r.from == s.to && r.to == s.from))
        });
        assert!(found, "stroke {s:?} is routed once");
    }
}

#[test]
fn small_sheets_and_huge_media_fabricate_without_a_panic() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let anchors = root.join("../shared/anchors/data/fold");
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

/// With a folder named like one of the outputs in the way, `fab` writes none of its files
/// and leaves no temporary file behind.
#[test]
fn a_folder_in_the_way_leaves_the_output_folder_untouched() {
    let dir = std::env::temp_dir().join(format!("crease-fab-blocked-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("report.json")).unwrap();
    let design = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura-bent.fold");
    let (code, _, err) = run_crease(&[
        "fab",
        design.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("report.json"), "{err}");
    let left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        left,
        vec!["report.json".to_string()],
        "only the folder stays"
    );
    let _ = std::fs::remove_dir_all(dir);
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
fn sheet_dxf_read_by_an_independent_parser_carries_exactly_the_toolpath() {
    // The dxf crate (ixmilia) reads sheet.dxf back: one LINE per stroke, on the layer of
    // its operation, ends within a micrometre of the toolpath's (whose y grows upward, as
    // DXF's), in millimetres.
    let machine = Machine::load("generic-hpgl").unwrap();
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &a3()).unwrap();
        let bytes = output(&out, "sheet.dxf");
        let drawing = dxf::Drawing::load(&mut &bytes[..])
            .unwrap_or_else(|e| panic!("{}: sheet.dxf does not parse: {e}", path.display()));
        assert_eq!(drawing.header.version, dxf::enums::AcadVersion::R12);
        let lines: Vec<(String, [f64; 4])> = drawing
            .entities()
            .map(|e| match &e.specific {
                dxf::entities::EntityType::Line(l) => {
                    (e.common.layer.clone(), [l.p1.x, l.p1.y, l.p2.x, l.p2.y])
                }
                other => panic!("{}: unexpected entity {other:?}", path.display()),
            })
            .collect();
        let strokes = &out.toolpath.strokes;
        assert_eq!(lines.len(), strokes.len(), "{}", path.display());
        for ((layer, [x1, y1, x2, y2]), s) in lines.iter().zip(strokes) {
            let expected = match s.kind {
                LineKind::Cut => "CUT",
                LineKind::Mountain => "MOUNTAIN",
                LineKind::Valley => "VALLEY",
                LineKind::Flat => "FLAT",
            };
            assert_eq!(layer, expected);
            for (got, want) in [
                (*x1, s.from.x),
                (*y1, s.from.y),
                (*x2, s.to.x),
                (*y2, s.to.y),
            ] {
                assert!(
                    (got - want).abs() <= 1e-4,
                    "{}: {got} vs {want}",
                    path.display()
                );
            }
        }
        // Every layer is declared, with distinct colours.
        let colours: Vec<_> = drawing.layers().map(|l| l.color.index()).collect();
        let mut unique = colours.clone();
        unique.sort();
        unique.dedup();
        assert!(
            colours.len() >= 3 && unique.len() == colours.len(),
            "{colours:?}"
        );
    }
}

/// An independent GP-GL reader: the pen-down segments of a job, as (tool holder, from,
/// to) in cutter steps, (feed, carriage) as written.
fn read_gpgl(job: &str) -> Vec<(u32, [i64; 2], [i64; 2])> {
    let body = job
        .strip_prefix("\u{1b}\u{4}")
        .expect("a GP-GL job starts by resetting the cutter (ESC EOT)");
    assert!(body.ends_with('\u{3}'), "every command ends with ETX");
    let numbers = |s: &str| -> Vec<i64> { s.split(',').map(|n| n.parse().unwrap()).collect() };
    let (mut tool, mut at, mut segments) = (0, [0i64, 0], Vec::new());
    for cmd in body.split('\u{3}').filter(|c| !c.is_empty()) {
        assert!(cmd.bytes().all(|b| (0x20..0x7f).contains(&b)), "{cmd:?}");
        if let Some(rest) = cmd.strip_prefix('J') {
            tool = rest.parse().unwrap();
        } else if let Some(rest) = cmd.strip_prefix('M') {
            let p = numbers(rest);
            at = [p[0], p[1]];
        } else if let Some(rest) = cmd.strip_prefix('D') {
            for p in numbers(rest).chunks(2) {
                segments.push((tool, at, [p[0], p[1]]));
                at = [p[0], p[1]];
            }
        }
    }
    segments
}

#[test]
fn sheet_gpgl_read_by_an_independent_reader_carries_exactly_the_toolpath() {
    // Graphtec profile: 20 steps per mm, media feed (the sheet's y) first. Every stroke
    // of the toolpath is one cut segment with the kind's tool holder, its ends within
    // one step of the stroke's and its length within one step of the stroke's (rounding
    // both ends to their nearest step alone would allow √2).
    let machine = Machine::load("graphtec-ce").unwrap();
    let units = machine.units_per_mm;
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &a3()).unwrap();
        assert!(!out.files.iter().any(|f| f.0 == "sheet.hpgl"));
        let job = output_text(&out, "sheet.gpgl");
        let segments = read_gpgl(job);
        // The cutter's origin is the media's top-left corner; the toolpath's y grows up.
        let h = out.toolpath.media.height;
        let step = |p: Vec2| {
            [
                ((h - p.y) * units).round() as i64,
                (p.x * units).round() as i64,
            ]
        };
        let strokes: Vec<_> = out
            .toolpath
            .strokes
            .iter()
            .filter(|s| step(s.from) != step(s.to))
            .collect();
        assert_eq!(segments.len(), strokes.len(), "{}", path.display());
        for ((tool, from, to), s) in segments.iter().zip(&strokes) {
            assert_eq!(*tool, machine.tools[s.kind.name()].pen);
            for (got, want) in [(from, s.from), (to, s.to)] {
                let want = [(h - want.y) * units, want.x * units];
                assert!(
                    (got[0] as f64 - want[0]).abs() < 1.0 && (got[1] as f64 - want[1]).abs() < 1.0,
                    "{}: {got:?} vs {want:?}",
                    path.display()
                );
            }
            let length = |a: [i64; 2], b: [i64; 2]| {
                (((a[0] - b[0]).pow(2) + (a[1] - b[1]).pow(2)) as f64).sqrt()
            };
            let (got, want) = (length(*from, *to), (s.to - s.from).norm() * units);
            assert!(
                (got - want).abs() <= 1.0,
                "{}: length {got} vs {want}",
                path.display()
            );
        }
    }
    // Carriage first (as inkcut sends): the same job with each pair swapped.
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/graphtec-ce.toml"),
    )
    .unwrap()
    .replace(
        "axis_order = \"feed-first\"",
        "axis_order = \"carriage-first\"",
    );
    let swapped = Machine::parse(&text).unwrap();
    let mesh = crease::io::read(&patterns()[0]).unwrap();
    let read = |m: &Machine| {
        let out = fabricate(&mesh, m, &a3()).unwrap();
        read_gpgl(output_text(&out, "sheet.gpgl"))
    };
    let flipped: Vec<_> = read(&swapped)
        .into_iter()
        .map(|(t, a, b)| (t, [a[1], a[0]], [b[1], b[0]]))
        .collect();
    assert_eq!(flipped, read(&machine));
}

#[test]
fn a_laser_profile_gets_dxf_and_svg_and_no_cutter_job() {
    let machine = Machine::load("laser-dxf").unwrap();
    let mesh = crease::io::read(&patterns()[0]).unwrap();
    let out = fabricate(&mesh, &machine, &a3()).unwrap();
    let names: Vec<&str> = out.files.iter().map(|f| f.0.as_str()).collect();
    assert!(
        names.contains(&"sheet.dxf") && names.contains(&"sheet.svg"),
        "{names:?}"
    );
    assert!(
        !names
            .iter()
            .any(|n| n.ends_with(".hpgl") || n.ends_with(".gpgl")),
        "{names:?}"
    );
    assert_eq!(out.report["sheet"]["job_files"], serde_json::json!([]));
    assert!(out.report["sheet"]["plotter"].is_null());
}

#[test]
fn every_output_shows_the_sheet_the_same_way_round() {
    // A mirrored file folds into the mirror image of the design. Seen from above with
    // the origin at the media's top-left corner: sheet.svg as drawn (y down), sheet.dxf
    // and sheet.hpgl with y up from the lower edge, sheet.gpgl feed-first from the top.
    // The bird base is laid out asymmetrically enough (its kite lines) that a flip of any
    // one file changes its set of segments.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bird = crease::io::read(&root.join("patterns/bird-base.fold")).unwrap();
    type Segment = ([f64; 2], [f64; 2]);
    let hpgl_machine = Machine::load("generic-hpgl").unwrap();
    let out = fabricate(&bird, &hpgl_machine, &a3()).unwrap();
    let h = out.toolpath.media.height;
    // The SVG's lines, as drawn.
    let svg = output_text(&out, "sheet.svg");
    let from_svg: Vec<Segment> = svg_segments(svg)
        .into_iter()
        .map(|(_, a, b)| (a, b))
        .collect();
    // The DXF, turned to y down.
    let dxf = output_text(&out, "sheet.dxf");
    let drawing = dxf::Drawing::load(&mut dxf.as_bytes()).unwrap();
    let from_dxf: Vec<Segment> = drawing
        .entities()
        .filter_map(|e| match &e.specific {
            dxf::entities::EntityType::Line(l) => {
                Some(([l.p1.x, h - l.p1.y], [l.p2.x, h - l.p2.y]))
            }
            _ => None,
        })
        .collect();
    // The HP-GL as the plotter draws it.
    let u = hpgl_machine.units_per_mm;
    let drawn = hpgl::interpret(output_text(&out, "sheet.hpgl"))
        .unwrap()
        .segments;
    let from_hpgl: Vec<Segment> = drawn
        .iter()
        .map(|(_, a, b)| {
            let p = |q: [i64; 2]| [q[0] as f64 / u, h - q[1] as f64 / u];
            (p(*a), p(*b))
        })
        .collect();
    // The GP-GL from the top-left origin, feed (down) first.
    let gpgl_machine = Machine::load("graphtec-ce").unwrap();
    let g = fabricate(&bird, &gpgl_machine, &a3()).unwrap();
    let gu = gpgl_machine.units_per_mm;
    let from_gpgl: Vec<Segment> = read_gpgl(output_text(&g, "sheet.gpgl"))
        .into_iter()
        .map(|(_, a, b)| {
            let p = |q: [i64; 2]| [q[1] as f64 / gu, q[0] as f64 / gu];
            (p(a), p(b))
        })
        .collect();
    // Each segment of `other` lies on one of sheet.svg's, ends within 0.1 mm (the
    // cutters' steps are 0.025–0.05 mm), and the counts agree.
    let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) < 0.1;
    let same = |s: &Segment, t: &Segment| {
        (near(s.0, t.0) && near(s.1, t.1)) || (near(s.0, t.1) && near(s.1, t.0))
    };
    let matched = |other: &[Segment]| {
        other
            .iter()
            .filter(|s| from_svg.iter().any(|t| same(s, t)))
            .count()
    };
    let mirrored: Vec<Segment> = from_svg
        .iter()
        .map(|&(p, q)| ([p[0], 2.0 * h - p[1] - h], [q[0], 2.0 * h - q[1] - h]))
        .collect();
    assert!(
        (matched(&mirrored) as f64) < 0.9 * from_svg.len() as f64,
        "the test pattern must not be its own mirror image"
    );
    let agree = |name: &str, other: &Vec<Segment>| {
        assert_eq!(other.len(), from_svg.len(), "{name}");
        assert_eq!(
            matched(other),
            other.len(),
            "{name}: segments off sheet.svg's"
        );
    };
    agree("sheet.dxf", &from_dxf);
    agree("sheet.hpgl", &from_hpgl);
    agree("sheet.gpgl", &from_gpgl);
}

/// The segments of a sheet.svg's paths: (layer, from, to) as drawn (y down), closing
/// segments of `Z` included.
fn svg_segments(svg: &str) -> Vec<(String, [f64; 2], [f64; 2])> {
    let mut out = Vec::new();
    for layer in svg.split("<g ").skip(1) {
        let name = layer
            .split("id=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        for path in layer.split("<path d=\"").skip(1) {
            let d = path.split('"').next().unwrap();
            let mut tokens = d.split_whitespace();
            let (mut at, mut start) = ([0.0; 2], [0.0; 2]);
            while let Some(t) = tokens.next() {
                let (op, x) = t.split_at(1);
                if op == "Z" {
                    out.push((name.to_string(), at, start));
                    at = start;
                    continue;
                }
                let p = [x.parse().unwrap(), tokens.next().unwrap().parse().unwrap()];
                match op {
                    "M" => start = p,
                    "L" => out.push((name.to_string(), at, p)),
                    other => panic!("unexpected path command {other}"),
                }
                at = p;
            }
        }
    }
    out
}

#[test]
fn sheet_svg_holds_only_what_is_cut_or_scored_one_path_per_line() {
    // What cutter and laser software take: no media frame, hairlines, one colour per
    // layer; the outline one closed path; each crease's dashes one path element; and,
    // segment by segment, exactly the toolpath.
    let machine = Machine::load("generic-hpgl").unwrap();
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &a3()).unwrap();
        let svg = output_text(&out, "sheet.svg");
        let name = path.display();
        assert!(!svg.contains("<rect") && !svg.contains("<line"), "{name}");
        // Every layer drawn in hairlines.
        assert_eq!(
            svg.matches("stroke-width=\"0.0254\"").count(),
            svg.matches("<g ").count(),
            "{name}"
        );
        let strokes = &out.toolpath.strokes;
        for kind in [LineKind::Cut, LineKind::Mountain, LineKind::Valley] {
            let layer = svg.split(&format!("id=\"{}\"", kind.name())).nth(1);
            let ours: Vec<_> = strokes.iter().filter(|s| s.kind == kind).collect();
            let Some(layer) = layer else {
                assert!(ours.is_empty(), "{name}: no {} layer", kind.name());
                continue;
            };
            let layer = layer.split("</g>").next().unwrap();
            let paths = layer.matches("<path").count();
            if kind == LineKind::Cut {
                assert_eq!(paths, 1, "{name}: the outline is one path");
                let d = layer
                    .split("d=\"")
                    .nth(1)
                    .unwrap()
                    .split('"')
                    .next()
                    .unwrap();
                assert_eq!(
                    d.matches('M').count(),
                    d.matches('Z').count(),
                    "{name}: every loop of the outline is closed"
                );
            } else {
                let mut lines: Vec<usize> = ours.iter().map(|s| s.line).collect();
                lines.sort_unstable();
                lines.dedup();
                assert_eq!(
                    paths,
                    lines.len(),
                    "{name}: one path per {} crease",
                    kind.name()
                );
            }
        }
        // Segment by segment the toolpath (the SVG's y runs down the sheet).
        let h = out.toolpath.media.height;
        let drawn = svg_segments(svg);
        assert_eq!(drawn.len(), strokes.len(), "{name}");
        let near = |a: [f64; 2], b: Vec2| (a[0] - b.x).hypot(a[1] - (h - b.y)) < 1e-3;
        for s in strokes {
            assert!(
                drawn.iter().any(|(layer, a, b)| layer == s.kind.name()
                    && ((near(*a, s.from) && near(*b, s.to))
                        || (near(*a, s.to) && near(*b, s.from)))),
                "{name}: stroke {s:?} missing from sheet.svg"
            );
        }
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

#[test]
fn every_fold_is_scored_or_named_in_the_report() {
    // A fold too short for a dash once the junction clearance is kept (a 0.6 mm valley
    // on miura-collapse) used to vanish in silence.
    let machine = Machine::load("generic-hpgl").unwrap();
    let mut named = 0;
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &a3()).unwrap();
        let strokes: Vec<_> = out
            .toolpath
            .strokes
            .iter()
            .chain(out.back.iter().flat_map(|b| &b.strokes))
            .collect();
        let listed = out.report["sheet"]["unscored_creases"].as_array().unwrap();
        for (i, line) in out.sheet.lines.iter().enumerate() {
            if !matches!(line.kind, LineKind::Mountain | LineKind::Valley) {
                continue;
            }
            let scored = strokes.iter().any(|s| s.line == i);
            let in_report = listed.iter().any(|u| {
                u["kind"] == line.kind.name()
                    && (u["length_mm"].as_f64().unwrap() - line.length()).abs() < 1e-9
                    && (u["from_mm"][0].as_f64().unwrap() - line.a.x).abs() < 1e-9
            });
            assert!(
                scored != in_report,
                "{}: line {i} scored {scored}, named {in_report}",
                path.display()
            );
            named += usize::from(in_report);
        }
    }
    assert!(
        named > 0,
        "no design has a fold too short to score: the test checks nothing"
    );
}

/// Closest distance between two segments in the plane (zero if they cross).
fn segment_distance(a: &Stroke, b: &Stroke) -> f64 {
    let cross = |o: Vec2, p: Vec2, q: Vec2| (p - o).perp(&(q - o));
    let crosses = cross(a.from, a.to, b.from) * cross(a.from, a.to, b.to) < 0.0
        && cross(b.from, b.to, a.from) * cross(b.from, b.to, a.to) < 0.0;
    if crosses {
        return 0.0;
    }
    [
        distance_to_segment(a.from, b),
        distance_to_segment(a.to, b),
        distance_to_segment(b.from, a),
        distance_to_segment(b.to, a),
    ]
    .into_iter()
    .fold(f64::INFINITY, f64::min)
}

#[test]
fn no_dash_comes_within_the_clearance_of_the_cut_or_of_another_creases_dash() {
    // Measured in the plane, pair by pair, on every bundled design and every anchor
    // that fabricates: waterbomb-curved, miura-collapse, plane-crumpled and resch-dome
    // had dashes 0.20-0.46 mm from the cut or from a neighbour's dashes.
    let machine = Machine::load("generic-hpgl").unwrap();
    let clearance = machine.clearance_mm;
    let designs = designs_and_anchors();
    // Fitted to A3, and cut even where verification objects (box.fold, wavy_pleats):
    // scoring is what is measured here.
    let options = FabOptions {
        fit: true,
        force: true,
        ..a3()
    };
    let mut pairs = 0usize;
    for path in &designs {
        let mesh = crease::io::read(path).unwrap();
        let out = fabricate(&mesh, &machine, &options)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let strokes = &out.toolpath.strokes;
        let is_dash = |s: &Stroke| matches!(s.kind, LineKind::Mountain | LineKind::Valley);
        // A coarse grid keeps the pairwise check near linear on BoxPleatPyramid.
        let cell = 10.0;
        let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> = Default::default();
        for (i, s) in strokes.iter().enumerate() {
            let lo = s.from.inf(&s.to) - Vec2::repeat(clearance);
            let hi = s.from.sup(&s.to) + Vec2::repeat(clearance);
            for x in (lo.x / cell).floor() as i64..=(hi.x / cell).floor() as i64 {
                for y in (lo.y / cell).floor() as i64..=(hi.y / cell).floor() as i64 {
                    grid.entry((x, y)).or_default().push(i);
                }
            }
        }
        let mut near = std::collections::HashSet::new();
        for list in grid.values() {
            for (k, &i) in list.iter().enumerate() {
                for &j in &list[k + 1..] {
                    near.insert((i.min(j), i.max(j)));
                }
            }
        }
        for (i, j) in near {
            let (a, b) = (&strokes[i], &strokes[j]);
            if a.line == b.line || !(is_dash(a) || is_dash(b)) {
                continue;
            }
            pairs += 1;
            let d = segment_distance(a, b);
            assert!(
                d >= clearance - 1e-6,
                "{}: a {} dash of line {} passes {d:.3} mm from a {} stroke of line {}",
                path.display(),
                a.kind.name(),
                a.line,
                b.kind.name(),
                b.line
            );
        }
    }
    assert!(
        pairs > 1000,
        "only {pairs} pairs near each other: the check checks nothing"
    );
}

/// Every bundled design and every anchor file.
fn designs_and_anchors() -> Vec<PathBuf> {
    let anchors = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/anchors/data");
    let mut designs = patterns();
    for sub in ["fold", "origamisimulator"] {
        for e in std::fs::read_dir(anchors.join(sub)).unwrap() {
            let p = e.unwrap().path();
            if matches!(p.extension().and_then(|e| e.to_str()), Some("fold" | "svg")) {
                designs.push(p);
            }
        }
    }
    designs
}

#[test]
fn mountain_and_valley_read_apart_on_every_crease_however_short() {
    // On BoxPleatPyramid at 180 mm, 512 mountain dashes were 1.53 mm against the valleys'
    // 1.5 mm on the same pen. Now a mountain mark is a dash at least 0.5 mm longer than
    // any valley dash, or a close pair of short dashes, which valleys never make.
    let machine = Machine::load("generic-hpgl").unwrap();
    let settings = machine.score_settings();
    let valley = settings.codes[&LineKind::Valley].unwrap().cut;
    let options = FabOptions {
        fit: true,
        force: true,
        ..a3()
    };
    let mut pairs = 0;
    for path in designs_and_anchors() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &options)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let strokes = &out.toolpath.strokes;
        // A close pair: two dashes of one line, each under half a valley dash, no further
        // apart than the shorter is long.
        let in_pair = |s: &Stroke| {
            s.length() < valley / 2.0
                && strokes.iter().any(|o| {
                    o != s
                        && o.line == s.line
                        && o.length() < valley / 2.0
                        && [o.from, o.to].iter().any(|p| {
                            (p - s.from).norm().min((p - s.to).norm())
                                <= s.length().max(o.length()) + 1e-6
                        })
                })
        };
        for s in strokes {
            match s.kind {
                LineKind::Mountain => {
                    let long = s.length() >= valley + crease::fab::score::DISTINCT_MM - 1e-6;
                    pairs += usize::from(!long);
                    assert!(
                        long || in_pair(s),
                        "{}: a {:.2} mm mountain dash reads as a valley",
                        path.display(),
                        s.length()
                    );
                }
                LineKind::Valley => assert!(
                    s.length() <= valley + 1e-6 && !in_pair(s),
                    "{}: a {:.2} mm valley dash reads as a mountain",
                    path.display(),
                    s.length()
                ),
                _ => {}
            }
        }
    }
    assert!(
        pairs > 0,
        "no short mountain on any design: the test checks nothing"
    );
}

#[test]
fn the_profile_chooses_what_folds_too_short_to_score_get() {
    // miura-collapse has folds too short for a dash once the junction clearance is kept.
    // With short_folds = "dash" each gets one dash centred on it; with "solid" a cut along
    // it; the report names them either way, with what they got.
    let mesh = crease::io::read(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura-collapse.fold"),
    )
    .unwrap();
    let generic = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/generic-hpgl.toml"),
    )
    .unwrap();
    let with = |choice: &str| {
        let text = generic.replace(
            "protocol = \"hpgl\"",
            &format!("protocol = \"hpgl\"\nshort_folds = \"{choice}\""),
        );
        let machine = Machine::parse(&text).unwrap();
        fabricate(&mesh, &machine, &a3()).unwrap()
    };
    let plain = with("nothing");
    let short = plain.report["sheet"]["unscored_creases"]
        .as_array()
        .unwrap()
        .clone();
    assert!(!short.is_empty(), "miura-collapse has short folds");
    let lines_of = |out: &crease::pipeline::FabOutput, i: usize| -> Vec<Stroke> {
        out.toolpath
            .strokes
            .iter()
            .copied()
            .filter(|s| s.line == i)
            .collect()
    };
    let short_lines: Vec<usize> = (0..plain.sheet.lines.len())
        .filter(|&i| {
            matches!(
                plain.sheet.lines[i].kind,
                LineKind::Mountain | LineKind::Valley
            ) && lines_of(&plain, i).is_empty()
        })
        .collect();
    assert_eq!(short_lines.len(), short.len());
    for (choice, given) in [("dash", "a centred dash"), ("solid", "a solid cut")] {
        let out = with(choice);
        let listed = out.report["sheet"]["unscored_creases"].as_array().unwrap();
        assert_eq!(listed.len(), short.len(), "{choice}: still named");
        assert!(listed.iter().all(|u| u["given"] == given), "{choice}");
        assert!(
            out.warnings.iter().any(|w| w.contains(given)),
            "{choice}: {:?}",
            out.warnings
        );
        for &i in &short_lines {
            let line = &out.sheet.lines[i];
            let got = lines_of(&out, i);
            assert_eq!(got.len(), 1, "{choice}: one mark on line {i}");
            let s = got[0];
            let middle = (line.a + line.b) / 2.0;
            assert!(((s.from + s.to) / 2.0 - middle).norm() < 1e-9, "centred");
            if choice == "solid" {
                assert!(
                    (s.length() - line.length()).abs() < 1e-9,
                    "solid: the whole fold"
                );
            } else {
                let code = machine_code(line.kind);
                assert!(
                    (s.length() - code.min(line.length())).abs() < 1e-9,
                    "a dash"
                );
            }
        }
    }
}

/// The generic profile's dash length for a kind.
fn machine_code(kind: LineKind) -> f64 {
    Machine::load("generic-hpgl")
        .unwrap()
        .score_settings()
        .codes[&kind]
        .unwrap()
        .cut
}

#[test]
fn a_later_run_leaves_no_files_of_an_earlier_one_and_a_failed_run_touches_nothing() {
    let dir = std::env::temp_dir().join(format!("crease-fab-stale-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let design = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura.fold");
    let fab = |extra: &[&str]| {
        let mut args = vec![
            "fab",
            design.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        run_crease(&args)
    };
    let (code, _, err) = fab(&["--mountains-from-back"]);
    assert_eq!(code, 0, "{err}");
    std::fs::write(dir.join("sheet-back.hpgl.journal"), "{}").unwrap();
    assert!(dir.join("sheet-back.hpgl").is_file() && dir.join("sheet-back.svg").is_file());
    // A failed run (a width too small to cut) leaves the earlier run whole.
    let (code, _, _) = fab(&["--width", "1"]);
    assert_eq!(code, 2);
    assert!(dir.join("sheet-back.hpgl").is_file());
    // A run without the back job removes the old one and its journal.
    let (code, _, err) = fab(&[]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("sheet-back.hpgl") && err.contains("earlier run"),
        "{err}"
    );
    for stale in [
        "sheet-back.hpgl",
        "sheet-back.svg",
        "sheet-back.hpgl.journal",
    ] {
        assert!(!dir.join(stale).exists(), "{stale} left over");
    }
    // A GP-GL machine's run replaces sheet.hpgl by sheet.gpgl.
    let (code, _, err) = fab(&["--machine", "graphtec-ce"]);
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("sheet.gpgl").is_file() && !dir.join("sheet.hpgl").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
