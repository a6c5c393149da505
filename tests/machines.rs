//! Machine profiles with absurd values are refused with one line naming the file and the
//! key, instead of being accepted (a 1e-5 mm dash used to take gigabytes).

mod common;

use common::run_crease;
use crease::plotter::Machine;
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
    for name in crease::plotter::machine::known_machines() {
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
    let dir = std::env::temp_dir().join(format!("crease-file-only-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
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
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_bad_profile_stops_fab_with_one_line_naming_the_file() {
    let dir = std::env::temp_dir().join(format!("crease-machines-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
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
    let _ = std::fs::remove_dir_all(dir);
}
