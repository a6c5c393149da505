//! PDF pages, drawn at 1:1 in millimetres: the template to fold by (`template`: crease
//! lines in distinct dash styles for folding by hand, mountain dash-dot, valley dashed, cut
//! solid; a 100 mm scale bar to check the printer did not scale; a legend, the title and
//! the report's summary) and the print-and-cut page ([`print`]).

mod guide;
mod print;
mod template;

pub use guide::{FoldingGuide, GUIDE_DPI};
pub use print::{to_bytes_print, PrintPage};
pub use template::{
    home_paper_for, home_tiles, paper_for, to_bytes, to_bytes_tiled, to_bytes_two_sided, Paper,
    Template, AS_CUT_TITLE, PRINTABLE_MARGIN_MM, TILE_MARGIN_MM, TILE_OVERLAP_MM,
};

use crate::fab::LineKind;
use crate::mesh::Vec2;
use printpdf::{
    BuiltinFont, Color, Line, LineDashPattern, LinePoint, Mm, Op, PaintMode, PdfDocument,
    PdfFontHandle, PdfPage, PdfSaveOptions, Point, Polygon, PolygonRing, Pt, Rgb, TextItem,
    WindingOrder,
};

/// Length of the scale bar (mm).
pub const SCALE_BAR_MM: f64 = 100.0;

fn rgb(r: f32, g: f32, b: f32) -> Color {
    Color::Rgb(Rgb {
        r,
        g,
        b,
        icc_profile: None,
    })
}

/// A kind's colour ([`super::colour`], the same in every file) and its line style on the
/// template.
fn style(kind: LineKind) -> (Color, LineDashPattern) {
    let [r, g, b] = super::colour::rgb(kind).map(|c| f32::from(c) / 255.0);
    let dash = match kind {
        LineKind::Cut => LineDashPattern::solid(),
        LineKind::Mountain => LineDashPattern::new(0.0, &[6.0, 2.0, 1.0, 2.0]),
        LineKind::Valley => LineDashPattern::new(0.0, &[4.0, 3.0]),
        LineKind::Flat => LineDashPattern::new(0.0, &[1.0, 2.0]),
    };
    (rgb(r, g, b), dash)
}

fn line(a: (f64, f64), b: (f64, f64)) -> Op {
    path(Vec2::new(a.0, a.1), [(Vec2::new(b.0, b.1), None)])
}

/// A path from `start` through `steps`: each to its point, straight or along a cubic
/// with the given inner control points (printpdf marks control points `bezier`).
fn path(start: Vec2, steps: impl IntoIterator<Item = (Vec2, Option<[Vec2; 2]>)>) -> Op {
    let p = |v: Vec2, bezier: bool| LinePoint {
        p: Point::new(Mm(v.x as f32), Mm(v.y as f32)),
        bezier,
    };
    let mut points = vec![p(start, false)];
    for (to, bend) in steps {
        if let Some([c1, c2]) = bend {
            points.extend([p(c1, true), p(c2, true)]);
        }
        points.push(p(to, false));
    }
    Op::DrawLine {
        line: Line {
            points,
            is_closed: false,
        },
    }
}

/// A stroke moved by `shift`: a segment, or its cubic.
fn stroke(s: &crate::fab::Stroke, shift: Vec2) -> Op {
    let s = s.mapped(|p| p + shift);
    path(s.from, [(s.to, s.bend)])
}

/// A sheet line moved by `shift`: a segment, or its curve's cubics.
fn crease_line(l: &crate::fab::CreaseLine, shift: Vec2) -> Op {
    let l = l.mapped(|p| p + shift);
    match &l.curve {
        Some(curve) => path(
            l.a,
            curve.pieces().iter().map(|c| (c.p3, Some([c.c1, c.c2]))),
        ),
        None => path(l.a, [(l.b, None)]),
    }
}

fn text(ops: &mut Vec<Op>, x: f64, y: f64, size: f32, s: &str) {
    ops.extend([
        Op::StartTextSection,
        Op::SetTextCursor {
            pos: Point::new(Mm(x as f32), Mm(y as f32)),
        },
        Op::SetFont {
            font: PdfFontHandle::Builtin(BuiltinFont::Helvetica),
            size: Pt(size),
        },
        Op::SetFillColor {
            col: rgb(0.0, 0.0, 0.0),
        },
        Op::ShowText {
            items: vec![TextItem::Text(s.to_string())],
        },
        Op::EndTextSection,
    ]);
}

/// A cross of arms `arm` mm end to end centred on `c`, in the current colour.
fn cross(ops: &mut Vec<Op>, c: (f64, f64), arm: f64) {
    let h = arm / 2.0;
    ops.push(line((c.0 - h, c.1), (c.0 + h, c.1)));
    ops.push(line((c.0, c.1 - h), (c.0, c.1 + h)));
}

fn solid_black(ops: &mut Vec<Op>) {
    ops.push(Op::SetOutlineColor {
        col: rgb(0.0, 0.0, 0.0),
    });
    ops.push(Op::SetLineDashPattern {
        dash: LineDashPattern::solid(),
    });
}

/// `s` broken at spaces into lines of at most `width` characters.
fn wrap(s: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in s.split_whitespace() {
        let last = lines.last_mut().expect("one line");
        if !last.is_empty() && last.len() + 1 + word.len() > width {
            lines.push(word.to_string());
        } else {
            if !last.is_empty() {
                last.push(' ');
            }
            last.push_str(word);
        }
    }
    lines
}

/// `pages` as a PDF, the folding guide after them on paper the size of the first.
fn save(title: &str, mut pages: Vec<PdfPage>, guide: Option<&FoldingGuide>) -> Vec<u8> {
    let mut doc = PdfDocument::new(title);
    if let (Some(guide), Some(first)) = (guide, pages.first()) {
        let mm = |p: Pt| f64::from(Mm::from(p).0);
        let size = [mm(first.media_box.width), mm(first.media_box.height)];
        pages.push(guide::page(&mut doc, guide, size, title));
    }
    doc.with_pages(pages)
        .save(&PdfSaveOptions::default(), &mut Vec::new())
}

/// A filled polygon through `points` (mm), in the current fill colour.
fn filled(points: &[Vec2]) -> Op {
    let ring = PolygonRing {
        points: points
            .iter()
            .map(|p| LinePoint {
                p: Point::new(Mm(p.x as f32), Mm(p.y as f32)),
                bezier: false,
            })
            .collect(),
    };
    Op::DrawPolygon {
        polygon: Polygon {
            rings: vec![ring],
            mode: PaintMode::Fill,
            winding_order: WindingOrder::NonZero,
        },
    }
}
