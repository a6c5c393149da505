//! Machine profiles with absurd values are refused with one line naming the file and the
//! key, instead of being accepted (a 1e-5 mm dash used to take gigabytes).

use crate::common;

use common::run_crease;
use crease::fab::LineKind;
use crease::machine::Machine;
use std::path::Path;

fn generic() -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/generic-hpgl.toml"),
    )
    .unwrap()
}

#[test]
fn every_field_out_of_range_is_refused_naming_its_key() {
    let text = generic();
    assert!(Machine::parse(&text).is_ok());
    let cases = [
        ("units_per_mm = 40.0", "units_per_mm = 0.0", "units_per_mm"),
        ("units_per_mm = 40.0", "units_per_mm = 1e9", "units_per_mm"),
        ("margin_mm = 10.0", "margin_mm = -1.0", "margin_mm"),
        ("margin_mm = 10.0", "margin_mm = nan", "margin_mm"),
        ("baud = 9600", "baud = 9601", "baud"),
        ("buffer_bytes = 1024", "buffer_bytes = 0", "buffer_bytes"),
        (
            "pen_up_speed_mm_s = 200.0",
            "pen_up_speed_mm_s = 0.0",
            "pen_up_speed_mm_s",
        ),
        ("clearance_mm = 1.0", "clearance_mm = inf", "clearance_mm"),
        ("pen = 2", "pen = 99", "tools.mountain.pen"),
        (
            "speed_mm_s = 100.0",
            "speed_mm_s = -5.0",
            "tools.cut.speed_mm_s",
        ),
        ("force = 120.0", "force = 0.0", "tools.cut.force"),
        (
            "dash = [3.0, 1.5]",
            "dash = [1e-5, 1e-5]",
            "tools.mountain.dash",
        ),
        ("dash = [3.0, 1.5]", "dash = [3.0]", "line"),
        ("dash = [3.0, 1.5]", "dash = [3.0, 1.5, 2.0]", "line"),
        ("baud = 9600", "baud = \"fast\"", "key baud"),
    ];
    for (from, to, key) in cases {
        assert!(text.contains(from), "{from}");
        let bad = text.replacen(from, to, 1);
        let err = Machine::parse(&bad).expect_err(to);
        assert!(err.contains(key), "{to}: {err}");
        assert!(!err.contains('\n'), "{to}: one line: {err}");
    }
}

#[test]
fn protocols_and_connections_are_checked_naming_their_key() {
    // Every bundled profile loads, whatever its protocol.
    for name in crease::machine::known_machines() {
        Machine::load(&name).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
    let text = generic();
    let graphtec = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/graphtec-ce.toml"),
    )
    .unwrap();
    let cases = [
        (
            &text,
            "protocol = \"hpgl\"",
            "protocol = \"camm\"",
            "protocol",
        ),
        (&text, "baud = 9600\n", "", "needs baud"),
        (
            &text,
            "protocol = \"hpgl\"",
            "protocol = \"hpgl\"\nshort_folds = \"perforate\"",
            "short_folds",
        ),
        (
            &text,
            "flow_control = \"xonxoff\"",
            "flow_control = \"dtr\"",
            "flow_control",
        ),
        (
            &text,
            "protocol = \"hpgl\"",
            "protocol = \"dxf\"",
            "connection = \"file\"",
        ),
        (
            &text,
            "protocol = \"hpgl\"",
            "protocol = \"svg\"",
            "connection = \"file\"",
        ),
        (
            &text,
            "protocol = \"hpgl\"",
            "protocol = \"hpgl\"\nsteps = [\"Upload sheet.svg\", \"x\"]\nsoftware = 3",
            "software",
        ),
        (
            &text,
            "protocol = \"hpgl\"",
            &format!("protocol = \"hpgl\"\nsteps = [\"{}\"]", "x".repeat(400)),
            "steps",
        ),
        (
            &text,
            "protocol = \"hpgl\"",
            "protocol = \"hpgl\"\nconnection = \"usb\"",
            "connection",
        ),
        (
            &graphtec,
            "force = 14.0",
            "force = 120.0",
            "tools.cut.force",
        ),
        (
            &graphtec,
            "axis_order = \"feed-first\"",
            "axis_order = \"yx\"",
            "gpgl.axis_order",
        ),
        (
            &graphtec,
            "blade_offset_mm = 0.9",
            "blade_offset_mm = 9.0",
            "gpgl.blade_offset_mm",
        ),
    ];
    for (base, from, to, key) in cases {
        assert!(base.contains(from), "{from}");
        let err = Machine::parse(&base.replacen(from, to, 1)).expect_err(to);
        assert!(err.contains(key), "{to}: {err}");
        assert!(!err.contains('\n'), "{to}: one line: {err}");
    }
}

#[test]
fn a_closed_set_in_a_profile_is_its_type_and_anything_else_is_refused_with_file_line_and_key() {
    // Issue 48: protocol, connection, flow control, axis order, short folds, print-and-cut
    // marks and tool names are enums read by serde; a value outside the set fails to load
    // naming the file, the line and the key (with its table), and lists what it may be.
    let graphtec = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/graphtec-ce.toml"),
    )
    .unwrap();
    let loaded = Machine::parse(&graphtec).unwrap();
    assert_eq!(loaded.protocol, crease::machine::Protocol::Gpgl);
    assert_eq!(
        loaded.gpgl.as_ref().unwrap().axis_order,
        crease::machine::AxisOrder::FeedFirst
    );
    assert_eq!(
        loaded.serial_line().unwrap().flow_control,
        crease::machine::FlowMode::RtsCts
    );
    let dir = common::Scratch::new("closed-sets");
    let cases = [
        (
            "protocol = \"gpgl\"",
            "protocol = \"gp-gl\"",
            "key protocol",
            "`gpgl`",
        ),
        (
            "protocol = \"gpgl\"",
            "protocol = \"gpgl\"\nconnection = \"wifi\"",
            "key connection",
            "`usb`",
        ),
        (
            "flow_control = \"rtscts\"",
            "flow_control = \"dtr\"",
            "key flow_control",
            "`xonxoff`",
        ),
        (
            "axis_order = \"feed-first\"",
            "axis_order = \"yx\"",
            "key gpgl.axis_order",
            "`carriage-first`",
        ),
        (
            "protocol = \"gpgl\"",
            "protocol = \"gpgl\"\nshort_folds = \"perforate\"",
            "key short_folds",
            "`solid`",
        ),
        (
            "protocol = \"gpgl\"",
            "protocol = \"gpgl\"\nprint_and_cut = \"brother\"",
            "key print_and_cut",
            "`cricut`",
        ),
        (
            "[tools.cut]",
            "[tools.knife]",
            "table [tools.knife]",
            "`mountain`",
        ),
    ];
    for (i, (from, to, key, choices)) in cases.into_iter().enumerate() {
        assert!(graphtec.contains(from), "{from}");
        let path = dir.join(format!("bad-{i}.toml"));
        std::fs::write(&path, graphtec.replacen(from, to, 1)).unwrap();
        let err = Machine::load(path.to_str().unwrap())
            .expect_err(to)
            .to_string();
        assert!(
            err.starts_with(&format!("{}: line ", path.display())),
            "{to}: {err}"
        );
        assert!(err.contains(key) && err.contains(choices), "{to}: {err}");
        assert!(!err.contains('\n'), "{to}: one line: {err}");
    }
}

#[test]
fn a_file_only_machine_has_a_job_file_and_plot_refuses_it_by_name() {
    // The Cameo is written to as a USB device node; the same cutter declared file-only
    // has no line at all, so plot refuses it by name.
    let cameo = Machine::load("silhouette-cameo").unwrap();
    assert!(cameo.serial_line().is_some_and(|l| l.device));
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/silhouette-cameo.toml"),
    )
    .unwrap()
    .replace("connection = \"usb\"", "connection = \"file\"");
    let dir = common::Scratch::new("file-only");
    let profile = dir.join("cameo-file.toml");
    std::fs::write(&profile, text).unwrap();
    let file_only = Machine::load(profile.to_str().unwrap()).unwrap();
    assert!(file_only.serial_line().is_none());
    assert_eq!(file_only.job_file("sheet").as_deref(), Some("sheet.gpgl"));
    let (code, _, err) = run_crease(&[
        "plot",
        "/dev/null",
        "--port",
        "/dev/null",
        "--machine",
        profile.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cameo-file") && err.contains("file"), "{err}");
}

#[test]
fn a_bad_profile_stops_fab_with_one_line_naming_the_file() {
    let dir = common::Scratch::new("machines");
    let profile = dir.join("tiny-dash.toml");
    std::fs::write(
        &profile,
        generic().replacen("dash = [3.0, 1.5]", "dash = [1e-5, 1e-5]", 1),
    )
    .unwrap();
    let design = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura-bent.fold");
    let out = dir.join("job");
    let (code, _, err) = run_crease(&[
        "fab",
        design.to_str().unwrap(),
        "--machine",
        profile.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("tiny-dash.toml") && err.contains("dash"),
        "{err}"
    );
    assert!(!out.exists(), "nothing written");
}

#[test]
fn each_shipped_material_sets_dash_force_and_clearance_as_its_file_says() {
    // generic-hpgl cutting miura-bent in each material of materials/: the longest dash of
    // each fold kind is the material's cut, consecutive dashes of a line are its gap
    // apart, the clearance is its own, the job's forces (FS) are the profile's times its
    // force_scale, and report.json names it.
    use crease::machine::Material;
    let names = crease::machine::known_materials();
    assert!(names.len() >= 4, "{names:?}");
    let base = Machine::load("generic-hpgl").unwrap();
    let mesh =
        crease::io::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura-bent.fold"))
            .unwrap();
    let mut clearances = std::collections::BTreeSet::new();
    for name in names {
        let material = Material::load(&name).unwrap();
        let machine = base.with_material(&material);
        assert_eq!(machine.clearance_mm, material.clearance_mm, "{name}");
        clearances.insert((material.clearance_mm * 100.0) as i64);
        let options = crease::pipeline::FabOptions {
            media: Some(crease::fab::Media::parse("a3").unwrap()),
            fit: true,
            ..Default::default()
        };
        let out = crease::pipeline::fabricate(&mesh, &machine, &options).unwrap();
        assert_eq!(
            out.report.sheet.material.as_deref(),
            Some(material.name.as_str())
        );
        for (kind, [cut, gap]) in [
            (LineKind::Mountain, material.dash.mountain),
            (LineKind::Valley, material.dash.valley),
        ] {
            let dashes: Vec<_> = out
                .toolpath
                .strokes
                .iter()
                .filter(|s| s.kind == kind)
                .collect();
            let longest = dashes.iter().map(|s| s.length()).fold(0.0, f64::max);
            assert!(
                (longest - cut).abs() < 1e-6,
                "{name} {kind:?}: longest dash {longest} vs {cut}"
            );
            // Full dashes of one line follow each other a gap apart (across a junction,
            // twice the clearance apart), never closer.
            let mut gaps = 0;
            let closest = gap.min(2.0 * material.clearance_mm);
            for a in &dashes {
                for b in &dashes {
                    let full = |s: &&&crease::fab::Stroke| (s.length() - cut).abs() < 1e-6;
                    if a.line != b.line || a == b || !full(&a) || !full(&b) {
                        continue;
                    }
                    let apart = (b.from - a.to).norm();
                    assert!(
                        apart > closest - 1e-6,
                        "{name} {kind:?}: dashes {apart} mm apart"
                    );
                    gaps += usize::from((apart - gap).abs() < 1e-6);
                }
            }
            assert!(gaps > 0, "{name} {kind:?}: no two full dashes a gap apart");
        }
        // Forces as sent: the profile's times the scale, one FS per distinct force.
        let job = std::str::from_utf8(&out.files.iter().find(|f| f.0 == "sheet.hpgl").unwrap().1)
            .unwrap();
        let sent: std::collections::BTreeSet<i64> = job
            .split(';')
            .filter_map(|c| c.strip_prefix("FS"))
            .map(|v| v.parse().unwrap())
            .collect();
        let expected: std::collections::BTreeSet<i64> = base
            .tools
            .values()
            .filter_map(|t| t.force)
            .map(|f| (f * material.force_scale).round().max(1.0) as i64)
            .collect();
        assert_eq!(sent, expected, "{name}");
    }
    assert!(clearances.len() >= 3, "the materials differ in clearance");
}

#[test]
fn a_bad_material_file_is_refused_naming_its_key() {
    use crease::machine::Material;
    let good = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("materials/paper-80gsm.toml"),
    )
    .unwrap();
    assert!(Material::parse(&good).is_ok());
    for (from, to, key) in [
        ("force_scale = 0.5", "force_scale = 40.0", "force_scale"),
        ("clearance_mm = 0.8", "clearance_mm = -1.0", "clearance_mm"),
        (
            "thickness_mm = 0.1",
            "thickness_mm = 0.1\ngrain = \"long\"",
            "grain",
        ),
        (
            "mountain = [2.5, 2.0]",
            "mountain = [0.01, 2.0]",
            "dash.mountain",
        ),
        ("speed_scale = 1.0\n", "", "speed_scale"),
    ] {
        assert!(good.contains(from), "{from}");
        let err = Material::parse(&good.replacen(from, to, 1)).expect_err(to);
        assert!(err.contains(key), "{to}: {err}");
        assert!(!err.contains('\n'), "{to}: one line: {err}");
    }
    // Through the command line: exit 2, the file and the key named, nothing written.
    let dir = common::Scratch::new("material");
    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        good.replacen("force_scale = 0.5", "force_scale = 40.0", 1),
    )
    .unwrap();
    let out = dir.join("out");
    let design = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura.fold");
    let (code, _, err) = run_crease(&[
        "fab",
        design.to_str().unwrap(),
        "--material",
        bad.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("bad.toml") && err.contains("force_scale"),
        "{err}"
    );
    assert!(!out.exists());
    // `crease materials` lists each shipped material by name.
    let (code, list, _) = run_crease(&["materials"]);
    assert_eq!(code, 0);
    for name in crease::machine::known_materials() {
        assert!(
            list.lines().any(|l| l.starts_with(&name)),
            "{name} missing: {list}"
        );
    }
}

#[test]
fn thick_board_is_cut_as_panels_set_back_from_each_valley_by_half_its_gap() {
    // corrugated-3mm (hinge_gap = true) on miura-bent: panels.dxf, read with the dxf
    // crate, holds one closed outline per panel. Each valley's gap is 2·h·tan(ρ/2) with
    // ρ the design's fold there, computed here from its faces' normals; no panel comes
    // nearer a valley's midpoint than half that gap, and panels reach the midpoint of
    // every mountain longer than 20 mm (they take no gap: the membrane is on their
    // inside).
    use crease::mesh::{Vec2, Vec3};
    let material = crease::machine::Material::load("corrugated-3mm").unwrap();
    assert!(material.hinge_gap);
    let h = material.thickness_mm;
    let machine = Machine::load("generic-hpgl")
        .unwrap()
        .with_material(&material);
    let mesh =
        crease::io::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura-bent.fold"))
            .unwrap();
    let options = crease::pipeline::FabOptions {
        media: Some(crease::fab::Media::parse("a3").unwrap()),
        fit: true,
        ..Default::default()
    };
    let out = crease::pipeline::fabricate(&mesh, &machine, &options).unwrap();
    let dxf_bytes = &out.files.iter().find(|f| f.0 == "panels.dxf").unwrap().1;
    let drawing = dxf::Drawing::load(&mut std::io::Cursor::new(dxf_bytes)).unwrap();
    let mut segments: Vec<(Vec2, Vec2)> = Vec::new();
    for e in drawing.entities() {
        if let dxf::entities::EntityType::Line(l) = &e.specific {
            segments.push((Vec2::new(l.p1.x, l.p1.y), Vec2::new(l.p2.x, l.p2.y)));
        }
    }
    // Closed outlines: every end meets exactly one other segment's start or end.
    let key = |p: Vec2| ((p.x * 1e4).round() as i64, (p.y * 1e4).round() as i64);
    let mut ends = std::collections::HashMap::new();
    for (a, b) in &segments {
        *ends.entry(key(*a)).or_insert(0) += 1;
        *ends.entry(key(*b)).or_insert(0) += 1;
    }
    assert!(ends.values().all(|&n| n % 2 == 0), "an open outline");
    let hinge = out.report.hinge.as_ref().unwrap();
    assert_eq!(hinge.thickness_mm, h);
    let panels = hinge.panels;
    // report.json reads back as the report written, hinge and all.
    let text = &out.files.iter().find(|f| f.0 == "report.json").unwrap().1;
    let read = crease::pipeline::FabReport::from_text(std::str::from_utf8(text).unwrap());
    assert_eq!(read.unwrap(), out.report);
    assert!(panels > 20, "{panels} panels");
    // DXF's y grows up, as the sheet's does. The gap along a fold is measured from its
    // midpoint: at its ends other panels come to the vertex.
    let dist = |p: Vec2, a: Vec2, b: Vec2| {
        let d = b - a;
        let t = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
        (a + d * t - p).norm()
    };
    let positions = mesh.positions();
    let topology = mesh.topology();
    let normal = |f: usize| {
        let [i, j, k] = mesh.faces()[f];
        let n: Vec3 = (positions[j] - positions[i]).cross(&(positions[k] - positions[i]));
        n.normalize()
    };
    let (mut valleys, mut mountains, mut exact, mut reached) = (0, 0, 0, 0);
    let kinds = LineKind::of_mesh(&mesh);
    for (e, edge) in mesh.edges().iter().enumerate() {
        let kind = kinds[e];
        let [Some(l), Some(r)] = topology.edge_faces[e] else {
            continue;
        };
        let [a, b] = edge.vertices.map(|v| out.sheet.vertices[v]);
        match kind {
            LineKind::Valley => {
                valleys += 1;
                let rho = normal(l).dot(&normal(r)).clamp(-1.0, 1.0).acos();
                let gap = 2.0 * h * (rho.min(2.0 * 2f64.atan()) / 2.0).tan();
                let mid = (a + b) / 2.0;
                let closest = segments
                    .iter()
                    .map(|&(p, q)| dist(mid, p, q))
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    closest >= gap / 2.0 - 1e-3,
                    "edge {e}: a panel {closest:.3} mm from a valley's middle that needs {:.3}",
                    gap / 2.0
                );
                // A straight valley line takes the largest gap among its edges.
                exact += usize::from(closest <= gap / 2.0 + 1e-3);
                let reported = hinge.folds.iter().find(|f| f.edge == e).unwrap();
                assert!((reported.gap_mm - gap).abs() < 1e-6);
            }
            LineKind::Mountain => {
                mountains += 1;
                let mid = (a + b) / 2.0;
                let touching = segments
                    .iter()
                    .filter(|&&(p, q)| dist(mid, p, q) < 1e-3)
                    .count();
                // A short mountain between wide valleys is swallowed by their gaps.
                assert!(
                    touching >= 2 || (b - a).norm() < 20.0,
                    "edge {e}: the panels do not reach the mountain"
                );
                reached += usize::from(touching >= 2);
            }
            _ => {}
        }
    }
    assert!(
        valleys > 10 && mountains > 10,
        "{valleys} valleys, {mountains} mountains"
    );
    assert!(reached * 10 >= mountains * 9, "{reached} of {mountains}");
    assert!(
        exact * 2 >= valleys,
        "panels come to half the gap at {exact} of {valleys} valleys"
    );
    // Without a hinge-gap material, no panels are written.
    let plain =
        crease::pipeline::fabricate(&mesh, &Machine::load("generic-hpgl").unwrap(), &options)
            .unwrap();
    assert!(plain.files.iter().all(|f| f.0 != "panels.dxf"));
    assert!(plain.report.hinge.is_none());
}

/// A machine says which of a material's settings it takes none of, and says it truly:
/// a material differing only in that setting leaves the machine's files byte for byte
/// the same, while a machine that takes it writes a different job and says nothing.
#[test]
fn a_machine_names_the_material_settings_it_ignores_and_they_change_nothing() {
    use crease::machine::Material;
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("materials/cardstock-250gsm.toml"),
    )
    .unwrap();
    let card = Material::parse(&text).unwrap();
    let forced = Material::parse(&text.replace("force_scale = 1.0", "force_scale = 2.0")).unwrap();
    let mesh = crease::io::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura.fold"))
        .unwrap();
    let options = crease::pipeline::FabOptions::default();
    for (name, takes_force) in [
        ("generic-hpgl", true),
        ("laser-dxf", false),
        ("cricut-maker", false),
    ] {
        let base = Machine::load(name).unwrap();
        let run = |m: &Material| {
            crease::pipeline::fabricate(&mesh, &base.with_material(m), &options).unwrap()
        };
        let (a, b) = (run(&card), run(&forced));
        let job = |o: &crease::pipeline::FabOutput| {
            o.files
                .iter()
                .filter(|(f, _)| f.starts_with("sheet.") && !f.ends_with(".pdf"))
                .map(|(f, bytes)| (f.clone(), bytes.clone()))
                .collect::<Vec<_>>()
        };
        let said = a.warnings.iter().find(|w| w.contains("takes no"));
        if takes_force {
            assert_ne!(job(&a), job(&b), "{name}: force changed nothing");
            assert!(said.is_none(), "{name}: {said:?}");
        } else {
            assert_eq!(job(&a), job(&b), "{name}: force changed the job");
            let said = said.unwrap_or_else(|| panic!("{name}: {:?}", a.warnings));
            assert!(
                said.contains("force") && said.contains("Cardstock"),
                "{said}"
            );
        }
    }
}
