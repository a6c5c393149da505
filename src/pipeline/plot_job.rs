//! What `crease plot` sends and over what line: the job file of a `fab` folder (or a
//! file named), the machine it was made for (from `--machine`, else its report.json,
//! else the default machine of its language), the settings of that line, the job read
//! back as the machine will read it, and the back side's job that follows a two-sided
//! front. The command line only prints and streams what this decides.

use crate::machine::FlowMode;
use crate::plotter::Language;
use std::path::{Path, PathBuf};

/// A job ready to stream: its file, its text and the line it goes over.
#[derive(Clone, Debug)]
pub struct PlotJob {
    /// The job file.
    pub path: PathBuf,
    /// Its text.
    pub text: String,
    /// The line it goes over.
    pub line: JobLine,
}

/// The line a job is streamed over, and where those settings came from.
#[derive(Clone, Debug, PartialEq)]
pub struct JobLine {
    /// Where the settings came from, for messages ("--machine graphtec-ce (Graphtec CE)").
    pub source: String,
    /// The job's language.
    pub language: Language,
    /// A USB device node written as a file (connection "usb"), not a serial port.
    pub device: bool,
    /// Serial speed (0 for a device node).
    pub baud: u32,
    /// Flow control.
    pub flow: FlowMode,
    /// The machine's input buffer, bytes.
    pub buffer: usize,
}

impl JobLine {
    /// The line of the machine profile `name`, found as `source` says (for messages);
    /// refused, naming it, when the machine takes its job as a file.
    pub fn from_profile(name: &str, source: &str) -> Result<JobLine, String> {
        let m = crate::machine::Machine::load(name).map_err(|e| e.to_string())?;
        let line = m.serial_line().ok_or_else(|| {
            format!(
                "{name} ({}) takes its job as a file (connection = \"{}\"), not over a serial port: send it with the machine's own software",
                m.name, m.connection
            )
        })?;
        let language = Language::from_protocol(m.protocol).ok_or_else(|| {
            format!(
                "{name} ({}) speaks {}, which is a file for its own software, not a stream",
                m.name, m.protocol
            )
        })?;
        Ok(JobLine {
            source: format!("{source} {name} ({})", m.name),
            language,
            device: line.device,
            baud: line.baud,
            flow: line.flow_control,
            buffer: line.buffer_bytes,
        })
    }

    /// The machine a `crease fab` folder was made for, from its report.json: `None` when
    /// there is no report or it predates reports naming their line settings.
    pub fn from_report(folder: &Path) -> Result<Option<JobLine>, String> {
        let path = folder.join("report.json");
        let Ok(text) = std::fs::read_to_string(&path) else {
            return Ok(None);
        };
        let bad = |why: &str| format!("{}: {why}; name the machine with --machine", path.display());
        let json: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| bad(&format!("not JSON ({e})")))?;
        // A report of another shape was made before reports named their line.
        let Ok(report) = serde_json::from_value::<super::FabReport>(json) else {
            return Ok(None);
        };
        let sheet = &report.sheet;
        let machine = sheet.machine.as_str();
        let Some(plotter) = &sheet.plotter else {
            return match &sheet.job_files {
                // Made before reports named their line.
                None => Ok(None),
                Some(files) if files.is_empty() => Err(format!(
                    "{}: made for {machine}, which takes sheet.dxf or sheet.svg in its own software; there is no cutter job to stream",
                    folder.display()
                )),
                Some(files) => Err(format!(
                    "{}: made for {machine}, which takes {} as a file (it is not on a serial port); send it with the cutter's software",
                    folder.display(),
                    files.join(" and ")
                )),
            };
        };
        let protocol = plotter.protocol;
        let language = Language::from_protocol(protocol).ok_or_else(|| {
            bad(&format!(
                "made for {machine}, whose protocol \"{protocol}\" is not streamed"
            ))
        })?;
        Ok(Some(JobLine {
            source: format!("the job's machine ({machine}, from report.json)"),
            language,
            device: plotter.connection == crate::machine::Connection::Usb,
            baud: plotter.baud,
            flow: plotter.flow_control,
            buffer: plotter.buffer_bytes,
        }))
    }
}

/// The job file, its text, and the line it goes over: `--machine` if given, else the
/// machine the job was made for, else generic-hpgl.
pub fn open_job(job: PathBuf, machine: Option<&str>) -> Result<PlotJob, String> {
    let folder = if job.is_dir() {
        job.clone()
    } else {
        job.parent().unwrap_or(Path::new(".")).to_path_buf()
    };
    // The machine first: a folder made for a GP-GL cutter or a laser has no sheet.hpgl,
    // and saying so beats "file not found".
    let settings = match machine {
        Some(name) => JobLine::from_profile(name, "--machine")?,
        None => match JobLine::from_report(&folder)? {
            Some(s) => s,
            None if job.extension().is_some_and(|e| e == "gpgl") => {
                JobLine::from_profile("graphtec-ce", "the default GP-GL machine")?
            }
            None => JobLine::from_profile("generic-hpgl", "the default machine")?,
        },
    };
    let (name, extension) = match settings.language {
        Language::Hpgl => ("HP-GL", "hpgl"),
        Language::Gpgl => ("GP-GL", "gpgl"),
    };
    let job_path = if job.is_dir() {
        job.join(format!("sheet.{extension}"))
    } else {
        job
    };
    let other = if extension == "hpgl" { "gpgl" } else { "hpgl" };
    let made_for_other = job_path
        .file_name()
        .is_some_and(|f| f == format!("sheet.{extension}").as_str())
        && !job_path.exists()
        && folder.join(format!("sheet.{other}")).exists();
    if made_for_other {
        return Err(format!(
            "{}: the folder holds sheet.{other}, a job for a machine that does not speak {name} as {} does; name that machine with --machine, or make a job for this one with `crease fab --machine`",
            folder.display(),
            settings.source
        ));
    }
    if job_path.extension().is_some_and(|e| e == other) {
        return Err(format!(
            "{}: a .{other} job, but {} speaks {name}; name a machine that speaks it with --machine",
            job_path.display(),
            settings.source
        ));
    }
    let bytes = crate::io::read_file_bytes(&job_path, crate::limits::MAX_FILE_BYTES)
        .map_err(|e| e.to_string())?;
    let text = String::from_utf8(bytes)
        .map_err(|_| format!("{}: not an {name} text file", job_path.display()))?;
    Ok(PlotJob {
        path: job_path,
        text,
        line: settings,
    })
}

/// What the job draws, read back as the machine will: a file the reader cannot read is
/// named with one short line of what it met, and a job that draws nothing is refused.
pub fn pen_path(
    text: &str,
    language: Language,
    job_path: &Path,
) -> Result<crate::output::hpgl::PenPath, String> {
    let path = match language {
        Language::Hpgl => crate::output::hpgl::interpret(text),
        Language::Gpgl => crate::output::gpgl::interpret(text),
    }
    .map_err(|e| {
        // The reader quotes what it could not read: one line of it, cut short.
        let first: String = e
            .to_string()
            .lines()
            .next()
            .unwrap_or("")
            .chars()
            .take(100)
            .collect();
        format!(
            "{}: not a job this machine reads: {first}",
            job_path.display()
        )
    })?;
    if path.segments.is_empty() {
        return Err(format!(
            "{}: an empty job (no pen-down stroke): nothing to plot; make one with `crease fab`",
            job_path.display()
        ));
    }
    Ok(path)
}

impl JobLine {
    /// Seconds the line needs to carry `bytes` at `baud` (the line's own speed unless
    /// `--baud` overrides it): the floor under any plot's time.
    pub fn seconds_for(&self, bytes: usize, baud: u32) -> f64 {
        bytes as f64 / crate::machine::line_bytes_per_second(self.device, baud)
    }
}

/// After the front job of a two-sided `fab` folder (its report says two-sided), the back
/// side's job beside it (`sheet-back.hpgl` or `.gpgl`), if it is there.
pub fn back_side_job(front: &Path) -> Option<PathBuf> {
    let name = front.file_name()?.to_str()?;
    let extension = name.strip_prefix("sheet.")?;
    let folder = front.parent()?;
    let text = std::fs::read_to_string(folder.join("report.json")).ok()?;
    super::FabReport::from_text(&text).ok()?.sheet.two_sided?;
    let back = folder.join(format!("sheet-back.{extension}"));
    back.is_file().then_some(back)
}
