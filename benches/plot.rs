//! `cargo bench --bench plot`: streaming a real job to the emulated plotter (9600 baud
//! drawing 600 B/s, and query mode also at 115200 baud drawing 2000 B/s) with a 1024-byte
//! buffer; reports the share of time the plotter sat idle while the job
//! was unfinished (aim: at most 2% in query mode), per flow mode.

use crease::plotter::{stream, Emulator, EmulatorConfig, Flow, FlowMode, Language, StreamOptions};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

fn main() {
    let machine = crease::machine::Machine::load("generic-hpgl").unwrap();
    let mesh =
        crease::io::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura-bent.fold"))
            .unwrap();
    let out = crease::pipeline::fabricate(&mesh, &machine, &Default::default()).unwrap();
    let job = out
        .files
        .iter()
        .find(|f| f.0 == "sheet.hpgl")
        .unwrap()
        .1
        .clone();
    let dir = std::env::temp_dir().join(format!("crease-bench-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let job_path = dir.join("job.hpgl");
    std::fs::write(&job_path, &job).unwrap();
    println!("{} bytes of HP-GL", job.len());
    for (flow, emu, baud, rate) in [
        (FlowMode::Query, Flow::None, 9600, 600.0),
        (FlowMode::Query, Flow::None, 115200, 2000.0),
        (FlowMode::XonXoff, Flow::XonXoff, 9600, 600.0),
        (FlowMode::RtsCts, Flow::RtsCts, 9600, 600.0),
        (FlowMode::None, Flow::None, 9600, 600.0),
    ] {
        let link = dir.join(format!("plotter-{flow:?}-{baud}"));
        let emulator = Emulator::start(
            &link,
            EmulatorConfig {
                flow: emu,
                rate,
                baud,
                ..Default::default()
            },
        )
        .unwrap();
        let options = StreamOptions {
            device: false,
            port: link.clone(),
            baud,
            language: Language::Hpgl,
            flow,
            buffer: 1024,
            resume: false,
            answer_timeout: Duration::from_secs(10),
        };
        let report = stream(
            &job,
            &job_path,
            &options,
            &mut |_| {},
            &AtomicBool::new(false),
        )
        .unwrap();
        emulator.wait_idle(Duration::from_millis(300), Duration::from_secs(60));
        let s = emulator.stop();
        println!(
            "{flow:>8?} at {baud} baud, drawing {rate} B/s: {:.1} s, idle {:.2}% of the job ({:.2} s of {:.1} s), {} bytes lost",
            report.elapsed.as_secs_f64(),
            100.0 * s.idle.as_secs_f64() / s.busy_span.as_secs_f64().max(1e-9),
            s.idle.as_secs_f64(),
            s.busy_span.as_secs_f64(),
            s.lost
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
