//! Streaming to the emulated plotter over a real pty through `serialport`: every flow mode
//! delivers the job intact; a sender that ignores flow control loses bytes (so the tests
//! can fail); a pulled cable and a power cut are recovered with --resume.

use crease::output::hpgl;
use crease::plotter::{
    stream, Emulator, EmulatorConfig, Flow, FlowMode, StreamError, StreamOptions,
};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("crease-plot-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A real job: the bundled Miura-ori's HP-GL, from the fabrication pipeline.
fn job(design: &str) -> String {
    let machine = crease::plotter::Machine::load("generic-hpgl").unwrap();
    let mesh = crease::io::read(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("patterns")
            .join(design),
    )
    .unwrap();
    let options = crease::pipeline::FabOptions {
        media: Some(crease::fab::Media::parse("a3").unwrap()),
        ..Default::default()
    };
    let out = crease::pipeline::fabricate(&mesh, &machine, &options).unwrap();
    String::from_utf8(
        out.files
            .iter()
            .find(|f| f.0 == "sheet.hpgl")
            .unwrap()
            .1
            .clone(),
    )
    .unwrap()
}

fn options(port: &Path, flow: FlowMode, baud: u32) -> StreamOptions {
    StreamOptions {
        port: port.to_path_buf(),
        baud,
        flow,
        buffer: 1024,
        resume: false,
        answer_timeout: Duration::from_secs(5),
    }
}

fn emulator_flow(flow: FlowMode) -> Flow {
    match flow {
        FlowMode::XonXoff => Flow::XonXoff,
        FlowMode::RtsCts => Flow::RtsCts,
        FlowMode::Query | FlowMode::None => Flow::None,
    }
}

fn run(
    job_text: &str,
    flow: FlowMode,
    baud: u32,
    rate: f64,
    name: &str,
) -> crease::plotter::EmulatorState {
    let dir = scratch(name);
    let link = dir.join("plotter");
    let config = EmulatorConfig {
        baud,
        rate,
        flow: emulator_flow(flow),
        ..Default::default()
    };
    let emulator = Emulator::start(&link, config).unwrap();
    let job_path = dir.join("job.hpgl");
    std::fs::write(&job_path, job_text).unwrap();
    stream(
        job_text.as_bytes(),
        &job_path,
        &options(&link, flow, baud),
        &mut |_| {},
        &AtomicBool::new(false),
    )
    .unwrap_or_else(|e| panic!("{name}: {e}"));
    emulator.wait_idle(Duration::from_millis(300), Duration::from_secs(60));
    emulator.stop()
}

fn delivers_intact(flow: FlowMode, design: &str) {
    let text = job(design);
    let expected = hpgl::interpret(&text).unwrap().segments;
    // Drawing slower than the line (600 B/s vs 960 B/s) keeps the 1024-byte buffer full.
    let state = run(&text, flow, 9600, 600.0, &format!("{flow:?}-{design}"));
    assert_eq!(state.lost, 0, "{flow:?} {design}: bytes lost");
    assert!(
        state.errors.is_empty(),
        "{flow:?} {design}: {:?}",
        state.errors
    );
    assert_eq!(
        state.path.segments, expected,
        "{flow:?} {design}: drawing differs from the job"
    );
}

#[test]
fn xonxoff_delivers_the_job_intact_at_9600_baud() {
    delivers_intact(FlowMode::XonXoff, "miura.fold");
}

#[test]
fn rtscts_delivers_the_job_intact_at_9600_baud() {
    delivers_intact(FlowMode::RtsCts, "miura.fold");
}

#[test]
fn query_delivers_the_job_intact_at_9600_baud() {
    delivers_intact(FlowMode::Query, "miura.fold");
}

#[test]
fn paced_sending_delivers_the_job_intact_at_9600_baud() {
    delivers_intact(FlowMode::None, "miura.fold");
}

/// Every design in `patterns/` in every mode at 9600 baud: about 15 minutes of line time,
/// so it runs on request (`cargo test --release --test plot -- --ignored`); the four tests
/// above cover each mode on the Miura-ori.
#[test]
#[ignore]
fn every_design_in_every_mode_at_9600_baud() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns");
    let mut designs: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".fold"))
        .collect();
    designs.sort();
    for d in designs {
        for flow in [
            FlowMode::XonXoff,
            FlowMode::RtsCts,
            FlowMode::Query,
            FlowMode::None,
        ] {
            delivers_intact(flow, &d);
        }
    }
}

#[test]
fn a_sender_that_ignores_flow_control_loses_bytes() {
    // The emulator asks with XOFF, but the host's port does not listen (no IXON): the
    // buffer overruns and the emulator counts the loss, so the tests above can fail.
    let text = job("miura.fold");
    let dir = scratch("ignore");
    let link = dir.join("plotter");
    let emulator = Emulator::start(
        &link,
        EmulatorConfig {
            baud: 9600,
            rate: 300.0,
            flow: Flow::XonXoff,
            ..Default::default()
        },
    )
    .unwrap();
    let mut port = serialport::new(link.to_string_lossy(), 9600)
        .flow_control(serialport::FlowControl::None)
        .timeout(Duration::from_millis(100))
        .open_native()
        .unwrap();
    use std::io::Write;
    port.write_all(text.as_bytes()).unwrap();
    emulator.wait_idle(Duration::from_millis(500), Duration::from_secs(60));
    let state = emulator.stop();
    assert!(state.lost > 0, "an ignored XOFF must overrun the buffer");
    let expected = hpgl::interpret(&text).unwrap().segments;
    assert_ne!(state.path.segments, expected);
}

/// Pen-down segments: (pen, from, to) in plotter units.
type Segments = Vec<(u32, [i64; 2], [i64; 2])>;

/// Streams until the emulator pulls the cable, waits for the port to come back, resumes.
fn pull_and_resume(
    seed: usize,
    flow: FlowMode,
    power_cycle: bool,
) -> (crease::plotter::EmulatorState, Segments) {
    let text = job("miura.fold");
    let expected = hpgl::interpret(&text).unwrap().segments;
    let dir = scratch(&format!("pull-{seed}-{flow:?}-{power_cycle}"));
    let link = dir.join("plotter");
    // A byte somewhere in the job, different per seed.
    let fail_after = 600 + (seed * 2654435761) % (text.len() - 1200);
    let config = EmulatorConfig {
        baud: 115200,
        rate: 6000.0,
        flow: emulator_flow(flow),
        fail_after: Some(fail_after),
        reconnect_after: Some(Duration::from_millis(700)),
        power_cycle,
        ..Default::default()
    };
    let emulator = Emulator::start(&link, config).unwrap();
    let job_path = dir.join("job.hpgl");
    std::fs::write(&job_path, &text).unwrap();
    let mut opts = options(&link, flow, 115200);
    let first = stream(
        text.as_bytes(),
        &job_path,
        &opts,
        &mut |_| {},
        &AtomicBool::new(false),
    );
    assert!(
        matches!(first, Err(StreamError::Vanished { .. })),
        "seed {seed}: {first:?}"
    );
    // The journal survives; wait for the port to come back.
    assert!(crease::plotter::stream::journal_path(&job_path).is_file());
    let start = std::time::Instant::now();
    while std::fs::symlink_metadata(&link).is_err() && start.elapsed() < Duration::from_secs(10) {
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(100));
    opts.resume = true;
    // The link can reappear a moment before the replugged port opens (a busy machine):
    // a resume that could not open it sent nothing, and is tried again, as a user would.
    let mut second = stream(
        text.as_bytes(),
        &job_path,
        &opts,
        &mut |_| {},
        &AtomicBool::new(false),
    );
    for _ in 0..5 {
        if !matches!(second, Err(StreamError::Open { .. })) {
            break;
        }
        std::thread::sleep(Duration::from_millis(300));
        second = stream(
            text.as_bytes(),
            &job_path,
            &opts,
            &mut |_| {},
            &AtomicBool::new(false),
        );
    }
    let second = second.unwrap_or_else(|e| panic!("seed {seed}: resume failed: {e}"));
    assert!(
        second.resumed_from > 0 || power_cycle,
        "seed {seed}: resumed from the start ({:?})",
        second.resume_note
    );
    emulator.wait_idle(Duration::from_millis(300), Duration::from_secs(60));
    (emulator.stop(), expected)
}

#[test]
fn a_pulled_cable_is_resumed_without_redrawing_or_skipping() {
    for seed in 1..=4 {
        for flow in [FlowMode::Query, FlowMode::XonXoff] {
            let (state, expected) = pull_and_resume(seed, flow, false);
            assert_eq!(state.lost, 0, "seed {seed} {flow:?}");
            assert_eq!(state.disconnects, 1);
            // The plotter kept power: one continuous drawing, exactly the job.
            assert_eq!(
                state.path.segments, expected,
                "seed {seed} {flow:?}: drawing differs (a segment twice or missing)"
            );
        }
    }
}

#[test]
fn a_power_cut_is_resumed_with_nothing_missing() {
    for seed in [2, 5] {
        let (state, expected) = pull_and_resume(seed, FlowMode::Query, true);
        let drawn: std::collections::HashSet<_> =
            state.earlier.iter().chain(&state.path.segments).collect();
        for s in &expected {
            assert!(drawn.contains(s), "seed {seed}: segment {s:?} never drawn");
        }
        assert!(
            !state.earlier.is_empty(),
            "seed {seed}: something was drawn before the cut"
        );
    }
}

#[test]
fn bad_ports_and_speeds_exit_2_with_a_clear_message() {
    let bin = env!("CARGO_BIN_EXE_crease");
    let dir = scratch("badport");
    let job_path = dir.join("job.hpgl");
    std::fs::write(&job_path, job("miura.fold")).unwrap();
    let run = |args: &[&str]| {
        let o = std::process::Command::new(bin)
            .arg("plot")
            .arg(&job_path)
            .args(args)
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (code, err) = run(&["--port", "/dev/no-such-plotter"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("/dev/no-such-plotter") && err.contains("no such port"),
        "{err}"
    );
    let (code, err) = run(&["--port", "/dev/null", "--baud", "1234"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("1234") && err.contains("serial speed"),
        "{err}"
    );
    // A port someone else holds.
    let link = dir.join("plotter");
    let emulator = Emulator::start(&link, EmulatorConfig::default()).unwrap();
    let _holder = serialport::new(link.to_string_lossy(), 9600)
        .open_native()
        .unwrap();
    let (code, err) = run(&["--port", link.to_str().unwrap()]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("busy"), "{err}");
    drop(emulator);
}

/// Makes a `crease fab` job folder for `design` on `machine` (A3 for the generic plotter,
/// the profile's own media otherwise).
fn fab_job(design: &str, machine: &str, name: &str) -> PathBuf {
    let dir = scratch(name).join("job");
    let input = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("patterns")
        .join(design);
    let mut args = vec![
        "fab",
        input.to_str().unwrap(),
        "--machine",
        machine,
        "--out",
    ];
    args.push(dir.to_str().unwrap());
    if machine == "generic-hpgl" {
        args.extend(["--media", "a3"]);
    }
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_crease"))
        .args(&args)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    dir
}

fn plot_cli(job: &Path, port: &Path, extra: &[&str]) -> (Option<i32>, String) {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_crease"))
        .arg("plot")
        .arg(job)
        .arg("--port")
        .arg(port)
        .args(extra)
        .output()
        .unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn a_job_is_plotted_over_the_line_of_the_machine_it_was_made_for() {
    // A roland-cutter job (RTS/CTS, 2 KiB buffer) plotted with neither --machine nor
    // --flow: the line settings come from its report.json, so the cutter's hardware
    // flow control holds it and nothing is lost. Streamed with the default profile's
    // XON/XOFF instead, the host would ignore CTS and overrun the buffer (as
    // a_sender_that_ignores_flow_control_loses_bytes shows).
    let dir = fab_job("miura.fold", "roland-cutter", "own-machine");
    let text = std::fs::read_to_string(dir.join("sheet.hpgl")).unwrap();
    let link = scratch("own-machine").join("plotter");
    let emulator = Emulator::start(
        &link,
        EmulatorConfig {
            baud: 9600,
            rate: 800.0,
            buffer: 2048,
            flow: Flow::RtsCts,
            ..Default::default()
        },
    )
    .unwrap();
    let (code, err) = plot_cli(&dir, &link, &[]);
    emulator.wait_idle(Duration::from_millis(300), Duration::from_secs(60));
    let state = emulator.stop();
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("RtsCts") && err.contains("report.json"),
        "{err}"
    );
    assert_eq!(state.lost, 0);
    assert_eq!(
        state.path.segments,
        hpgl::interpret(&text).unwrap().segments
    );
}

#[test]
fn a_plain_plot_of_an_unfinished_job_sends_nothing_and_exits_2() {
    let dir = fab_job("miura.fold", "generic-hpgl", "unfinished");
    let text = std::fs::read_to_string(dir.join("sheet.hpgl")).unwrap();
    // A fast XON/XOFF plotter, its cable pulled after `fail_after` bytes if given.
    let link = scratch("unfinished").join("plotter");
    let plotter = |fail_after: Option<usize>| {
        Emulator::start(
            &link,
            EmulatorConfig {
                baud: 115200,
                rate: 6000.0,
                flow: Flow::XonXoff,
                fail_after,
                ..Default::default()
            },
        )
        .unwrap()
    };
    let plain = ["--baud", "115200", "--flow", "xonxoff"];
    // Interrupt a real plot: the cable is pulled a third of the way in.
    let emulator = plotter(Some(text.len() / 3));
    let (code, err) = plot_cli(&dir, &link, &plain);
    assert_eq!(code, Some(1), "{err}");
    drop(emulator.stop());
    // A plain plot refuses before it opens the port: the plotter receives nothing.
    let emulator = plotter(None);
    let (code, err) = plot_cli(&dir, &link, &plain);
    std::thread::sleep(Duration::from_millis(200));
    assert_eq!(emulator.stop().received, 0, "the refused plot sent nothing");
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("--resume") && err.contains("--restart"),
        "{err}"
    );
    // --restart plots the whole job again.
    let emulator = plotter(None);
    let (code, err) = plot_cli(&dir, &link, &[&plain[..], &["--restart"]].concat());
    emulator.wait_idle(Duration::from_millis(300), Duration::from_secs(60));
    let state = emulator.stop();
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(state.lost, 0);
    assert_eq!(
        state.path.segments,
        hpgl::interpret(&text).unwrap().segments
    );
}
