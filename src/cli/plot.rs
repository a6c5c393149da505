//! `crease plot` and `crease emulate`.

use super::out;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;

/// Arguments of `crease plot`.
#[derive(clap::Args)]
pub struct PlotArgs {
    /// An .hpgl file, or a `crease fab` output folder (its sheet.hpgl).
    pub job: PathBuf,
    /// Serial port, e.g. /dev/ttyUSB0.
    #[arg(long)]
    pub port: PathBuf,
    /// Machine profile for baud, flow control and buffer size.
    #[arg(long, default_value = "generic-hpgl")]
    pub machine: String,
    /// Line speed (default: the machine's).
    #[arg(long)]
    pub baud: Option<u32>,
    /// xonxoff, rtscts, query or none (default: the machine's).
    #[arg(long)]
    pub flow: Option<String>,
    /// Continue an interrupted job from its journal.
    #[arg(long)]
    pub resume: bool,
    /// Check the job and print what would be sent, without opening the port.
    #[arg(long)]
    pub dry_run: bool,
}

/// Arguments of `crease emulate`.
#[derive(clap::Args)]
pub struct EmulateArgs {
    /// Path of a symlink to the plotter's port (what `plot --port` opens).
    #[arg(long)]
    pub link: PathBuf,
    /// Input buffer size in bytes.
    #[arg(long, default_value_t = 1024)]
    pub buffer: usize,
    /// Drawing rate in bytes of HP-GL per second.
    #[arg(long, default_value_t = 600.0)]
    pub rate: f64,
    /// Line speed.
    #[arg(long, default_value_t = 9600)]
    pub baud: u32,
    /// Flow control the plotter uses: xonxoff, rtscts, query, none.
    #[arg(long, default_value = "xonxoff")]
    pub flow: String,
    /// Pull the cable after this many bytes.
    #[arg(long)]
    pub fail_after: Option<usize>,
    /// Plug it back in after this many milliseconds.
    #[arg(long)]
    pub reconnect_after: Option<u64>,
    /// With --fail-after: switch the plotter off too (it forgets everything).
    #[arg(long)]
    pub power_cycle: bool,
}

/// `crease plot`: stream an HP-GL job to a port.
pub fn plot(args: PlotArgs) -> Result<u8, String> {
    let PlotArgs {
        job,
        port,
        machine,
        baud,
        flow,
        resume,
        dry_run,
    } = args;
    use crease::plotter::{stream, FlowMode, StreamOptions};
    let job_path = if job.is_dir() {
        job.join("sheet.hpgl")
    } else {
        job
    };
    let bytes = std::fs::read(&job_path).map_err(|e| format!("{}: {e}", job_path.display()))?;
    let text = String::from_utf8(bytes)
        .map_err(|_| format!("{}: not an HP-GL text file", job_path.display()))?;
    let path = crease::output::hpgl::interpret(&text)
        .map_err(|e| format!("{}: {e}", job_path.display()))?;
    let machine = crease::plotter::Machine::load(&machine).map_err(|e| e.to_string())?;
    let baud = baud.unwrap_or(machine.baud);
    let flow = FlowMode::parse(flow.as_deref().unwrap_or(&machine.flow_control))?;
    let seconds = text.len() as f64 * 10.0 / baud as f64;
    if dry_run {
        out(&format!(
            "{}: {} bytes, {} pen-down segments; {:.0} s on the line at {baud} baud; would send to {} with {:?} flow control\n",
            job_path.display(),
            text.len(),
            path.segments.len(),
            seconds,
            port.display(),
            flow
        ));
        return Ok(0);
    }
    let interrupted = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = interrupted.clone();
    ctrlc::set_handler(move || flag.store(true, std::sync::atomic::Ordering::SeqCst))
        .map_err(|e| e.to_string())?;
    let options = StreamOptions {
        port,
        baud,
        flow,
        buffer: machine.buffer_bytes,
        resume,
        answer_timeout: std::time::Duration::from_secs(10),
    };
    let bar = ProgressBar::new(text.len() as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "[{bar:40}] {bytes}/{total_bytes} confirmed, {elapsed}; {msg}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    let result = stream(
        text.as_bytes(),
        &job_path,
        &options,
        &mut |p| {
            bar.set_position(p.confirmed as u64);
            // The line is the hard limit: what remains cannot cross it faster than baud/10.
            let left = (p.total - p.confirmed) as f64 * 10.0 / baud as f64;
            bar.set_message(format!(
                "{} commands, ≥{left:.0} s left at the line rate",
                p.commands
            ));
        },
        &interrupted,
    );
    bar.finish_and_clear();
    match result {
        Ok(report) => {
            if let Some(note) = &report.resume_note {
                eprintln!("resume: {note}");
            }
            eprintln!(
                "plotted {} bytes in {:.1} s; the plotter confirmed every one",
                report.sent,
                report.elapsed.as_secs_f64()
            );
            Ok(0)
        }
        Err(e) if e.is_input_error() => Err(e.to_string()),
        Err(e) => {
            eprintln!("error: {e}");
            eprintln!(
                "journal: {}",
                crease::plotter::stream::journal_path(&job_path).display()
            );
            Ok(1)
        }
    }
}

/// `crease emulate`: an emulated plotter on a pty until Ctrl-C.
pub fn emulate(args: EmulateArgs) -> Result<u8, String> {
    let EmulateArgs {
        link,
        buffer,
        rate,
        baud,
        flow,
        fail_after,
        reconnect_after,
        power_cycle,
    } = args;
    use crease::plotter::{emulator, EmulatorConfig, Flow};
    if buffer == 0 || rate.is_nan() || rate <= 0.0 {
        return Err("--buffer and --rate must be positive".into());
    }
    let config = EmulatorConfig {
        buffer,
        rate,
        baud,
        flow: Flow::parse(&flow)?,
        fail_after,
        reconnect_after: reconnect_after.map(std::time::Duration::from_millis),
        power_cycle,
    };
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = stop.clone();
    ctrlc::set_handler(move || flag.store(true, std::sync::atomic::Ordering::SeqCst))
        .map_err(|e| e.to_string())?;
    eprintln!(
                "emulated plotter at {} ({} baud, {} flow, {buffer}-byte buffer, draws {rate} B/s); Ctrl-C to stop",
                link.display(),
                baud,
                flow
            );
    let state = emulator::run_foreground(&link, config, stop)
        .map_err(|e| format!("{}: {e}", link.display()))?;
    let idle = if state.busy_span.as_secs_f64() > 0.0 {
        100.0 * state.idle.as_secs_f64() / state.busy_span.as_secs_f64()
    } else {
        0.0
    };
    eprintln!(
        "received {} bytes, lost {}, drew {} segments, idle {:.1}% of the job, {} error(s)",
        state.received,
        state.lost,
        state.path.segments.len(),
        idle,
        state.errors.len()
    );
    Ok(if state.lost > 0 { 1 } else { 0 })
}
