//! Streaming to the emulated plotter over a real pty through `serialport`: every flow mode
//! delivers the job intact, in HP-GL and GP-GL; a sender that ignores flow control loses
//! bytes (so the tests can fail); `plot` takes the job's own line and refuses to start an
//! unfinished job again. Recovery after a pulled cable or a power cut is in plot_resume.rs.

use crate::common;

use common::plotting::{cutter_job, scratch};
use common::Scratch;
use crease::output::hpgl;
use crease::plotter::{
    stream, Emulator, EmulatorConfig, Flow, FlowMode, Language, StreamError, StreamOptions,
};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// A real job: a bundled design's HP-GL from the fabrication pipeline.
fn job(design: &str) -> String {
    cutter_job(design, "generic-hpgl")
}

fn options(port: &Path, flow: FlowMode, baud: u32) -> StreamOptions {
    StreamOptions {
        device: false,
        port: port.to_path_buf(),
        baud,
        language: Language::Hpgl,
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
/// so it runs on request (`cargo test --release --test plotting -- --ignored`); the four tests
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

/// Streams a GP-GL job to a GP-GL emulator on an RTS/CTS line.
fn gpgl_run(
    text: &str,
    name: &str,
    media_loaded: bool,
) -> (Result<(), StreamError>, crease::plotter::EmulatorState) {
    let dir = scratch(name);
    let link = dir.join("cutter");
    let config = EmulatorConfig {
        baud: 9600,
        rate: 600.0,
        flow: Flow::RtsCts,
        language: Language::Gpgl,
        media_loaded,
        ..Default::default()
    };
    let emulator = Emulator::start(&link, config).unwrap();
    let job_path = dir.join("sheet.gpgl");
    std::fs::write(&job_path, text).unwrap();
    let mut opts = options(&link, FlowMode::RtsCts, 9600);
    opts.language = Language::Gpgl;
    let result = stream(
        text.as_bytes(),
        &job_path,
        &opts,
        &mut |_| {},
        &AtomicBool::new(false),
    )
    .map(|_| ());
    emulator.wait_idle(Duration::from_millis(300), Duration::from_secs(60));
    (result, emulator.stop())
}

#[test]
fn a_gpgl_job_arrives_complete_at_9600_baud() {
    let text = cutter_job("miura.fold", "graphtec-ce");
    let expected = crease::output::gpgl::interpret(&text).unwrap().segments;
    assert!(expected.len() > 100, "a real job: {} cuts", expected.len());
    let (result, state) = gpgl_run(&text, "gpgl-9600", true);
    result.unwrap();
    assert_eq!(state.lost, 0, "bytes lost");
    assert!(state.errors.is_empty(), "{:?}", state.errors);
    // Only the job's own reset came before the cuts.
    assert!(state.earlier.is_empty());
    assert_eq!(
        state.path.segments, expected,
        "the cuts differ from the job"
    );
}

#[test]
fn a_cutter_without_media_stops_the_job_with_a_clear_error() {
    let text = cutter_job("miura.fold", "graphtec-ce");
    let (result, state) = gpgl_run(&text, "gpgl-no-media", false);
    let err = result.expect_err("no media must stop the job");
    assert!(matches!(err, StreamError::NoMedia { .. }), "{err}");
    assert!(err.to_string().contains("load the sheet"), "{err}");
    // It asked before the first chunk and stopped: no job byte went, no endless polling.
    assert!(state.received <= 2, "{} bytes sent", state.received);
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
fn fab_job(design: &str, machine: &str, name: &str) -> Scratch {
    fab_job_with(design, machine, name, &[])
}

/// [`fab_job`] with more `fab` options.
fn fab_job_with(design: &str, machine: &str, name: &str, extra: &[&str]) -> Scratch {
    let dir = scratch(name);
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
    args.extend_from_slice(extra);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_crease"))
        .args(&args)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    dir
}

/// A fast XON/XOFF plotter at 115200 baud on `link`, its cable pulled after `fail_after`
/// bytes if given.
fn fast_plotter(link: &Path, fail_after: Option<usize>) -> Emulator {
    Emulator::start(
        link,
        EmulatorConfig {
            baud: 115200,
            rate: 6000.0,
            flow: Flow::XonXoff,
            fail_after,
            ..Default::default()
        },
    )
    .unwrap()
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
    let link = dir.join("plotter");
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
fn a_graphtec_job_is_plotted_as_gpgl_from_its_folder() {
    // `fab --machine graphtec-ce` writes sheet.gpgl; `plot DIR` finds it, speaks GP-GL
    // with the profile's RTS/CTS, and the cutter cuts exactly the file.
    let dir = fab_job("miura.fold", "graphtec-ce", "graphtec");
    let text = std::fs::read_to_string(dir.join("sheet.gpgl")).unwrap();
    let link = dir.join("cutter");
    let emulator = Emulator::start(
        &link,
        EmulatorConfig {
            baud: 9600,
            rate: 800.0,
            flow: Flow::RtsCts,
            language: Language::Gpgl,
            ..Default::default()
        },
    )
    .unwrap();
    let (code, err) = plot_cli(&dir, &link, &[]);
    emulator.wait_idle(Duration::from_millis(300), Duration::from_secs(60));
    let state = emulator.stop();
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("graphtec-ce") || err.contains("Graphtec"),
        "{err}"
    );
    assert_eq!(state.lost, 0);
    assert_eq!(
        state.path.segments,
        crease::output::gpgl::interpret(&text).unwrap().segments
    );
    // A GP-GL job offered to an HP-GL machine is refused before the port is opened.
    let (code, err) = plot_cli(
        &dir.join("sheet.gpgl"),
        &link,
        &["--machine", "generic-hpgl"],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains(".gpgl job") && err.contains("--machine"),
        "{err}"
    );
    // So is its folder: it holds sheet.gpgl, not the sheet.hpgl that machine would take.
    let (code, err) = plot_cli(&dir, &link, &["--machine", "generic-hpgl"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("sheet.gpgl") && err.contains("--machine") && !err.contains("No such file"),
        "{err}"
    );
}

#[test]
fn a_plain_plot_of_an_unfinished_job_sends_nothing_and_exits_2() {
    let dir = fab_job("miura.fold", "generic-hpgl", "unfinished");
    let text = std::fs::read_to_string(dir.join("sheet.hpgl")).unwrap();
    let link = dir.join("plotter");
    let plotter = |fail_after: Option<usize>| fast_plotter(&link, fail_after);
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

#[test]
fn after_the_front_of_a_two_sided_job_plot_says_how_to_go_on() {
    // The front job plotted from its folder: plot names the back job to run next and how
    // to turn the sheet; the back job plotted then cuts exactly its file and says nothing
    // more (there is no third side).
    let dir = fab_job_with(
        "miura.fold",
        "generic-hpgl",
        "two-sided",
        &["--mountains-from-back"],
    );
    let link = dir.join("plotter");
    let fast = ["--baud", "115200", "--flow", "xonxoff"];
    let plotter = || fast_plotter(&link, None);
    let emulator = plotter();
    let (code, err) = plot_cli(&dir, &link, &fast);
    emulator.wait_idle(Duration::from_millis(300), Duration::from_secs(60));
    drop(emulator.stop());
    assert_eq!(code, Some(0), "{err}");
    let back = dir.join("sheet-back.hpgl");
    assert!(
        err.contains(&back.display().to_string()) && err.contains("left to right"),
        "{err}"
    );
    let emulator = plotter();
    let (code, err) = plot_cli(&back, &link, &fast);
    emulator.wait_idle(Duration::from_millis(300), Duration::from_secs(60));
    let state = emulator.stop();
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains("left to right"), "{err}");
    let text = std::fs::read_to_string(&back).unwrap();
    assert_eq!(state.lost, 0);
    assert_eq!(
        state.path.segments,
        hpgl::interpret(&text).unwrap().segments
    );
}

#[test]
fn a_cameo_job_is_written_to_its_usb_device_node_with_status_polled() {
    // `fab --machine silhouette-cameo` then `plot DIR --port NODE`: the report says the
    // machine is a USB device, so the job is written to the node as a file (no baud, no
    // line flow control), in chunks each sent when ESC ENQ says the cutter is ready. The
    // emulator's pty stands in for /dev/usb/lp0.
    let dir = fab_job("miura.fold", "silhouette-cameo", "cameo-usb");
    let text = std::fs::read_to_string(dir.join("sheet.gpgl")).unwrap();
    let link = dir.join("lp0");
    let emulator = Emulator::start(
        &link,
        EmulatorConfig {
            baud: 115200,
            rate: 8000.0,
            flow: Flow::None,
            language: Language::Gpgl,
            ..Default::default()
        },
    )
    .unwrap();
    let (code, err) = plot_cli(&dir, &link, &["--dry-run"]);
    assert_eq!(code, Some(0), "{err}");
    let (code, err) = plot_cli(&dir, &link, &[]);
    emulator.wait_idle(Duration::from_millis(300), Duration::from_secs(60));
    let state = emulator.stop();
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("USB device"), "{err}");
    assert_eq!(state.lost, 0);
    assert_eq!(state.received, text.len() + 2 * state.status_queries);
    assert!(
        state.status_queries >= text.len() / 1024,
        "{} status checks for {} bytes",
        state.status_queries,
        text.len()
    );
    assert_eq!(
        state.path.segments,
        crease::output::gpgl::interpret(&text).unwrap().segments
    );
    // Baud and flow control mean nothing to a device node: refused, naming them.
    let (code, err) = plot_cli(&dir, &link, &["--baud", "9600"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--baud") && err.contains("USB"), "{err}");
}

#[test]
fn a_print_and_cut_job_cuts_only_after_the_cutter_finds_its_marks() {
    // `fab --print-and-cut` on the Cameo: the job searches for the marks (TB123) and the
    // sender waits for the answer. Marks found: the job arrives complete and is cut as
    // written. Marks not found: plot stops with a message naming the marks, and the
    // emulator has cut nothing (the sender sent no cut after the search).
    let dir = fab_job_with(
        "miura.fold",
        "silhouette-cameo",
        "print-and-cut-plot",
        &["--print-and-cut"],
    );
    let text = std::fs::read_to_string(dir.join("sheet.gpgl")).unwrap();
    let search = text.find("TB123").expect("the job searches for marks");
    assert!(
        search < text.find('D').unwrap(),
        "the search comes before any cut"
    );
    for found in [true, false] {
        let link = dir.join(format!("lp-{found}"));
        let emulator = Emulator::start(
            &link,
            EmulatorConfig {
                baud: 115200,
                rate: 8000.0,
                flow: Flow::None,
                language: Language::Gpgl,
                marks_found: found,
                ..Default::default()
            },
        )
        .unwrap();
        let (code, err) = plot_cli(&dir, &link, &["--restart"]);
        emulator.wait_idle(Duration::from_millis(300), Duration::from_secs(60));
        let state = emulator.stop();
        if found {
            assert_eq!(code, Some(0), "{err}");
            assert_eq!(state.lost, 0);
            assert_eq!(
                state.path.segments,
                crease::output::gpgl::interpret(&text).unwrap().segments
            );
        } else {
            assert_eq!(code, Some(1), "{err}");
            assert!(err.contains("did not find the registration marks"), "{err}");
            assert!(state.path.segments.is_empty(), "{:?}", state.path.segments);
            // The search's chunk is all that went: it ends at the search command.
            assert!(state.received <= search + 40 + 2 * state.status_queries);
        }
    }
}
