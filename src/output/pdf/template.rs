//! The template to fold by: the sheet at 1:1 with its lines in styles to fold by, a scale
//! bar, a legend, the title and the run's summary; a two-sided job's page of steps; a
//! sheet too large tiled over pages; and the page as cut.

use super::{cross, line, rgb, save, solid_black, style, text, wrap, SCALE_BAR_MM};
use crate::fab::{LineKind, Media, Sheet, Toolpath};
use crate::mesh::Vec2;
use printpdf::{LineDashPattern, Mm, Op, PdfPage, Pt};

/// Drawing ops of one page of `page_w × page_h` mm showing the sheet shifted by `shift`.
fn page_ops(
    sheet: &Sheet,
    shift: (f64, f64),
    page_w: f64,
    page_h: f64,
    title: &str,
    summary: &[String],
) -> Vec<Op> {
    let mut ops = Vec::new();
    ops.push(Op::SetOutlineThickness { pt: Pt(0.5) });
    let visible =
        |x: f64, y: f64| (-1.0..=page_w + 1.0).contains(&x) && (-1.0..=page_h + 1.0).contains(&y);
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
            let (a, b) = (
                (l.a.x + shift.0, l.a.y + shift.1),
                (l.b.x + shift.0, l.b.y + shift.1),
            );
            // Lines wholly off the page are left out (the page boundary clips the rest).
            let off = (a.0 < 0.0 && b.0 < 0.0)
                || (a.1 < 0.0 && b.1 < 0.0)
                || (a.0 > page_w && b.0 > page_w)
                || (a.1 > page_h && b.1 > page_h);
            if !off || visible(a.0, a.1) {
                ops.push(line(a, b));
            }
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
    // Legend, bottom right: every kind of line the page draws.
    let drawn: Vec<LineKind> = [
        LineKind::Mountain,
        LineKind::Valley,
        LineKind::Cut,
        LineKind::Flat,
    ]
    .into_iter()
    .filter(|&k| k != LineKind::Flat || sheet.lines.iter().any(|l| l.kind == k))
    .collect();
    let mut lx = page_w - 5.0 - 21.0 * drawn.len() as f64;
    for kind in drawn {
        let (col, dash) = style(kind);
        ops.push(Op::SetOutlineColor { col });
        ops.push(Op::SetLineDashPattern { dash });
        ops.push(line((lx, y0), (lx + 8.0, y0)));
        text(&mut ops, lx + 9.0, y0 - 1.0, 7.0, kind.name());
        lx += 21.0;
    }
    // Title and summary, top margin.
    text(&mut ops, 5.0, page_h - 6.0, 9.0, title);
    for (i, s) in summary.iter().enumerate() {
        text(&mut ops, 5.0, page_h - 10.0 - 3.5 * i as f64, 6.5, s);
    }
    ops
}

/// Title of the page that shows the cut as the knife makes it.
pub const AS_CUT_TITLE: &str = "As cut: every dash and cut as the job makes it (fold by page 1)";

/// A page the size of the media with the toolpath's strokes as they are cut: every dash
/// a solid segment in its operation's colour, as `sheet.svg` and the cutter's job have
/// them (page 1 draws whole fold lines in a style to fold by).
pub(super) fn as_cut_page(path: &Toolpath) -> PdfPage {
    let (w, h) = (path.media.width, path.media.height);
    let mut ops = vec![Op::SetOutlineThickness { pt: Pt(0.4) }];
    solid_black(&mut ops);
    for kind in LineKind::ALL {
        let (col, _) = style(kind);
        ops.push(Op::SetOutlineColor { col });
        for s in path.strokes.iter().filter(|s| s.kind == kind) {
            ops.push(line((s.from.x, s.from.y), (s.to.x, s.to.y)));
        }
    }
    text(&mut ops, 5.0, h - 6.0, 9.0, AS_CUT_TITLE);
    PdfPage::new(Mm(w as f32), Mm(h as f32), ops)
}

/// The template as PDF bytes: one page the size of the sheet's media to fold by
/// (`summary` lines under the title), then, with `cut`, the page as cut.
pub fn to_bytes(sheet: &Sheet, title: &str, summary: &[String], cut: Option<&Toolpath>) -> Vec<u8> {
    let (w, h) = (sheet.media.width, sheet.media.height);
    let ops = page_ops(sheet, (0.0, 0.0), w, h, title, summary);
    let mut pages = vec![PdfPage::new(Mm(w as f32), Mm(h as f32), ops)];
    pages.extend(cut.map(as_cut_page));
    save(title, pages)
}

/// A two-sided job's template: the sheet with the front job's registration crosses at
/// `marks` (page 1), then a page with the `steps` — which job first, how to turn the sheet,
/// how to check the registration — and a sketch of the sheet's two sides with the crosses.
pub fn to_bytes_two_sided(
    sheet: &Sheet,
    title: &str,
    summary: &[String],
    marks: &[Vec2],
    steps: &[String],
    cut: Option<&Toolpath>,
) -> Vec<u8> {
    let (w, h) = (sheet.media.width, sheet.media.height);
    let mut ops = page_ops(sheet, (0.0, 0.0), w, h, title, summary);
    solid_black(&mut ops);
    for m in marks {
        cross(&mut ops, (m.x, m.y), crate::fab::registration::MARK_ARM_MM);
    }
    let mut second = Vec::new();
    text(
        &mut second,
        10.0,
        h - 15.0,
        12.0,
        &format!("{title}: two-sided job"),
    );
    // Helvetica averages about half an em per character.
    let per_line = ((w - 20.0) / (9.0 * 0.5 * 25.4 / 72.0)) as usize;
    let mut y = h - 25.0;
    for step in steps {
        for l in wrap(step, per_line) {
            text(&mut second, 10.0, y, 9.0, &l);
            y -= 4.5;
        }
        y -= 2.0;
    }
    // The sheet's two sides, small: the front as it is cut, then turned over left to
    // right, with the crosses where each job cuts them.
    let k = ((w - 30.0) / 2.0 / w).min((y - 20.0) / h).max(0.05);
    let mirrored: Vec<Vec2> = marks
        .iter()
        .map(|&m| crate::fab::registration::mirrored(w, m))
        .collect();
    solid_black(&mut second);
    for (i, (label, points)) in [
        ("front (first job)", marks),
        ("back, turned left to right (second job)", &mirrored[..]),
    ]
    .into_iter()
    .enumerate()
    {
        let x0 = 10.0 + i as f64 * (w * k + 10.0);
        let y0 = y - 5.0 - h * k;
        let corners = [
            (x0, y0),
            (x0 + w * k, y0),
            (x0 + w * k, y0 + h * k),
            (x0, y0 + h * k),
        ];
        for j in 0..4 {
            second.push(line(corners[j], corners[(j + 1) % 4]));
        }
        for p in points {
            cross(&mut second, (x0 + p.x * k, y0 + p.y * k), 4.0);
        }
        text(&mut second, x0, y0 - 5.0, 8.0, label);
    }
    let mut pages = vec![
        PdfPage::new(Mm(w as f32), Mm(h as f32), ops),
        PdfPage::new(Mm(w as f32), Mm(h as f32), second),
    ];
    pages.extend(cut.map(as_cut_page));
    save(title, pages)
}

/// A sheet too large for the printer, split over `page` sized pages. Each page shows a
/// window of the sheet inside `margin`; neighbouring windows overlap by `overlap` mm, and
/// registration crosses mark the window corners so the pages can be aligned and taped.
pub fn to_bytes_tiled(
    sheet: &Sheet,
    page: &Media,
    margin: f64,
    overlap: f64,
    title: &str,
    summary: &[String],
) -> Vec<u8> {
    let (uw, uh) = (page.width - 2.0 * margin, page.height - 2.0 * margin);
    let step = (uw - overlap, uh - overlap);
    let size = [sheet.media.width, sheet.media.height];
    let (cols, rows) = crate::fab::layout::tile_grid(size, page, margin, overlap);
    let mut pages = Vec::new();
    for r in 0..rows {
        for c in 0..cols {
            // Window of the sheet shown on this page, bottom-left corner.
            let (wx, wy) = (c as f64 * step.0, r as f64 * step.1);
            let shift = (margin - wx, margin - wy);
            let label = format!("{title}: page {} of {} (row {} of {rows}, column {} of {cols}); overlap {overlap} mm", r * cols + c + 1, rows * cols, r + 1, c + 1);
            let mut ops = page_ops(sheet, shift, page.width, page.height, &label, summary);
            solid_black(&mut ops);
            // Registration crosses at the window's corners and at its overlap edges.
            let xs = [margin, margin + overlap, margin + uw - overlap, margin + uw];
            let ys = [margin, margin + overlap, margin + uh - overlap, margin + uh];
            for &x in &[xs[0], xs[3]] {
                for &y in &[ys[0], ys[1], ys[2], ys[3]] {
                    cross(&mut ops, (x, y), 6.0);
                }
            }
            for &x in &[xs[1], xs[2]] {
                for &y in &[ys[0], ys[3]] {
                    cross(&mut ops, (x, y), 6.0);
                }
            }
            pages.push(PdfPage::new(
                Mm(page.width as f32),
                Mm(page.height as f32),
                ops,
            ));
        }
    }
    save(title, pages)
}
