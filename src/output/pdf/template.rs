//! The template to fold by: the sheet at 1:1 with its lines in styles to fold by, a scale
//! bar, a legend, the title and the run's summary; a two-sided job's page of steps; a
//! sheet too large tiled over pages; and the page as cut.

use super::guide::FoldingGuide;
use super::{crease_line, cross, line, save, solid_black, stroke, style, text, wrap, SCALE_BAR_MM};
use crate::fab::labels::{label_box, LABEL_PT};
use crate::fab::{LineKind, Media, Sheet, Toolpath};
use crate::geometry::clip_segment;
use crate::mesh::Vec2;
use printpdf::{Mm, Op, PdfPage, Pt};

/// Edge of the page no printer is trusted to print, mm: everything on a template stays
/// inside it.
pub const PRINTABLE_MARGIN_MM: f64 = 10.0;

/// Margin of a tiled page, mm: the printable margin, then a band for the page's label
/// above the window and the scale bar and legend below it.
pub const TILE_MARGIN_MM: f64 = 20.0;

/// Overlap between tiled PDF pages (mm).
pub const TILE_OVERLAP_MM: f64 = 10.0;

/// Paper a template may be printed on, portrait, mm, by area.
const PAPERS: [(&str, f64, f64); 5] = crate::fab::layout::PAPER_SIZES;

/// The paper a template is printed on, and the shift from the media's coordinates to it.
#[derive(Clone, Debug, PartialEq)]
pub struct Paper {
    /// Its name (a4, letter …), or the media's.
    pub name: String,
    /// Width, mm.
    pub width: f64,
    /// Height, mm.
    pub height: f64,
    /// Added to media coordinates to place them on the paper.
    pub shift: Vec2,
}

impl Paper {
    /// The media as the paper, nothing shifted.
    pub fn of_media(media: &Media) -> Paper {
        Paper {
            name: media.name.clone(),
            width: media.width,
            height: media.height,
            shift: Vec2::zeros(),
        }
    }
}

/// Whether `media` is one of the [`PAPERS`], either way round.
fn is_paper(media: &Media) -> bool {
    let same = |a: f64, b: f64| (a - b).abs() < 0.5;
    PAPERS.iter().any(|&(_, w, h)| {
        same(media.width, w) && same(media.height, h)
            || same(media.width, h) && same(media.height, w)
    })
}

/// Paper a home printer takes: A4, and Letter in the countries that measure in inches.
const HOME_PAPERS: [&str; 3] = ["a5", "letter", "a4"];

/// The paper to tile a template over when one page cannot carry it to a home printer:
/// the media is no paper (a cutting mat, a roll) and the pattern fits no A4 or Letter
/// page at 100% (a 12 × 12 in mat's pattern went onto A3, a sheet a home printer does
/// not take). A4, or Letter for media given in inches. `None` when one page serves; a
/// media that is paper, A3 included, is the maker's choice and printed as it is.
pub fn home_paper_for(sheet: &Sheet) -> Option<Media> {
    let media = &sheet.media;
    if is_paper(media) || HOME_PAPERS.contains(&paper_for(sheet).name.as_str()) {
        return None;
    }
    let name = if media.name.to_ascii_lowercase().ends_with("in") {
        "letter"
    } else {
        "a4"
    };
    Media::parse(name).ok()
}

/// How a template is tiled when its media is no paper a home printer takes
/// ([`home_paper_for`]): the paper, the tiles' margin ([`TILE_MARGIN_MM`] at least) and
/// the number of pages.
pub fn home_tiles(sheet: &Sheet) -> Option<(Media, f64, usize)> {
    let paper = home_paper_for(sheet)?;
    let margin = sheet.margin.max(TILE_MARGIN_MM);
    let size = [sheet.media.width, sheet.media.height];
    let (cols, rows) = crate::fab::layout::tile_grid(size, &paper, margin, TILE_OVERLAP_MM);
    Some((paper, margin, cols * rows))
}

/// The media itself when it is paper and holds the pattern inside the printable margin;
/// else the smallest paper that does (upright first), the pattern centred on it; else (a
/// pattern larger than A3) the media.
pub fn paper_for(sheet: &Sheet) -> Paper {
    let m = PRINTABLE_MARGIN_MM;
    let (lo, hi) = sheet.bounds();
    let media = &sheet.media;
    let as_media = Paper::of_media(media);
    let inside = lo.x >= m - 1e-9
        && lo.y >= m - 1e-9
        && hi.x <= media.width - m + 1e-9
        && hi.y <= media.height - m + 1e-9;
    if is_paper(media) && inside {
        return as_media;
    }
    let size = hi - lo;
    for &(name, w, h) in &PAPERS {
        for (pw, ph) in [(w, h), (h, w)] {
            if size.x + 2.0 * m <= pw && size.y + 2.0 * m <= ph {
                return Paper {
                    name: name.to_string(),
                    width: pw,
                    height: ph,
                    shift: (Vec2::new(pw, ph) - size) / 2.0 - lo,
                };
            }
        }
    }
    as_media
}

/// Helvetica's advance as text is wrapped and placed, mm per character at `size` points:
/// 0.6 em, above its digits' 0.556 em and its lower-case mean (about half an em), so a
/// line of figures (a list of short folds' lengths) still ends inside the page.
fn char_mm(size: f32) -> f64 {
    crate::fab::labels::char_width_mm(size)
}

/// The sheet's lines shifted by `shift` and clipped to `window` (page mm), each kind in
/// its style; flat lines only if `flat`.
fn pattern_ops(sheet: &Sheet, shift: Vec2, window: (Vec2, Vec2), flat: bool) -> Vec<Op> {
    let mut ops = vec![Op::SetOutlineThickness { pt: Pt(0.5) }];
    for kind in [
        LineKind::Flat,
        LineKind::Valley,
        LineKind::Mountain,
        LineKind::Cut,
    ] {
        if kind == LineKind::Flat && !flat {
            continue;
        }
        let (col, dash) = style(kind);
        ops.push(Op::SetOutlineColor { col });
        ops.push(Op::SetLineDashPattern { dash });
        for l in sheet.lines.iter().filter(|l| l.kind == kind) {
            let points: Vec<Vec2> = l.polyline().into_iter().map(|p| p + shift).collect();
            let inside = |p: &Vec2| {
                p.x >= window.0.x && p.y >= window.0.y && p.x <= window.1.x && p.y <= window.1.y
            };
            if l.curve.is_some() && points.iter().all(inside) {
                // A curve wholly on the page is drawn as its cubics, else chord by chord.
                ops.push(crease_line(l, shift));
                continue;
            }
            for w in points.windows(2) {
                if let Some((a, b)) = clip_segment(w[0], w[1], window) {
                    ops.push(line((a.x, a.y), (b.x, b.y)));
                }
            }
        }
    }
    for label in &sheet.labels {
        let (lo, hi) = label_box(label);
        let (lo, hi) = (lo + shift, hi + shift);
        let inside = lo.x >= window.0.x && hi.x <= window.1.x;
        if inside && lo.y >= window.0.y && lo.y <= window.1.y {
            text(&mut ops, lo.x, lo.y, LABEL_PT, &label.text);
        }
    }
    ops
}

/// The kinds of line a template of `sheet` draws, in legend order: those it has (flat
/// only when `flat`).
fn drawn_kinds(sheet: &Sheet, flat: bool) -> Vec<LineKind> {
    [
        LineKind::Mountain,
        LineKind::Valley,
        LineKind::Cut,
        LineKind::Flat,
    ]
    .into_iter()
    .filter(|&k| (k != LineKind::Flat || flat) && sheet.lines.iter().any(|l| l.kind == k))
    .collect()
}

/// Height of the band the scale bar and legend take above the printable margin, mm.
const FOOT_MM: f64 = 10.0;

/// The 100 mm scale bar (baseline `y`) and a legend of `kinds` in the row above it, from
/// the left printable margin.
fn foot_ops(ops: &mut Vec<Op>, y: f64, kinds: &[LineKind]) {
    let x0 = PRINTABLE_MARGIN_MM;
    solid_black(ops);
    ops.push(Op::SetOutlineThickness { pt: Pt(0.5) });
    ops.push(line((x0, y), (x0 + SCALE_BAR_MM, y)));
    for t in [0.0, 50.0, SCALE_BAR_MM] {
        ops.push(line((x0 + t, y - 1.0), (x0 + t, y + 1.5)));
    }
    text(ops, x0 + SCALE_BAR_MM + 2.0, y - 1.0, 6.0, "100 mm at 100%");
    let mut lx = x0;
    for &kind in kinds {
        let (col, dash) = style(kind);
        ops.push(Op::SetOutlineColor { col });
        ops.push(Op::SetLineDashPattern { dash });
        ops.push(line((lx, y + 5.0), (lx + 8.0, y + 5.0)));
        text(ops, lx + 9.0, y + 4.0, 6.0, kind.name());
        lx += 12.0 + char_mm(6.0) * kind.name().len() as f64;
    }
}

/// Lines of a title (9 pt) and summary (6.5 pt, wrapped to `width` mm) from baseline
/// `top` down; returns the baseline below the last.
fn head_ops(ops: &mut Vec<Op>, top: f64, width: f64, title: &str, summary: &[String]) -> f64 {
    let x0 = PRINTABLE_MARGIN_MM;
    let mut y = top;
    for l in wrap(title, (width / char_mm(9.0)) as usize) {
        text(ops, x0, y, 9.0, &l);
        y -= 4.0;
    }
    for s in summary {
        for l in wrap(s, (width / char_mm(6.5)) as usize) {
            text(ops, x0, y, 6.5, &l);
            y -= 3.0;
        }
    }
    y
}

/// Height the title and summary take, mm.
fn head_height(width: f64, title: &str, summary: &[String]) -> f64 {
    let mut ops = Vec::new();
    let top = 0.0;
    top - head_ops(&mut ops, top, width, title, summary)
}

/// The page to fold by: the pattern on `paper` with its title and summary above it and
/// the scale bar and legend below it, each where it clears the pattern by 2 mm inside the
/// printable margin. Returns the page and whether anything had no room (it then goes on
/// a page of notes).
fn fold_page(
    sheet: &Sheet,
    paper: &Paper,
    title: &str,
    summary: &[String],
    flat: bool,
) -> (Vec<Op>, bool) {
    let m = PRINTABLE_MARGIN_MM;
    let (w, h) = (paper.width, paper.height);
    let window = (Vec2::repeat(m), Vec2::new(w - m, h - m));
    let mut ops = pattern_ops(sheet, paper.shift, window, flat);
    let (lo, hi) = sheet.bounds();
    let (lo, hi) = (lo + paper.shift, hi + paper.shift);
    let width = w - 2.0 * m;
    let head = head_height(width, title, summary);
    let mut all = true;
    if h - m - head - 2.0 >= hi.y {
        head_ops(&mut ops, h - m - 4.0, width, title, summary);
    } else {
        all = false;
    }
    if lo.y >= m + FOOT_MM + 2.0 {
        foot_ops(&mut ops, m + 2.0, &drawn_kinds(sheet, flat));
    } else {
        all = false;
    }
    (ops, all)
}

/// A page of what had no room beside the pattern: title, summary, scale bar and legend.
fn notes_page(
    sheet: &Sheet,
    paper: &Paper,
    title: &str,
    summary: &[String],
    flat: bool,
) -> PdfPage {
    let m = PRINTABLE_MARGIN_MM;
    let mut ops = Vec::new();
    let mut lines = summary.to_vec();
    lines.push(format!("The last page: {AS_CUT_TITLE}."));
    lines.push(
        "The title, summary and legend are on this page: the pattern's pages leave them no room."
            .into(),
    );
    head_ops(
        &mut ops,
        paper.height - m - 4.0,
        paper.width - 2.0 * m,
        title,
        &lines,
    );
    foot_ops(&mut ops, m + 2.0, &drawn_kinds(sheet, flat));
    PdfPage::new(Mm(paper.width as f32), Mm(paper.height as f32), ops)
}

/// Title of the page that shows the cut as the knife makes it.
pub const AS_CUT_TITLE: &str = "As cut: every dash and cut as the job makes it (fold by page 1)";

/// The toolpath's strokes as they are cut, on `paper`: every dash a solid segment in its
/// operation's colour, as `sheet.svg` and the cutter's job have them (the page to fold by
/// draws whole fold lines in a style to fold by); titled above or below the strokes,
/// where there is room (else the page of notes says what it is).
pub(super) fn as_cut_page(path: &Toolpath, paper: &Paper) -> PdfPage {
    let (w, h) = (paper.width, paper.height);
    let mut ops = vec![Op::SetOutlineThickness { pt: Pt(0.4) }];
    solid_black(&mut ops);
    for kind in LineKind::ALL {
        let (col, _) = style(kind);
        ops.push(Op::SetOutlineColor { col });
        for s in path.strokes.iter().filter(|s| s.kind == kind) {
            ops.push(stroke(s, paper.shift));
        }
    }
    let (lo, hi) = stroke_bounds(path, paper.shift);
    if let Some(y) = as_cut_title_at(lo, hi, h) {
        text(&mut ops, PRINTABLE_MARGIN_MM, y, 9.0, AS_CUT_TITLE);
    }
    PdfPage::new(Mm(w as f32), Mm(h as f32), ops)
}

/// The baseline of the as-cut page's title: above strokes spanning `lo`–`hi` on a page
/// `h` mm tall, or below them, if either leaves room inside the printable margin.
fn as_cut_title_at(lo: Vec2, hi: Vec2, h: f64) -> Option<f64> {
    let m = PRINTABLE_MARGIN_MM;
    if hi.y <= h - m - 6.0 {
        Some(h - m - 4.0)
    } else if lo.y >= m + 6.0 {
        Some(m + 1.0)
    } else {
        None
    }
}

/// Whether the as-cut page of `path` on `paper` has room for its title.
fn as_cut_titled(path: &Toolpath, paper: &Paper) -> bool {
    let (lo, hi) = stroke_bounds(path, paper.shift);
    as_cut_title_at(lo, hi, paper.height).is_some()
}

/// The box of the toolpath's strokes moved by `shift`.
fn stroke_bounds(path: &Toolpath, shift: Vec2) -> (Vec2, Vec2) {
    let ends: Vec<Vec2> = path
        .strokes
        .iter()
        .flat_map(|s| [s.from + shift, s.to + shift])
        .collect();
    crate::mesh::bounds(&ends)
}

/// What a template carries besides the sheet.
pub struct Template<'a> {
    /// Its title (the design's).
    pub title: &'a str,
    /// The run's summary, one line each.
    pub summary: &'a [String],
    /// Whether flat lines are drawn (light grey) or left out.
    pub flat: bool,
    /// The folding guide, the last page, if any.
    pub guide: Option<&'a FoldingGuide<'a>>,
}

/// The template as PDF bytes, on [`paper_for`] the sheet: the page to fold by (flat
/// lines light grey, or left out when `flat` is false), a page of notes if the title,
/// summary or legend had no room beside the pattern, with `cut` the page as cut, and
/// the folding guide.
pub fn to_bytes(sheet: &Sheet, template: &Template, cut: Option<&Toolpath>) -> Vec<u8> {
    let (title, summary, flat, guide) = (
        template.title,
        template.summary,
        template.flat,
        template.guide,
    );
    let paper = paper_for(sheet);
    let (ops, all) = fold_page(sheet, &paper, title, summary, flat);
    let all = all && cut.is_none_or(|c| as_cut_titled(c, &paper));
    let mut pages = vec![PdfPage::new(
        Mm(paper.width as f32),
        Mm(paper.height as f32),
        ops,
    )];
    if !all {
        pages.push(notes_page(sheet, &paper, title, summary, flat));
    }
    pages.extend(cut.map(|c| as_cut_page(c, &paper)));
    save(title, pages, guide)
}

/// A two-sided job's template: the sheet with the front job's registration crosses at
/// `marks` (page 1), then a page with the `steps` — which job first, how to turn the sheet,
/// how to check the registration — and a sketch of the sheet's two sides with the crosses.
pub fn to_bytes_two_sided(
    sheet: &Sheet,
    template: &Template,
    marks: &[Vec2],
    steps: &[String],
    cut: Option<&Toolpath>,
) -> Vec<u8> {
    let (title, summary, flat, guide) = (
        template.title,
        template.summary,
        template.flat,
        template.guide,
    );
    let paper = paper_for(sheet);
    let (w, h) = (paper.width, paper.height);
    let (mut ops, all) = fold_page(sheet, &paper, title, summary, flat);
    let all = all && cut.is_none_or(|c| as_cut_titled(c, &paper));
    solid_black(&mut ops);
    for m in marks {
        let c = m + paper.shift;
        cross(&mut ops, (c.x, c.y), crate::fab::registration::MARK_ARM_MM);
    }
    let mut second = Vec::new();
    text(
        &mut second,
        10.0,
        h - 15.0,
        12.0,
        &format!("{title}: two-sided job"),
    );
    let per_line = ((w - 20.0) / char_mm(9.0)) as usize;
    let mut y = h - 25.0;
    for step in steps {
        for l in wrap(step, per_line) {
            text(&mut second, 10.0, y, 9.0, &l);
            y -= 4.5;
        }
        y -= 2.0;
    }
    two_sides_sketch(&mut second, sheet, marks, y, w);
    // The steps stay page 2, as the summary says; notes, if any, follow them.
    let mut pages = vec![
        PdfPage::new(Mm(w as f32), Mm(h as f32), ops),
        PdfPage::new(Mm(w as f32), Mm(h as f32), second),
    ];
    if !all {
        pages.push(notes_page(sheet, &paper, title, summary, flat));
    }
    pages.extend(cut.map(|c| as_cut_page(c, &paper)));
    save(title, pages, guide)
}

/// The sheet's two sides, small, below `y` on a page `w` mm wide: the front as it is cut,
/// then turned over left to right, with the crosses where each job cuts them.
fn two_sides_sketch(second: &mut Vec<Op>, sheet: &Sheet, marks: &[Vec2], y: f64, w: f64) {
    let (mw, mh) = (sheet.media.width, sheet.media.height);
    let k = ((w - 30.0) / 2.0 / mw).min((y - 20.0) / mh).max(0.05);
    let mirrored: Vec<Vec2> = marks
        .iter()
        .map(|&m| crate::fab::registration::mirrored(mw, m))
        .collect();
    solid_black(second);
    for (i, (label, points)) in [
        ("front (first job)", marks),
        ("back, turned left to right (second job)", &mirrored[..]),
    ]
    .into_iter()
    .enumerate()
    {
        let x0 = 10.0 + i as f64 * (mw * k + 10.0);
        let y0 = y - 5.0 - mh * k;
        let corners = [
            (x0, y0),
            (x0 + mw * k, y0),
            (x0 + mw * k, y0 + mh * k),
            (x0, y0 + mh * k),
        ];
        for j in 0..4 {
            second.push(line(corners[j], corners[(j + 1) % 4]));
        }
        for p in points {
            cross(second, (x0 + p.x * k, y0 + p.y * k), 4.0);
        }
        text(second, x0, y0 - 5.0, 8.0, label);
    }
}

/// A sheet too large for the printer, split over `page` sized pages. Each page shows a
/// window of the sheet inside `margin` (at least [`TILE_MARGIN_MM`]); neighbouring windows
/// overlap by `overlap` mm, and registration crosses mark the window corners so the pages
/// can be aligned and taped. Each page is labelled above its window, with the scale bar
/// and legend below it; a last page holds the title and `summary`.
pub fn to_bytes_tiled(
    sheet: &Sheet,
    page: &Media,
    margin: f64,
    overlap: f64,
    template: &Template,
) -> Vec<u8> {
    let (title, summary, flat, guide) = (
        template.title,
        template.summary,
        template.flat,
        template.guide,
    );
    let (uw, uh) = (page.width - 2.0 * margin, page.height - 2.0 * margin);
    let step = (uw - overlap, uh - overlap);
    let size = [sheet.media.width, sheet.media.height];
    let (cols, rows) = crate::fab::layout::tile_grid(size, page, margin, overlap);
    let window = (
        Vec2::repeat(margin),
        Vec2::new(page.width - margin, page.height - margin),
    );
    let kinds = drawn_kinds(sheet, flat);
    let mut pages = Vec::new();
    for r in 0..rows {
        for c in 0..cols {
            // Window of the sheet shown on this page, bottom-left corner.
            let (wx, wy) = (c as f64 * step.0, r as f64 * step.1);
            let shift = Vec2::new(margin - wx, margin - wy);
            let label = format!("{title}: page {} of {} (row {} of {rows}, column {} of {cols}); overlap {overlap} mm", r * cols + c + 1, rows * cols, r + 1, c + 1);
            let mut ops = pattern_ops(sheet, shift, window, flat);
            let m = PRINTABLE_MARGIN_MM;
            head_ops(
                &mut ops,
                page.height - m - 4.0,
                page.width - 2.0 * m,
                &label,
                &[],
            );
            foot_ops(&mut ops, m + 2.0, &kinds);
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
    pages.push(notes_page(
        sheet,
        &Paper::of_media(page),
        title,
        summary,
        flat,
    ));
    save(title, pages, guide)
}
