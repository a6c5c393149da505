//! A tube on the sheet (issue 31): the fabrication run lays out the strip the tube is cut
//! open to, with a glue tab on one side of the seam, and reports which edge is glued to
//! which. Its refusals are plain sentences: the run (`fabricate`) says they reject the
//! design.

use super::report_json::{SeamPair, SeamReport};
use crate::fab::labels::{place_beside_edges, EdgeLabel};
use crate::fab::{glue_tab, with_tab, CreaseLine, GlueTab, SheetLabel};
use crate::mesh::{Mesh, Strip, Vec2};

/// A tube being fabricated: the strip it is cut open to (a sheet of its own, with its
/// crease pattern) and the glue tab's width.
pub(super) struct TubeStrip {
    pub strip: Strip,
    pub tab_mm: f64,
}

/// The strip of a tube with a glue tab `tab_mm` wide (already range-checked), `None` for
/// a sheet.
pub(super) fn tube_strip(mesh: &Mesh, tab_mm: f64) -> Result<Option<TubeStrip>, String> {
    if !mesh.is_tube() {
        return Ok(None);
    }
    let strip = crate::geometry::unfold::unfold_tube(mesh).map_err(|e| e.to_string())?;
    Ok(Some(TubeStrip { strip, tab_mm }))
}

impl TubeStrip {
    /// The glue tab on the seam's first side, and the lines with it.
    pub fn tab(
        &self,
        flat: &[Vec2],
        lines: Vec<CreaseLine>,
    ) -> Result<(GlueTab, Vec<CreaseLine>), crate::fab::Advice> {
        let mut hinge = vec![flat[self.strip.sides[0][0][0]]];
        hinge.extend(self.strip.sides.iter().map(|[[_, b], _]| flat[*b]));
        let tab = glue_tab(hinge, self.tab_mm)?;
        let lines = with_tab(lines, &tab);
        Ok((tab, lines))
    }

    /// The seam's numbers printed on the template: each pair's number on the tab beside
    /// its hinge and on the paper beside the edge glued onto it, so the maker matches
    /// them (`placed`: the strip's vertices in sheet millimetres, `scale` the sheet's),
    /// each where it meets no other number and no line of `lines`
    /// ([`crate::fab::labels::place_beside_edges`]).
    pub fn labels(&self, placed: &[Vec2], scale: f64, lines: &[CreaseLine]) -> Vec<SheetLabel> {
        // Half the tab's width in, and as far in on the paper; both lie on the right of
        // their edge (the tab beyond the hinge, the paper beyond the glued side).
        let depth = self.tab_mm * scale / 2.0;
        let edges: Vec<EdgeLabel> = self
            .strip
            .sides
            .iter()
            .enumerate()
            .flat_map(|(k, [[a, b], [c, d]])| {
                let text = (k + 1).to_string();
                [(*a, *b), (*c, *d)].map(|(from, to)| EdgeLabel {
                    a: placed[from],
                    b: placed[to],
                    text: text.clone(),
                    depth,
                })
            })
            .collect();
        place_beside_edges(&edges, lines)
    }

    /// The seam's pairs at their places on the sheet (`placed`: the strip's vertices in
    /// sheet millimetres).
    pub fn report(&self, placed: &[Vec2]) -> SeamReport {
        let at = |v: usize| [placed[v].x, placed[v].y];
        SeamReport {
            tab_mm: self.tab_mm,
            pairs: self
                .strip
                .sides
                .iter()
                .enumerate()
                .map(|(k, [[a, b], [c, d]])| SeamPair {
                    number: k + 1,
                    tab_side: [at(*a), at(*b)],
                    glued_side: [at(*c), at(*d)],
                })
                .collect(),
        }
    }
}
