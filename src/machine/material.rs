//! Materials as data: `materials/*.toml` say how a sheet wants to be cut and scored (dash
//! codes, clearance, force and speed relative to the machine profile's), and `--material`
//! lays them over a machine. A machine profile's forces and speeds are set for 250 g/m²
//! cardstock, the reference every material file is relative to.

use super::profile::{text, Machine};
use crate::fab::LineKind;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// How one material is cut and scored.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Human name, e.g. "Cardstock 250 g/m²".
    pub name: String,
    /// Sheet thickness, mm.
    pub thickness_mm: f64,
    /// Distance dashes keep from junctions, the cut and other creases, mm (replaces the
    /// profile's `clearance_mm`).
    pub clearance_mm: f64,
    /// Force relative to the profile's (its values are for 250 g/m² cardstock).
    pub force_scale: f64,
    /// Speed relative to the profile's.
    pub speed_scale: f64,
    /// Perforation per fold kind, `[cut, gap]` mm (replaces the profile's where it
    /// perforates; a continuous score line stays continuous).
    pub dash: MaterialDashes,
    /// Thick enough that its panels are cut apart with a hinge gap at every valley
    /// ([`crate::fab::hinge`]): `fab` writes panels.svg and panels.dxf.
    #[serde(default)]
    pub hinge_gap: bool,
}

/// Dash codes of a material.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MaterialDashes {
    /// Mountain folds.
    pub mountain: [f64; 2],
    /// Valley folds.
    pub valley: [f64; 2],
}

/// Relative force or speed: a tenth to four times the profile's.
const SCALE: crate::limits::Range = crate::limits::Range {
    what: "a scale",
    unit: "",
    min: 0.1,
    max: 4.0,
};

/// Sheet thickness a cutter or laser takes: 0.01 to 20 mm.
const THICKNESS: crate::limits::Range = crate::limits::Range {
    what: "the thickness",
    unit: "mm",
    min: 0.01,
    max: 20.0,
};

/// Folders searched for materials by name: `$CREASE_MATERIALS`, `./materials`, and the
/// `materials/` folder crease was built from.
pub fn search_path() -> Vec<PathBuf> {
    let mut dirs = Vec::new();
    if let Ok(d) = std::env::var("CREASE_MATERIALS") {
        dirs.push(PathBuf::from(d));
    }
    dirs.push(PathBuf::from("materials"));
    dirs.push(Path::new(env!("CARGO_MANIFEST_DIR")).join("materials"));
    dirs
}

/// Why a material cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum MaterialError {
    /// No such material.
    #[error("--material {name}: no such material (known: {known}; or give a path to a .toml)")]
    Unknown {
        /// What was asked for.
        name: String,
        /// Materials found.
        known: String,
    },
    /// The material file could not be read.
    #[error("{}: {source}", path.display())]
    Unreadable {
        /// The file.
        path: PathBuf,
        /// The system's refusal.
        source: std::io::Error,
    },
    /// The material file is wrong; the cause names the key.
    #[error("{}: {cause}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the key.
        cause: String,
    },
}

/// Names of the materials found, sorted, each once.
pub fn known_materials() -> Vec<String> {
    super::lookup::toml_names(&search_path())
}

impl Material {
    /// Loads a material by name (from [`search_path`]) or by path; errors name the file
    /// and the key.
    pub fn load(name_or_path: &str) -> Result<Material, MaterialError> {
        let path = super::lookup::find_toml(name_or_path, &search_path());
        let Some(path) = path else {
            return Err(MaterialError::Unknown {
                name: name_or_path.to_string(),
                known: known_materials().join(", "),
            });
        };
        let text =
            crate::io::read_text_as_io(&path).map_err(|source| MaterialError::Unreadable {
                path: path.clone(),
                source,
            })?;
        Material::parse(&text).map_err(|cause| MaterialError::Invalid { path, cause })
    }

    /// Parses and checks material text: each refusal names its key.
    pub fn parse(source: &str) -> Result<Material, String> {
        use crate::limits::{CLEARANCE, DASH};
        let m: Material = toml::from_str(source).map_err(|e| crate::io::toml_error(source, &e))?;
        THICKNESS
            .check("thickness_mm", m.thickness_mm)
            .map_err(text)?;
        CLEARANCE
            .check("clearance_mm", m.clearance_mm)
            .map_err(text)?;
        SCALE.check("force_scale", m.force_scale).map_err(text)?;
        SCALE.check("speed_scale", m.speed_scale).map_err(text)?;
        for (kind, [cut, gap]) in [("mountain", m.dash.mountain), ("valley", m.dash.valley)] {
            DASH.check(format!("dash.{kind} cut"), cut).map_err(text)?;
            DASH.check(format!("dash.{kind} gap"), gap).map_err(text)?;
        }
        Ok(m)
    }
}

impl Machine {
    /// This machine cutting `material`: its dash codes where the profile perforates, its
    /// clearance, and forces and speeds scaled from the profile's (kept within what the
    /// machine's language takes: GP-GL pressure 1 to 33).
    pub fn with_material(&self, material: &Material) -> Machine {
        let mut m = self.clone();
        m.clearance_mm = material.clearance_mm;
        for (kind, tool) in m.tools.iter_mut() {
            let dash = match kind {
                LineKind::Mountain => Some(material.dash.mountain),
                LineKind::Valley => Some(material.dash.valley),
                LineKind::Cut | LineKind::Flat => None,
            };
            if tool.dash.is_some() {
                tool.dash = dash.or(tool.dash);
            }
            tool.force = tool.force.map(|f| {
                let f = f * material.force_scale;
                if m.protocol == super::Protocol::Gpgl {
                    f.round().clamp(1.0, 33.0)
                } else {
                    f
                }
            });
            tool.speed_mm_s = tool.speed_mm_s.map(|v| v * material.speed_scale);
        }
        m.material = Some(material.name.clone());
        m.hinge_thickness_mm = material.hinge_gap.then_some(material.thickness_mm);
        let takes = |used: fn(&super::profile::Tool) -> bool| m.tools.values().any(used);
        m.material_unused = [
            (
                takes(|t| t.dash.is_some()),
                "dash lengths (it draws whole lines)",
            ),
            (takes(|t| t.force.is_some()), "force"),
            (takes(|t| t.speed_mm_s.is_some()), "speed"),
        ]
        .into_iter()
        .filter(|(used, _)| !used)
        .map(|(_, what)| what.to_string())
        .collect();
        m
    }
}
