//! Fabrication end to end: every design in `patterns/` becomes a scored sheet whose
//! layout is isometric to the design, whose dashes keep clear of crease junctions, whose
//! HP-GL draws exactly the toolpath, and whose PDF is 1:1 with a true 100 mm scale bar.

use crate::common;

use common::fabbing::{a3, distance_to_segment, output, output_text, patterns};
use common::run_crease;
use crease::fab::{LineKind, Stroke};
use crease::machine::Machine;
use crease::mesh::{Mesh, Vec2};
use crease::output::hpgl;
use crease::pipeline::{fabricate, FabOptions};
use std::path::Path;

/// Vertices where three or more scored creases or cuts meet, on the sheet.
fn junctions(mesh: &Mesh, placed: &[Vec2]) -> Vec<Vec2> {
    let mut degree = vec![0; placed.len()];
    for (e, kind) in mesh.edges().iter().zip(LineKind::of_mesh(mesh)) {
        if kind != LineKind::Flat {
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
    // What each sheet holds, not its cutting order: a draft route (the job read-back test
    // in sheet_files.rs reads the full route's jobs on every machine).
    let options = FabOptions {
        route: crease::fab::RouteSearch::Draft,
        ..a3()
    };
    for path in patterns() {
        let design = crease::io::read(&path).unwrap();
        let out = fabricate(&design, &machine, &options)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        // A tube is laid out as the strip it is cut open to (tests/fabricate/tubes.rs
        // glues it back): the sheet's vertices are the strip's.
        let mesh = match design.is_tube() {
            true => {
                crease::geometry::unfold::unfold_tube(&design)
                    .unwrap()
                    .sheet
            }
            false => design,
        };
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
fn the_rulings_of_a_curved_crease_design_bend_and_are_not_scored() {
    // arc-pulled's rulings (unassigned) bend by degrees in the polyhedral model, as
    // Resch's tuck sides do, but they are a smooth developable's rulings: the sheet
    // scores the curved crease alone, as the smooth curve through its chords' ends.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/arc-pulled.fold");
    let mesh = crease::io::read(&path).unwrap();
    let bent = mesh
        .edges()
        .iter()
        .zip(crease::geometry::fold_angles(&mesh))
        .filter(|(e, a)| {
            e.assignment == crease::mesh::Assignment::Unassigned && a.abs() > 1f64.to_radians()
        })
        .count();
    assert!(bent > 20, "only {bent} rulings bend");
    let machine = Machine::load("generic-hpgl").unwrap();
    let out = fabricate(&mesh, &machine, &a3()).unwrap();
    let scored: Vec<&crease::fab::CreaseLine> = out
        .sheet
        .lines
        .iter()
        .filter(|l| matches!(l.kind, LineKind::Mountain | LineKind::Valley))
        .collect();
    // One scored line, the curve through the chain's vertices in order: no ruling, and
    // no chord on its own.
    assert_eq!(scored.len(), 1, "one scored line, no ruling");
    let chain = &crease::constraints::crease_chains(&mesh)[0].vertices;
    let placed = &out.sheet.vertices;
    let curve = scored[0]
        .curve
        .as_ref()
        .expect("the crease leaves as a curve");
    let through = curve.points();
    assert_eq!(through.len(), chain.len());
    let forward = (through[0] - placed[chain[0]]).norm() < 1e-9;
    for (k, &v) in chain.iter().enumerate() {
        let p = if forward {
            through[k]
        } else {
            through[through.len() - 1 - k]
        };
        assert!((p - placed[v]).norm() < 1e-9, "vertex {v}");
    }
}

#[test]
fn the_crease_pattern_svg_reimports_to_the_same_graph() {
    let machine = Machine::load("generic-hpgl").unwrap();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura-bent.fold");
    let mesh = crease::io::read(&path).unwrap();
    let out = fabricate(&mesh, &machine, &a3()).unwrap();
    let svg = output(&out, "crease-pattern.svg");
    let dir = common::Scratch::new("fab-cp");
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
            // The folding guide's page is its own test's (design/animate.rs).
            guide: crease::pipeline::Guide::Never,
            ..Default::default()
        };
        let out = fabricate(&mesh, &machine, &options).unwrap();
        let pdf = output(&out, "sheet.pdf");
        let doc = printpdf::PdfDocument::parse(pdf, &Default::default(), &mut Vec::new()).unwrap();
        // The page to fold by, then the page as cut.
        assert_eq!(doc.pages.len(), 2);
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
    let folder = common::Scratch::new("fab-bad");
    let out = folder.join("job");
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
    let broken = folder.join("broken.fold");
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
}

#[test]
fn machine_profiles_load_and_unknown_keys_are_errors() {
    for name in ["generic-hpgl", "hp7475a", "roland-cutter"] {
        let m = Machine::load(name).unwrap();
        assert!(m.tools.contains_key(&LineKind::Cut));
    }
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/generic-hpgl.toml"),
    )
    .unwrap();
    let typo = text.replace("clearance_mm", "clearence_mm");
    assert!(Machine::parse(&typo).unwrap_err().contains("clearence_mm"));
}

/// The router searched rings of grid cells around the pen, bounded by the grid's size, so
/// a small design far from the pen's origin ran out of rings ("an undone stroke remains").
/// Now it starts at the grid and visits only cells in it, in the order a full sweep would.
#[test]
fn routing_a_small_design_far_from_the_pen_keeps_every_stroke() {
    let mut strokes = Vec::new();
    for i in 0..40 {
        let x = 1000.0 + (i % 8) as f64 * 0.7;
        let y = 800.0 + (i / 8) as f64 * 0.9;
        let kind = if i % 3 == 0 {
            LineKind::Valley
        } else {
            LineKind::Mountain
        };
        strokes.push(Stroke::straight(
            kind,
            Vec2::new(x, y),
            Vec2::new(x + 0.5, y + 0.2),
            i,
        ));
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
fn a_draft_route_cuts_the_same_strokes_with_no_less_travel() {
    // `--draft-route` skips the long search: the same strokes in another order, and
    // never a shorter pen-up travel than the full search finds.
    let machine = Machine::load("generic-hpgl").unwrap();
    for name in ["resch", "miura-dome", "waterbomb-tube-bent"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("patterns/{name}.fold"));
        let mesh = crease::io::read(&path).unwrap();
        let full = fabricate(&mesh, &machine, &a3()).unwrap();
        let draft_options = FabOptions {
            route: crease::fab::RouteSearch::Draft,
            ..a3()
        };
        let draft = fabricate(&mesh, &machine, &draft_options).unwrap();
        let key = |s: &Stroke| {
            let (a, b) = if (s.from.x, s.from.y) <= (s.to.x, s.to.y) {
                (s.from, s.to)
            } else {
                (s.to, s.from)
            };
            format!("{:?} {:.9} {:.9} {:.9} {:.9}", s.kind, a.x, a.y, b.x, b.y)
        };
        let set = |o: &crease::pipeline::FabOutput| {
            let mut v: Vec<String> = o.toolpath.strokes.iter().map(key).collect();
            v.sort();
            v
        };
        assert_eq!(set(&full), set(&draft), "{name}: the same strokes");
        let (f, d) = (full.toolpath.travel(), draft.toolpath.travel());
        assert!(
            d >= f - 1e-6,
            "{name}: draft travel {d:.1} mm < full {f:.1} mm"
        );
    }
}

/// With a folder named like one of the outputs in the way, `fab` writes none of its files
/// and leaves no temporary file behind.
#[test]
fn a_folder_in_the_way_leaves_the_output_folder_untouched() {
    let dir = common::Scratch::new("fab-blocked");
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
}

#[test]
fn a_later_run_leaves_no_files_of_an_earlier_one_and_a_failed_run_touches_nothing() {
    let dir = common::Scratch::new("fab-stale");
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
        "sheet-back.dxf",
        "sheet-back.hpgl.journal",
    ] {
        assert!(!dir.join(stale).exists(), "{stale} left over");
    }
    // A GP-GL machine's run replaces sheet.hpgl by sheet.gpgl.
    let (code, _, err) = fab(&["--machine", "graphtec-ce"]);
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("sheet.gpgl").is_file() && !dir.join("sheet.hpgl").exists());
    // And a GP-GL back job goes with its journal when a later run has none.
    let (code, _, err) = fab(&["--machine", "graphtec-ce", "--mountains-from-back"]);
    assert_eq!(code, 0, "{err}");
    std::fs::write(dir.join("sheet-back.gpgl.journal"), "{}").unwrap();
    let (code, _, err) = fab(&["--machine", "graphtec-ce"]);
    assert_eq!(code, 0, "{err}");
    for stale in ["sheet-back.gpgl", "sheet-back.gpgl.journal"] {
        assert!(!dir.join(stale).exists(), "{stale} left over");
    }
}

/// What `fab` writes depends on the design and the machine only: the same bytes on one
/// worker thread as on four, so `tests/fab-outputs` (every output of every bundled
/// design on every machine, hashed before and after a change meant to keep them) compares
/// like with like on any machine. The waterbomb tube's strip has no flat layer order, and
/// report.json names the faces of its conflict: they were once narrowed for a time
/// budget, and a busy machine named 128 faces where an idle one named 96.
#[test]
fn fab_writes_the_same_bytes_on_one_thread_as_on_four() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = common::Scratch::new("same-bytes");
    for (design, machine) in [("waterbomb-tube", "laser-dxf"), ("miura", "graphtec-ce")] {
        let written: Vec<std::collections::BTreeMap<String, Vec<u8>>> = ["1", "4"]
            .iter()
            .map(|threads| {
                let out = dir.join(format!("{design}-{threads}"));
                let status = std::process::Command::new(env!("CARGO_BIN_EXE_crease"))
                    .args(["fab", &format!("patterns/{design}.fold")])
                    .args(["--machine", machine, "--force", "--fit", "--out"])
                    .arg(&out)
                    .current_dir(root)
                    .env("RAYON_NUM_THREADS", threads)
                    .output()
                    .unwrap();
                assert!(status.status.success(), "{design}: {status:?}");
                std::fs::read_dir(&out)
                    .unwrap()
                    .map(|e| {
                        let path = e.unwrap().path();
                        let name = path.file_name().unwrap().to_string_lossy().into_owned();
                        (name, std::fs::read(&path).unwrap())
                    })
                    .collect()
            })
            .collect();
        assert!(written[0].len() >= 8, "{design}: {:?}", written[0].keys());
        assert_eq!(
            written[0].keys().collect::<Vec<_>>(),
            written[1].keys().collect::<Vec<_>>()
        );
        for (name, bytes) in &written[0] {
            assert!(
                *bytes == written[1][name],
                "{design} on {machine}: {name} differs between one thread and four"
            );
        }
    }
}
