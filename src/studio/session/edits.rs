//! Requests that replace or reshape the design as a whole: settings, folding, new
//! patterns, files, saving and fabrication.

use super::requests::{FabRequest, GenerateRequest, Refusal, Reply, Settings};
use super::{ok, Session};
use crate::constraints::ConstraintSet;
use crate::fab::{self, FabOption};
use crate::generate::{self, Params, PatternKind};
use crate::mesh::Mesh;
use crate::pipeline::{self, FabOptions};
use crate::solver::{FoldReport, Mode};

impl Session {
    pub(super) fn settings(&mut self, s: Settings) -> Result<Reply, Refusal> {
        let mode = s
            .mode
            .as_deref()
            .map(Mode::parse)
            .transpose()
            .map_err(Refusal::bad)?;
        let conditions = s
            .conditions
            .as_ref()
            .map(|list| {
                if list.is_empty() {
                    return Ok(Vec::new());
                }
                ConstraintSet::parse(&list.join(",")).map(|c| c.families)
            })
            .transpose()
            .map_err(Refusal::bad)?;
        let bad = |e: crate::limits::OutOfRange| Refusal::bad(e.to_string());
        if let Some(a) = s.alpha {
            crate::limits::ALPHA.check("alpha", a).map_err(bad)?;
        }
        if let Some(r) = s.remesh {
            crate::limits::REMESH.check("remesh", r).map_err(bad)?;
        }
        let to_simulation = mode == Some(Mode::Simulation) && self.design.mode == Mode::Design;
        self.release();
        self.remember();
        if to_simulation && self.design.relaid {
            // Simulation keeps the paper's lengths: those of the design as it is now, so
            // the design is finished as saving finishes it (polished, its crease pattern
            // laid out anew) before the mode changes.
            let mesh = self.finished().inspect_err(|_| {
                self.history.pop();
            })?;
            self.solver = None;
            self.design.mesh = mesh;
            self.design.relaid = false;
            self.design_changed(true);
        }
        self.settle();
        if let Some(m) = mode {
            self.design.mode = m;
        }
        if let Some(c) = conditions {
            self.design.conditions = (!c.is_empty()).then_some(c);
        }
        if let Some(a) = s.alpha {
            pipeline::set_alpha(&mut self.design.mesh, a)
                .map_err(|e| Refusal::bad(e.to_string()))?;
            self.design.alpha = a;
        }
        if s.remesh_off == Some(true) {
            self.design.remesh = None;
        } else if let Some(r) = s.remesh {
            self.design.remesh = Some(r);
        }
        self.blocked = None;
        self.report = None;
        self.in_force = None;
        self.versions.positions += 1;
        self.message = "settings changed".into();
        Ok(ok())
    }

    pub(super) fn fold(&mut self, amount: f64) -> Result<Reply, Refusal> {
        crate::limits::FRACTION
            .check("amount", amount)
            .map_err(|e| Refusal::bad(e.to_string()))?;
        if self.design.mode != Mode::Simulation {
            return Err(Refusal::conflict(
                "folding keeps every edge length: switch to simulation mode first",
            ));
        }
        self.release();
        let report = self.fold_design(amount)?;
        self.message = format!(
            "folded to {:.0}% of the targets on average",
            100.0 * report.mean_fraction
        );
        Ok(Reply::Json(serde_json::json!({
            "ok": true, "steps": report.steps, "meanFraction": report.mean_fraction,
            "error": report.error
        })))
    }

    /// Folds the design toward `amount` of its targets (simulation, rigid panels), one
    /// undoable change.
    pub(super) fn fold_design(&mut self, amount: f64) -> Result<FoldReport, Refusal> {
        self.settle();
        let (mesh, report) =
            pipeline::fold_mesh(self.design.mesh.clone(), amount, &mut |_, _, _| {})
                .map_err(|e| Refusal::failed(format!("folding failed: {e}")))?;
        self.remember();
        self.design.mesh = mesh;
        self.design_changed(false);
        Ok(report)
    }

    /// New and Open: the design replaced, and the studio as it starts — no target or fit
    /// of the last design, design mode with the new design's own conditions (a fit on a
    /// fresh pattern ran in the last design's simulation mode and missed: issue 47).
    fn replace_design(&mut self, mesh: Mesh, title: String) {
        self.release();
        self.remember();
        self.stop_fit("a new design");
        self.target = None;
        self.solver = None;
        self.design.mesh = mesh;
        self.title = title;
        self.design.pinned.clear();
        self.design.relaid = false;
        self.design.mode = Mode::Design;
        self.design.conditions = None;
        self.design.remesh = None;
        self.blocked = None;
        self.design.alpha = self.mesh_alpha();
        self.design_changed(true);
    }

    pub(super) fn generate(&mut self, g: GenerateRequest) -> Result<Reply, Refusal> {
        let kind = PatternKind::parse(&g.pattern).map_err(Refusal::bad)?;
        let d = Params::defaults(kind);
        let p = Params {
            kind,
            nx: g.nx.unwrap_or(d.nx),
            ny: g.ny.unwrap_or(d.ny),
            size: g.size.unwrap_or(d.size),
            angle_deg: g.angle.unwrap_or(d.angle_deg),
            fold: g.fold.or(d.fold),
            alpha: d.alpha,
        };
        for (name, cells) in [("nx", p.nx), ("ny", p.ny)] {
            crate::limits::STUDIO_CELLS
                .check_count(name, cells as u64)
                .map_err(|e| Refusal::bad(e.to_string()))?;
        }
        let mesh = generate::generate(&p).map_err(|e| Refusal::bad(e.to_string()))?;
        let title = format!("{} {}x{}", kind.name(), p.nx, p.ny);
        self.replace_design(mesh, title);
        self.message = format!("generated {}", self.title);
        Ok(ok())
    }

    /// Starts from a file already read (`crate::io::read_bytes`, on the connection's
    /// thread).
    pub(super) fn open(&mut self, name: &str, imported: crate::io::Imported) -> Reply {
        let stem = pipeline::names::file_stem(name);
        self.replace_design(imported.mesh, stem);
        self.message = format!("opened {name}");
        Reply::Json(serde_json::json!({"ok": true, "notes": imported.notes}))
    }

    /// The design as `deform` writes it: residual polished to 1e-12, fold angles recorded,
    /// the crease pattern unfolded anew when design mode changed lengths.
    pub(super) fn finished(&mut self) -> Result<Mesh, Refusal> {
        self.release();
        if let Some(s) = self.solver.as_mut() {
            s.polish(crate::tolerance::SAVED_RESIDUAL);
        }
        let mut mesh = self.current();
        pipeline::finish_design(&mut mesh, self.design.relaid)
            .map_err(|e| Refusal::failed(format!("the design cannot be unfolded: {e}")))?;
        mesh.title.clone_from(&self.title);
        Ok(mesh)
    }

    pub(super) fn fabricate(&mut self, r: FabRequest) -> Result<Reply, Refusal> {
        // A name the page was offered, never a path: a request opens no file it names.
        let known = crate::machine::known_machines();
        if !known.contains(&r.machine) {
            return Err(Refusal::bad(format!(
                "machine \"{}\" is not one of the studio's machines ({}); profiles in other places are for `crease fab --machine PATH`",
                r.machine.chars().take(60).collect::<String>(),
                known.join(", ")
            )));
        }
        let machine = crate::machine::Machine::load(&r.machine)
            .map_err(|e| Refusal::bad(format!("machine: {e}")))?;
        let media = r
            .media
            .as_deref()
            .filter(|m| !m.trim().is_empty())
            .map(fab::Media::parse)
            .transpose()
            .map_err(|e| Refusal::bad(format!("media: {e}")))?;
        // The width is checked where `fab`'s is (pipeline::fabricate), with the same range.
        let mesh = self.finished()?;
        let options = FabOptions {
            media,
            width: r.width,
            fit: r.fit.unwrap_or(false),
            margin: r.margin,
            tile: r.tile.unwrap_or(false),
            force: r.force.unwrap_or(false),
            ..FabOptions::default()
        };
        match pipeline::fabricate(&mesh, &machine, &options) {
            Ok(out) => {
                let mut files = out.files;
                // What the page shows: the toolpath drawn to be seen (sheet.svg is the job,
                // in hairlines a cutter's software takes).
                files.push((
                    "preview.svg".into(),
                    crate::output::svg::preview_to_string(&out.toolpath).into_bytes(),
                ));
                let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
                let reply = serde_json::json!({"ok": true, "files": names, "report": out.report});
                self.fab_files = files;
                self.message = format!("fabricated for {}", machine.name);
                Ok(Reply::Json(reply))
            }
            Err(e) if e.is_input() => Err(Refusal::bad(e.naming(&page_control))),
            // Only a failed verification is what "cut anyway" overrides, and its message
            // says so (in the page's words); a sheet too large for the media is not.
            Err(rejected) => Err(Refusal::failed(rejected.naming(&page_control))),
        }
    }
}

/// The page's name for a fabrication option a message asks to change.
fn page_control(option: FabOption) -> String {
    match option {
        FabOption::Force => "the \"cut anyway\" box".into(),
        FabOption::Tile | FabOption::Fit => format!("{} (tick it)", option.word()),
        FabOption::Media | FabOption::Width | FabOption::Margin | FabOption::Machine => {
            option.word().into()
        }
        // Not on the page (the studio never sets them): the command line's.
        FabOption::PrintAndCut | FabOption::MountainsFromBack | FabOption::Tab => {
            format!("`crease fab --{}`", option.word())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fab_messages_name_the_page_controls() {
        let too_large = crate::fab::LayoutError::TooLarge {
            need_w: 300.0,
            need_h: 400.0,
            media: "a4".into(),
            media_w: 210.0,
            media_h: 297.0,
        };
        let m = too_large.advice().naming(&page_control);
        assert!(!m.contains("--"), "{m}");
        assert!(
            m.contains("a larger media, a smaller width, or tile (tick it)"),
            "{m}"
        );
    }
}
