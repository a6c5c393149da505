//! Machine profiles: data, not code (`machines/NAME.toml`). Unknown keys are an error, so a
//! typo in a profile is caught instead of silently ignored.

use super::protocol::{AxisOrder, Connection, FlowMode, Protocol, SerialLine};
use crate::fab::print_and_cut::MarkFamily;
use crate::fab::{DashCode, LineKind, ScoreSettings, ShortFolds};
use crate::output::{HpglSettings, ToolSetting};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One tool of a machine and how it treats its lines.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Tool {
    /// Pen or tool number.
    pub pen: u32,
    /// Cutting or drawing speed, mm/s.
    pub speed_mm_s: Option<f64>,
    /// Blade force in the machine's units.
    pub force: Option<f64>,
    /// Perforation `[cut, gap]` in mm; absent for a solid line.
    #[serde(default, deserialize_with = "cut_and_gap")]
    pub dash: Option<[f64; 2]>,
}

/// Exactly two lengths (an array of three used to be cut to its first two in silence).
fn cut_and_gap<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
    let v: Option<Vec<f64>> = Deserialize::deserialize(d)?;
    v.map(|v| match v[..] {
        [cut, gap] => Ok([cut, gap]),
        _ => Err(serde::de::Error::custom(format!(
            "dash must be two lengths [cut, gap] in mm, got {}",
            v.len()
        ))),
    })
    .transpose()
}

/// A plotter or cutter profile.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Machine {
    /// Human name.
    pub name: String,
    /// The job the machine takes: "hpgl" (sheet.hpgl), "gpgl" (sheet.gpgl, Graphtec and
    /// Silhouette), "dxf" (laser cutters: sheet.dxf and sheet.svg, no cutter job) or
    /// "svg" (cutters driven by their own design software, such as Cricut Design Space:
    /// sheet.svg with one layer per operation, Cut and Score).
    pub protocol: Protocol,
    /// How the job reaches it: "serial" (`crease plot` streams it; needs `baud`,
    /// `flow_control` and `buffer_bytes`), "usb" (`crease plot --port /dev/usb/lpN`
    /// writes it to a USB printer-class device node; needs `buffer_bytes`) or "file" (the
    /// maker's own software sends it).
    #[serde(default)]
    pub connection: Connection,
    /// Plotter units per mm.
    pub units_per_mm: f64,
    /// Default media (a4, letter, 12x12in, WxHmm).
    pub media: String,
    /// Margin the machine cannot reach, mm.
    pub margin_mm: f64,
    /// Serial speed.
    pub baud: Option<u32>,
    /// xonxoff, rtscts, query or none.
    pub flow_control: Option<FlowMode>,
    /// Input buffer of the machine, bytes.
    pub buffer_bytes: Option<usize>,
    /// Pen-up travel speed, mm/s.
    pub pen_up_speed_mm_s: f64,
    /// Distance dashes keep from points where three or more creases meet, mm.
    pub clearance_mm: f64,
    /// What a fold too short for any dash gets: "nothing" (named, to crease by hand),
    /// "dash" (one dash centred on it) or "solid" (cut along its length).
    #[serde(default)]
    pub short_folds: ShortFolds,
    /// GP-GL details (protocol "gpgl" only).
    #[serde(default)]
    pub gpgl: Option<GpglProfile>,
    /// Tools by line kind: cut, mountain, valley, and optionally flat.
    pub tools: BTreeMap<LineKind, Tool>,
    /// The software a file-connected machine's files go to (e.g. "Cricut Design Space").
    #[serde(default)]
    pub software: Option<String>,
    /// What the maker does there, step by step (at most 20, each under 300 characters):
    /// `fab` prints them and report.json keeps them.
    #[serde(default)]
    pub steps: Vec<String>,
    /// The registration marks its print-and-cut finds: "silhouette" (Type 1 marks, a
    /// GP-GL job in their frame) or "cricut" (Design Space's own frame; protocol "svg").
    #[serde(default)]
    pub print_and_cut: Option<MarkFamily>,
    /// The material laid over the profile ([`Machine::with_material`]), if any: not a
    /// profile key.
    #[serde(skip)]
    pub material: Option<String>,
    /// The thickness (mm) of a material laid over the profile whose panels take hinge
    /// gaps ([`crate::fab::hinge`]); not a profile key.
    #[serde(skip)]
    pub hinge_thickness_mm: Option<f64>,
    /// What of the material laid over the profile the machine has no use for (its
    /// dashes on a machine that scores whole lines, a force or speed it does not take),
    /// said when it cuts; not a profile key.
    #[serde(skip)]
    pub material_unused: Vec<String>,
}

/// What differs between GP-GL cutters.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GpglProfile {
    /// Order of `M`/`D` coordinates: "feed-first" (media feed, then carriage: Silhouette
    /// and Graphtec in portrait, `FN0`) or "carriage-first" (as inkcut and robocut send).
    #[serde(default)]
    pub axis_order: AxisOrder,
    /// Drag-knife blade offset, mm (`FC`, in 0.05 mm); absent or 0 for a pen.
    #[serde(default)]
    pub blade_offset_mm: Option<f64>,
}

/// Why a machine profile cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum MachineError {
    /// No such profile.
    #[error("unknown machine \"{name}\"; known: {known}")]
    Unknown {
        /// What was asked for.
        name: String,
        /// Profiles found.
        known: String,
    },
    /// The profile file could not be read.
    #[error("{path}: {source}")]
    Unreadable {
        /// The file.
        path: String,
        /// The system's refusal.
        source: std::io::Error,
    },
    /// The profile file is wrong.
    #[error("{path}: {cause}")]
    Invalid {
        /// The file.
        path: String,
        /// The cause.
        cause: String,
    },
}

/// Serial speeds a profile may name.
pub const STANDARD_BAUDS: [u32; 12] = [
    300, 600, 1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200, 230400, 460800,
];
/// Highest pen or tool number (HP-GL `SP`, GP-GL `J`).
pub const MAX_PEN: u32 = 8;
/// Shortest dash or bridge a profile may ask for, mm: a few plotter steps, below which a
/// blade only tears and a sheet of dashes grows without bound.
pub const MIN_DASH_MM: f64 = crate::limits::DASH.min;

/// Folders searched for profiles by name: `$CREASE_MACHINES`, `.`, `./machines`, and the
/// `machines/` folder crease was built from.
pub fn search_path() -> Vec<PathBuf> {
    let mut dirs = Vec::new();
    if let Ok(d) = std::env::var("CREASE_MACHINES") {
        dirs.push(PathBuf::from(d));
    }
    dirs.push(PathBuf::from("."));
    dirs.push(PathBuf::from("machines"));
    dirs.push(Path::new(env!("CARGO_MANIFEST_DIR")).join("machines"));
    dirs
}

/// Names of the profiles found in [`search_path`], sorted, each once.
pub fn known_machines() -> Vec<String> {
    // The working folder is searched by name but not listed: its .toml files are mostly
    // not profiles (Cargo.toml).
    let dirs = search_path();
    super::lookup::toml_names(dirs.iter().filter(|d| d.as_os_str() != "."))
}

impl Machine {
    /// Loads a profile by name (searched in [`search_path`]) or by path.
    pub fn load(name_or_path: &str) -> Result<Machine, MachineError> {
        let path = super::lookup::find_toml(name_or_path, &search_path());
        let path = match path {
            Some(p) => p,
            None => {
                let known = known_machines();
                return Err(MachineError::Unknown {
                    name: name_or_path.to_string(),
                    known: if known.is_empty() {
                        "none found".into()
                    } else {
                        known.join(", ")
                    },
                });
            }
        };
        let invalid = |cause: String| MachineError::Invalid {
            path: path.display().to_string(),
            cause,
        };
        let text =
            crate::io::read_text_as_io(&path).map_err(|source| MachineError::Unreadable {
                path: path.display().to_string(),
                source,
            })?;
        Machine::parse(&text).map_err(invalid)
    }

    /// Parses and checks profile text: every field within the range a real machine can
    /// have, each refusal naming its key.
    pub fn parse(text: &str) -> Result<Machine, String> {
        let m: Machine = toml::from_str(text).map_err(|e| crate::io::toml_error(text, &e))?;
        m.check_ranges()?;
        m.check_protocol()?;
        m.check_print_and_cut()?;
        for (k, t) in &m.tools {
            if let Some([c, g]) = t.dash {
                if !(c > 0.0 && g > 0.0) {
                    return Err(format!("tool {}: dash lengths must be positive", k.name()));
                }
            }
        }
        if !m.tools.contains_key(&LineKind::Cut) {
            return Err("the profile needs a \"cut\" tool for the outline".into());
        }
        Ok(m)
    }

    fn check_ranges(&self) -> Result<(), String> {
        use crate::limits::{BLADE_OFFSET, BUFFER, CLEARANCE, MARGIN, SPEED, UNITS_PER_MM};
        UNITS_PER_MM
            .check("units_per_mm", self.units_per_mm)
            .map_err(text)?;
        CLEARANCE
            .check("clearance_mm", self.clearance_mm)
            .map_err(text)?;
        MARGIN.check("margin_mm", self.margin_mm).map_err(text)?;
        crate::fab::Media::parse(&self.media).map_err(|e| format!("media: {e}"))?;
        SPEED
            .check("pen_up_speed_mm_s", self.pen_up_speed_mm_s)
            .map_err(text)?;
        if let Some(baud) = self.baud.filter(|b| !STANDARD_BAUDS.contains(b)) {
            return Err(format!(
                "baud = {baud}: not a standard rate ({})",
                STANDARD_BAUDS.map(|b| b.to_string()).join(", ")
            ));
        }
        if let Some(bytes) = self.buffer_bytes {
            BUFFER
                .check_count("buffer_bytes", bytes as u64)
                .map_err(text)?;
        }
        if let Some(offset) = self.gpgl.as_ref().and_then(|g| g.blade_offset_mm) {
            BLADE_OFFSET
                .check("gpgl.blade_offset_mm", offset)
                .map_err(text)?;
        }
        for (k, t) in &self.tools {
            check_tool(k.name(), t)?;
        }
        Ok(())
    }

    /// Protocol, connection and the settings they need, each refusal naming its key.
    fn check_protocol(&self) -> Result<(), String> {
        self.check_connection()?;
        if self.steps.len() > 20 || self.steps.iter().any(|s| s.chars().count() >= 300) {
            return Err("steps: at most 20 steps, each under 300 characters".into());
        }
        if self.gpgl.is_some() && self.protocol != Protocol::Gpgl {
            return Err("a [gpgl] table belongs to protocol \"gpgl\" only".into());
        }
        if self.protocol == Protocol::Gpgl {
            for (k, t) in &self.tools {
                if let Some(f) = t.force.filter(|f| !(1.0..=33.0).contains(f)) {
                    return Err(format!(
                        "tools.{}.force = {f}: GP-GL pressure (FX) is 1 to 33",
                        k.name()
                    ));
                }
            }
        }
        Ok(())
    }

    /// The serial line `crease plot` streams over; `None` for a file-only machine.
    pub fn serial_line(&self) -> Option<SerialLine> {
        match self.connection {
            Connection::Usb => Some(SerialLine {
                device: true,
                baud: 0,
                flow_control: FlowMode::None,
                buffer_bytes: self.buffer_bytes?,
            }),
            Connection::Serial => Some(SerialLine {
                device: false,
                baud: self.baud?,
                flow_control: self.flow_control?,
                buffer_bytes: self.buffer_bytes?,
            }),
            Connection::File => None,
        }
    }

    /// The cutter job's file name, or `None` when the machine takes the drawing itself
    /// (a laser cutter's DXF or SVG).
    pub fn job_file(&self, side: &str) -> Option<String> {
        match self.protocol {
            Protocol::Hpgl => Some(format!("{side}.hpgl")),
            Protocol::Gpgl => Some(format!("{side}.gpgl")),
            Protocol::Dxf | Protocol::Svg => None,
        }
    }

    /// Units, axis order, blade offset and tools for the GP-GL writer.
    pub fn gpgl_settings(&self) -> crate::output::GpglSettings {
        let profile = self.gpgl.clone().unwrap_or_default();
        crate::output::GpglSettings {
            units_per_mm: self.units_per_mm,
            feed_first: profile.axis_order == AxisOrder::FeedFirst,
            blade_offset_mm: self.blade_offset_mm(),
            tools: self.hpgl_settings().tools,
            registration: None,
        }
    }

    /// The connection and the line settings it needs: a serial port its baud, flow
    /// control and buffer; a USB device node its buffer and no line settings; a file
    /// nothing. Each refusal names its key.
    fn check_connection(&self) -> Result<(), String> {
        match self.connection {
            Connection::Serial => {
                let missing: Vec<&str> = [
                    ("baud", self.baud.is_none()),
                    ("flow_control", self.flow_control.is_none()),
                    ("buffer_bytes", self.buffer_bytes.is_none()),
                ]
                .iter()
                .filter(|(_, absent)| *absent)
                .map(|(k, _)| *k)
                .collect();
                if !missing.is_empty() {
                    return Err(format!(
                        "connection = \"serial\" needs {} (or connection = \"file\" for a machine crease does not stream to)",
                        missing.join(", ")
                    ));
                }
                if !self.protocol.is_cutter_job() {
                    return Err(format!(
                        "protocol \"{}\" is a file for the machine's own software: use connection = \"file\"",
                        self.protocol
                    ));
                }
            }
            Connection::Usb => {
                if !self.protocol.is_cutter_job() {
                    return Err(format!(
                        "connection = \"usb\" streams a cutter job; protocol \"{}\" is a file for the machine's own software",
                        self.protocol
                    ));
                }
                if self.buffer_bytes.is_none() {
                    return Err("connection = \"usb\" needs buffer_bytes (how much of the job to send between status checks)".into());
                }
                if self.baud.is_some() || self.flow_control.is_some() {
                    return Err("connection = \"usb\" is a device node with no baud or flow_control: leave them out".into());
                }
            }
            Connection::File => {}
        }
        Ok(())
    }

    /// Silhouette marks are found by a GP-GL job; Cricut's by Design Space, from SVG.
    fn check_print_and_cut(&self) -> Result<(), String> {
        let Some(family) = self.print_and_cut else {
            return Ok(());
        };
        let needs = match family {
            MarkFamily::Silhouette => Protocol::Gpgl,
            MarkFamily::Cricut => Protocol::Svg,
        };
        if self.protocol != needs {
            return Err(format!(
                "print_and_cut = \"{}\" needs protocol \"{needs}\", not \"{}\"",
                family.name(),
                self.protocol
            ));
        }
        Ok(())
    }

    /// Dash codes and clearance for [`crate::fab::score()`].
    pub fn score_settings(&self) -> ScoreSettings {
        ScoreSettings {
            codes: self
                .tools
                .iter()
                .map(|(k, t)| (*k, t.dash.map(|[cut, gap]| DashCode { cut, gap })))
                .collect(),
            clearance: self.clearance_mm,
            short_folds: self.short_folds,
            // A cutter's job lands on its step grid; a laser's DXF keeps the drawing exact.
            step_mm: if self.protocol.is_cutter_job() {
                1.0 / self.units_per_mm
            } else {
                0.0
            },
            // A drag knife trails its tip by the blade offset and swivels into line over
            // about that length: a shorter dash is not cut as drawn, so it is not cut.
            min_dash: ScoreSettings::default()
                .min_dash
                .max(self.blade_offset_mm()),
        }
    }

    /// The drag knife's offset (mm): a GP-GL profile's `blade_offset_mm`, else 0.
    pub fn blade_offset_mm(&self) -> f64 {
        self.gpgl
            .as_ref()
            .and_then(|g| g.blade_offset_mm)
            .unwrap_or(0.0)
    }

    /// Units and tools for the HP-GL writer.
    pub fn hpgl_settings(&self) -> HpglSettings {
        HpglSettings {
            units_per_mm: self.units_per_mm,
            tools: self
                .tools
                .iter()
                .map(|(k, t)| {
                    (
                        *k,
                        ToolSetting {
                            pen: t.pen,
                            speed: t.speed_mm_s,
                            force: t.force,
                        },
                    )
                })
                .collect(),
        }
    }

    /// Speed of the tool for a kind (mm/s), falling back to the pen-up speed.
    pub fn speed(&self, kind: LineKind) -> f64 {
        self.tools
            .get(&kind)
            .and_then(|t| t.speed_mm_s)
            .unwrap_or(self.pen_up_speed_mm_s)
    }
}

/// A range's refusal as the profile's error text (it names the key).
pub(super) fn text(e: crate::limits::OutOfRange) -> String {
    e.to_string()
}

/// A tool's pen, speed, force and dash within what a machine can do.
fn check_tool(k: &str, t: &Tool) -> Result<(), String> {
    if !(1..=MAX_PEN).contains(&t.pen) {
        return Err(format!(
            "tools.{k}.pen = {}: must be a pen from 1 to {MAX_PEN}",
            t.pen
        ));
    }
    use crate::limits::{DASH, FORCE, SPEED};
    if let Some(v) = t.speed_mm_s {
        SPEED
            .check(format!("tools.{k}.speed_mm_s"), v)
            .map_err(text)?;
    }
    if let Some(v) = t.force {
        FORCE.check(format!("tools.{k}.force"), v).map_err(text)?;
    }
    if let Some(d) = t.dash {
        for v in d {
            DASH.check(format!("tools.{k}.dash"), v).map_err(text)?;
        }
    }
    Ok(())
}
