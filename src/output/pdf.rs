//! A printable template at 1:1: the page is the media, crease lines in distinct dash styles
//! for folding by hand (mountain dash-dot, valley dashed, cut solid), a 100 mm scale bar
//! to check the printer did not scale, a legend, the title and the report's summary.

use crate::fab::{LineKind, Sheet};
use printpdf::{
    BuiltinFont, Color, Line, LineDashPattern, LinePoint, Mm, Op, PdfDocument, PdfFontHandle,
    PdfPage, PdfSaveOptions, Point, Pt, Rgb, TextItem,
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

fn style(kind: LineKind) -> (Color, LineDashPattern) {
    match kind {
        LineKind::Cut => (rgb(0.0, 0.0, 0.0), LineDashPattern::solid()),
        LineKind::Mountain => (
            rgb(0.85, 0.0, 0.0),
            LineDashPattern::new(0.0, &[6.0, 2.0, 1.0, 2.0]),
        ),
        LineKind::Valley => (rgb(0.0, 0.0, 0.85), LineDashPattern::new(0.0, &[4.0, 3.0])),
        LineKind::Flat => (rgb(0.7, 0.7, 0.7), LineDashPattern::new(0.0, &[1.0, 2.0])),
    }
}

fn line(a: (f64, f64), b: (f64, f64)) -> Op {
    let p = |(x, y): (f64, f64)| LinePoint {
        p: Point::new(Mm(x as f32), Mm(y as f32)),
        bezier: false,
    };
    Op::DrawLine {
        line: Line {
            points: vec![p(a), p(b)],
            is_closed: false,
        },
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

/// The template as PDF bytes. `summary` lines go under the title.
pub fn to_bytes(sheet: &Sheet, title: &str, summary: &[String]) -> Vec<u8> {
    let (w, h) = (sheet.media.width, sheet.media.height);
    let mut ops = Vec::new();
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
            ops.push(line((l.a.x, l.a.y), (l.b.x, l.b.y)));
        }
    }
    // Scale bar with end ticks, in the bottom margin.
    let (x0, y0) = (5.0, 4.0);
    ops.push(Op::SetOutlineColor {
        col: rgb(0.0, 0.0, 0.0),
    });
    ops.push(Op::SetLineDashPattern {
        dash: LineDashPattern::solid(),
    });
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
    // Legend, bottom right.
    let mut lx = w - 62.0;
    for kind in [LineKind::Mountain, LineKind::Valley, LineKind::Cut] {
        let (col, dash) = style(kind);
        ops.push(Op::SetOutlineColor { col });
        ops.push(Op::SetLineDashPattern { dash });
        ops.push(line((lx, y0), (lx + 8.0, y0)));
        text(&mut ops, lx + 9.0, y0 - 1.0, 7.0, kind.name());
        lx += 21.0;
    }
    // Title and summary, top margin.
    text(&mut ops, 5.0, h - 6.0, 9.0, title);
    for (i, s) in summary.iter().enumerate() {
        text(&mut ops, 5.0, h - 10.0 - 3.5 * i as f64, 6.5, s);
    }
    let page = PdfPage::new(Mm(w as f32), Mm(h as f32), ops);
    PdfDocument::new(title)
        .with_pages(vec![page])
        .save(&PdfSaveOptions::default(), &mut Vec::new())
}
