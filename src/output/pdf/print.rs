//! The page a print-and-cut sheet is printed from ([`crate::fab::print_and_cut`]).

use super::template::as_cut_page;
use super::{crease_line, filled, line, rgb, save, solid_black, style, text, SCALE_BAR_MM};
use crate::fab::{LineKind, Sheet, Toolpath};
use crate::mesh::Vec2;
use printpdf::{Mm, Op, PdfPage, Pt};

/// What a print-and-cut page shows besides the sheet.
pub struct PrintPage<'a> {
    /// The Silhouette marks; none for Cricut (Design Space prints its own frame).
    pub frame: Option<&'a crate::fab::print_and_cut::MarkFrame>,
    /// The sheet's triangles (indices into its vertices), filled with `fill` if given.
    pub faces: &'a [[usize; 3]],
    /// A colour the maker chose for the paper's face, RGB.
    pub fill: Option<[u8; 3]>,
    /// Lines printed below the frame (title, how to print), clear of marks and sheet.
    pub caption: Vec<String>,
    /// The folding guide, a page after the page as cut, if any.
    pub guide: Option<&'a super::FoldingGuide<'a>>,
}

/// A print-and-cut sheet as PDF bytes: page 1 is printed (the sheet filled and its fold
/// guides, the registration marks, a caption and a 100 mm scale bar below the frame),
/// page 2 shows what the knife cuts, as the job has it; the folding guide follows.
pub fn to_bytes_print(sheet: &Sheet, title: &str, print: &PrintPage, cut: &Toolpath) -> Vec<u8> {
    use crate::fab::print_and_cut::LINE_MM;
    let (w, h) = (sheet.media.width, sheet.media.height);
    let mut ops = Vec::new();
    if let Some([r, g, b]) = print.fill {
        let col = rgb(
            f32::from(r) / 255.0,
            f32::from(g) / 255.0,
            f32::from(b) / 255.0,
        );
        ops.push(Op::SetFillColor { col });
        for f in print.faces {
            ops.push(filled(&f.map(|i| sheet.vertices[i])));
        }
    }
    ops.push(Op::SetOutlineThickness { pt: Pt(0.5) });
    for kind in [
        LineKind::Flat,
        LineKind::Valley,
        LineKind::Mountain,
        LineKind::Cut,
    ] {
        let (col, dash) = style(kind);
        ops.push(Op::SetOutlineColor { col });
        ops.push(Op::SetLineDashPattern { dash });
        for l in sheet.lines.iter().filter(|l| l.kind == kind) {
            ops.push(crease_line(l, Vec2::zeros()));
        }
    }
    if let Some(frame) = print.frame {
        ops.push(Op::SetFillColor {
            col: rgb(0.0, 0.0, 0.0),
        });
        let sq = frame.square();
        ops.push(filled(&[
            sq.lo,
            Vec2::new(sq.hi.x, sq.lo.y),
            sq.hi,
            Vec2::new(sq.lo.x, sq.hi.y),
        ]));
        solid_black(&mut ops);
        ops.push(Op::SetOutlineThickness {
            pt: Pt((LINE_MM * 72.0 / 25.4) as f32),
        });
        for [corner, along, down] in frame.corner_marks() {
            ops.push(line((corner.x, corner.y), (along.x, along.y)));
            ops.push(line((corner.x, corner.y), (down.x, down.y)));
        }
    }
    // Caption and scale bar in the band below the frame (or the image), 10 mm and more
    // up from the page's edge: inside every printer's printable area.
    solid_black(&mut ops);
    ops.push(Op::SetOutlineThickness { pt: Pt(0.5) });
    let (x0, y0) = (15.0, 12.0);
    ops.push(line((x0, y0), (x0 + SCALE_BAR_MM, y0)));
    for t in [0.0, 50.0, SCALE_BAR_MM] {
        ops.push(line((x0 + t, y0 - 1.0), (x0 + t, y0 + 1.5)));
    }
    text(
        &mut ops,
        x0 + SCALE_BAR_MM + 2.0,
        y0 - 1.0,
        7.0,
        "100 mm at 100%",
    );
    let mut y = y0 + 6.0 + 3.5 * print.caption.len() as f64;
    for l in std::iter::once(title).chain(print.caption.iter().map(String::as_str)) {
        text(&mut ops, x0, y, 7.0, l);
        y -= 3.5;
    }
    save(
        title,
        vec![
            PdfPage::new(Mm(w as f32), Mm(h as f32), ops),
            as_cut_page(cut, &super::template::Paper::of_media(&sheet.media)),
        ],
        print.guide,
    )
}
