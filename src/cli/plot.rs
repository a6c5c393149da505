//! `crease plot` and `crease emulate`.

use super::out;
use crease::pipeline::plot_job::{self, JobLine};
use crease::plotter::Language;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};

/// Arguments of `crease plot`.
#[derive(clap::Args)]
pub struct PlotArgs {
    /// An .hpgl or .gpgl file, or a `crease fab` output folder (its sheet.hpgl or
    /// sheet.gpgl, as its machine speaks).
    pub job: PathBuf,
    /// Serial port, e.g. /dev/ttyUSB0.
    #[arg(long)]
    pub port: PathBuf,
    /// Machine profile for language, baud, flow control and buffer size (default: the
    /// machine the job was made for, from the report.json beside it; generic-hpgl for a
    /// bare .hpgl file, graphtec-ce for a bare .gpgl file).
    #[arg(long)]
    pub machine: Option<String>,
    /// Line speed (default: the machine's).
    #[arg(long)]
    pub baud: Option<u32>,
    /// xonxoff, rtscts, query or none (default: the machine's).
    #[arg(long)]
    pub flow: Option<String>,
    /// Continue an interrupted job from its journal.
    #[arg(long, conflicts_with = "restart")]
    pub resume: bool,
    /// Plot an interrupted job again from its first byte (what was drawn is drawn twice).
    #[arg(long)]
    pub restart: bool,
    /// Check the job and print what would be sent, without opening the port.
    #[arg(long)]
    pub dry_run: bool,
}

/// Arguments of `crease emulate`.
#[derive(clap::Args)]
pub struct EmulateArgs {
    /// Path of a symlink to the plotter's port (what `plot --port` opens).
    #[arg(long, value_name = "PATH")]
    pub link: PathBuf,
    /// Input buffer size in bytes.
    #[arg(long, value_name = "BYTES", default_value_t = 1024)]
    pub buffer: usize,
    /// Drawing rate in bytes of the job per second.
    #[arg(long, value_name = "BYTES/S", default_value_t = 600.0)]
    pub rate: f64,
    /// Line speed.
    #[arg(long, default_value_t = 9600)]
    pub baud: u32,
    /// Flow control the plotter uses: xonxoff, rtscts, query, none.
    #[arg(long, default_value = "xonxoff")]
    pub flow: String,
    /// Pull the cable after this many bytes.
    #[arg(long, value_name = "BYTES")]
    pub fail_after: Option<usize>,
    /// Plug it back in after this many milliseconds.
    #[arg(long, value_name = "MS")]
    pub reconnect_after: Option<u64>,
    /// With --fail-after: switch the plotter off too (it forgets everything).
    #[arg(long)]
    pub power_cycle: bool,
    /// The language it speaks: hpgl or gpgl.
    #[arg(long, value_name = "LANG", default_value = "hpgl")]
    pub language: String,
    /// A GP-GL cutter with no media loaded (its status says 2).
    #[arg(long)]
    pub no_media: bool,
    /// A GP-GL cutter that cannot find print-and-cut registration marks (it answers 1 to
    /// the TB123 search; default: it finds them).
    #[arg(long)]
    pub no_marks: bool,
}

/// `crease plot`: stream an HP-GL or GP-GL job to a port.
pub fn plot(args: PlotArgs) -> Result<u8, String> {
    use crease::plotter::{stream, StreamOptions};
    let plot_job::PlotJob {
        path: job_path,
        text,
        line,
    } = plot_job::open_job(args.job, args.machine.as_deref())?;
    let path = plot_job::pen_path(&text, line.language, &job_path)?;
    let (baud, flow) = line_speed_and_flow(args.baud, args.flow.as_deref(), &args.port, &line)?;
    let unfinished = stream::unfinished(text.as_bytes(), &job_path);
    if let (Some(j), false, false) = (&unfinished, args.resume, args.restart) {
        return Err(format!(
            "{}: an earlier plot of this job stopped after {} of {} bytes; run again with --resume to continue it, or --restart to plot it from the start (what was drawn is cut twice)",
            job_path.display(),
            j.received,
            j.job_len
        ));
    }
    if args.dry_run {
        let plan = Plan {
            job: &job_path,
            bytes: text.len(),
            segments: path.segments.len(),
            baud,
            flow,
            port: &args.port,
            resume: args.resume,
        };
        out(&dry_run_summary(&plan, &line));
        return Ok(0);
    }
    if args.restart {
        let journal = stream::journal_path(&job_path);
        if journal.exists() {
            std::fs::remove_file(&journal).map_err(|e| format!("{}: {e}", journal.display()))?;
        }
    }
    if line.device {
        eprintln!(
            "plotting with {}: USB device {}, status polled",
            line.source,
            args.port.display()
        );
    } else {
        eprintln!(
            "plotting with {}: {baud} baud, {flow:?} flow control",
            line.source
        );
    }
    let options = StreamOptions {
        port: args.port,
        baud,
        language: line.language,
        flow,
        buffer: line.buffer,
        device: line.device,
        resume: args.resume,
        answer_timeout: std::time::Duration::from_secs(10),
    };
    let code = stream_with_progress(&text, &job_path, &options)?;
    if code == 0 {
        if let Some(next) = back_side_next(&job_path, &options.port) {
            eprintln!("{next}");
        }
    }
    Ok(code)
}

/// The line's speed and flow control: `--baud` and `--flow` where given (a serial port
/// only), else the machine's.
fn line_speed_and_flow(
    given_baud: Option<u32>,
    given_flow: Option<&str>,
    port: &Path,
    line: &JobLine,
) -> Result<(u32, crease::plotter::FlowMode), String> {
    let baud = given_baud.unwrap_or(line.baud);
    if line.device && (given_baud.is_some() || given_flow.is_some()) {
        return Err(format!(
            "--baud and --flow are for serial ports; {} is a USB device node ({}), which has neither",
            port.display(),
            line.source
        ));
    }
    if !line.device {
        crease::limits::BAUD
            .check_count("--baud", baud as u64)
            .map_err(|e| e.to_string())?;
    }
    let flow = match given_flow {
        Some(name) => crease::plotter::FlowMode::parse(name)?,
        None => line.flow,
    };
    Ok((baud, flow))
}

/// The job `plot` is about to send, as `--dry-run` describes it.
struct Plan<'a> {
    job: &'a Path,
    bytes: usize,
    segments: usize,
    baud: u32,
    flow: crease::plotter::FlowMode,
    port: &'a Path,
    resume: bool,
}

/// What `--dry-run` says: the job's size and how it would go to the port.
fn dry_run_summary(plan: &Plan, line: &JobLine) -> String {
    let verb = if plan.resume { "resume" } else { "send" };
    if line.device {
        format!(
            "{}: {} bytes, {} pen-down segments; would {verb} to the USB device {} in chunks checked by ESC ENQ, settings from {}\n",
            plan.job.display(),
            plan.bytes,
            plan.segments,
            plan.port.display(),
            line.source
        )
    } else {
        format!(
            "{}: {} bytes, {} pen-down segments; {:.0} s on the line at {} baud; would {verb} to {} with {:?} flow control and a {}-byte buffer, settings from {}\n",
            plan.job.display(),
            plan.bytes,
            plan.segments,
            line.seconds_for(plan.bytes, plan.baud),
            plan.baud,
            plan.port.display(),
            plan.flow,
            line.buffer,
            line.source
        )
    }
}

/// After the front job of a two-sided `fab` folder, what the maker does next: turn the
/// sheet and plot the back job (whose first strokes re-cut the registration crosses).
fn back_side_next(job_path: &Path, port: &Path) -> Option<String> {
    let back = plot_job::back_side_job(job_path)?;
    Some(format!(
        "two-sided job, front done: turn the sheet over left to right (the top stays at the top), load it against the same corner, then run `crease plot {} --port {}`; its first strokes cut the registration crosses again and must run in the front's slits",
        back.display(),
        port.display()
    ))
}

/// Streams the job with a progress bar of confirmed bytes; exit 1 (journal kept) when the
/// plotter or the port fails, an error for bad input.
fn stream_with_progress(
    text: &str,
    job_path: &Path,
    options: &crease::plotter::StreamOptions,
) -> Result<u8, String> {
    let interrupted = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = interrupted.clone();
    ctrlc::set_handler(move || flag.store(true, std::sync::atomic::Ordering::SeqCst))
        .map_err(|e| e.to_string())?;
    let bar = ProgressBar::new(text.len() as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "[{bar:40}] {bytes}/{total_bytes} confirmed, {elapsed}; {msg}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    let rate = options.line_rate();
    let result = crease::plotter::stream(
        text.as_bytes(),
        job_path,
        options,
        &mut |p| {
            bar.set_position(p.confirmed as u64);
            // The line is the hard limit: what remains cannot cross it faster.
            let left = (p.total - p.confirmed) as f64 / rate;
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
                crease::plotter::stream::journal_path(job_path).display()
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
        language,
        no_media,
        no_marks,
    } = args;
    use crease::limits::{BAUD, BUFFER, DRAW_RATE};
    use crease::plotter::{emulator, EmulatorConfig, Flow};
    let text = |e: crease::limits::OutOfRange| e.to_string();
    BUFFER
        .check_count("--buffer", buffer as u64)
        .map_err(text)?;
    DRAW_RATE.check("--rate", rate).map_err(text)?;
    BAUD.check_count("--baud", baud as u64).map_err(text)?;
    let config = EmulatorConfig {
        buffer,
        rate,
        baud,
        flow: Flow::parse(&flow)?,
        fail_after,
        reconnect_after: reconnect_after.map(std::time::Duration::from_millis),
        power_cycle,
        language: Language::parse(&language)
            .ok_or_else(|| format!("--language {language}: use hpgl or gpgl"))?,
        media_loaded: !no_media,
        marks_found: !no_marks,
    };
    // Refused before the banner: a user's file at that path is never replaced.
    emulator::check_link_path(&link).map_err(|e| e.to_string())?;
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
    let (all, distinct) = state.drawn();
    let drew = if all == distinct {
        format!("{all} segments")
    } else {
        format!(
            "{all} segments, {distinct} distinct ({} drawn again after a reset or power cut)",
            all - distinct
        )
    };
    eprintln!(
        "received {} bytes, lost {}, drew {drew}, idle {:.1}% of the job, {} error(s)",
        state.received,
        state.lost,
        idle,
        state.errors.len()
    );
    Ok(if state.lost > 0 { 1 } else { 0 })
}
