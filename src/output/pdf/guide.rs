//! The folding guide (issue 49): a page of still pictures of the folding motion, from the
//! flat sheet to the design, all seen from one viewpoint and framed alike, each with how
//! far it is folded, so the person holding the cut sheet sees the order of shapes.

use super::{line, text, wrap};
use crate::mesh::{Mesh, Vec3};
use crate::output::png::{stills, Picture};
use printpdf::{
    Mm, Op, PdfDocument, PdfPage, Pt, RawImage, RawImageData, RawImageFormat, XObjectTransform,
};

/// Resolution of the guide's pictures on paper, dots per inch: sharp in print, and a
/// page of six a few hundred kB.
pub const GUIDE_DPI: f64 = 150.0;

/// Widest picture of the guide, px: on large media the pictures grow, their pixels do not.
const MAX_PICTURE_PX: f64 = 1200.0;

/// Height under each picture for its caption, mm.
const CAPTION_MM: f64 = 6.0;

/// Height of the heading (title and up to three lines of note), mm.
const HEAD_MM: f64 = 24.0;

/// Margin of the page, mm (as the template's printable margin).
const MARGIN_MM: f64 = super::PRINTABLE_MARGIN_MM;

/// What the guide shows: the frames of a motion chosen for it, each with its caption.
pub struct FoldingGuide<'a> {
    /// The sheet the frames move (its faces and creases).
    pub sheet: &'a Mesh,
    /// Each picture's vertex positions (mm) and caption (how far folded).
    pub frames: Vec<(&'a [Vec3], String)>,
    /// A line under the heading: what the motion found (rigid or bending panels).
    pub note: String,
}

/// How the pictures sit on the page, mm: in `cols` columns of cells `cell` wide and
/// high below the heading, each picture `picture` (4:3) above its caption.
struct Grid {
    cols: usize,
    cell: [f64; 2],
    picture: [f64; 2],
}

/// The grid of `count` pictures on a `w × h` mm page: three columns on a landscape page,
/// two on a portrait one.
fn grid(w: f64, h: f64, count: usize) -> Grid {
    let cols = if w >= h { 3 } else { 2 }.min(count.max(1));
    let rows = count.div_ceil(cols).max(1);
    let cell = [
        (w - 2.0 * MARGIN_MM) / cols as f64,
        (h - 2.0 * MARGIN_MM - HEAD_MM) / rows as f64,
    ];
    let box_w = (cell[0] - 4.0).max(1.0);
    let box_h = (cell[1] - CAPTION_MM - 4.0).max(1.0);
    let pw = box_w.min(box_h * 4.0 / 3.0);
    Grid {
        cols,
        cell,
        picture: [pw, pw * 3.0 / 4.0],
    }
}

/// The guide as a `size` (mm) page, its pictures added to `doc`.
pub fn page(doc: &mut PdfDocument, guide: &FoldingGuide, size: [f64; 2], title: &str) -> PdfPage {
    let [w, h] = size;
    let Grid {
        cols,
        cell: [cell_w, cell_h],
        picture: [pw, ph],
    } = grid(w, h, guide.frames.len());
    let px_w = (pw / 25.4 * GUIDE_DPI).clamp(8.0, MAX_PICTURE_PX);
    let px = [px_w.round() as u32, (px_w * 0.75).round() as u32];
    let dpi = (f64::from(px[0]) / (pw / 25.4)) as f32;
    let mut ops = Vec::new();
    text(
        &mut ops,
        MARGIN_MM,
        h - MARGIN_MM - 5.0,
        12.0,
        &format!("{title}: how it folds"),
    );
    let per_line = ((w - 2.0 * MARGIN_MM) / crate::fab::labels::char_width_mm(8.0)) as usize;
    for (i, l) in wrap(&guide.note, per_line).iter().take(3).enumerate() {
        text(
            &mut ops,
            MARGIN_MM,
            h - MARGIN_MM - 11.0 - 4.0 * i as f64,
            8.0,
            l,
        );
    }
    let positions: Vec<&[Vec3]> = guide.frames.iter().map(|(x, _)| *x).collect();
    let pictures = match stills(guide.sheet, &positions, px) {
        Ok(p) => p,
        Err(why) => {
            text(
                &mut ops,
                MARGIN_MM,
                h / 2.0,
                10.0,
                &format!("no pictures: {why}"),
            );
            return PdfPage::new(Mm(w as f32), Mm(h as f32), ops);
        }
    };
    let top = h - MARGIN_MM - HEAD_MM;
    let mut frames = Vec::new();
    for (k, (picture, (_, caption))) in pictures.into_iter().zip(&guide.frames).enumerate() {
        let (col, row) = (k % cols, k / cols);
        let x = MARGIN_MM + col as f64 * cell_w + (cell_w - pw) / 2.0;
        let y = top - (row + 1) as f64 * cell_h + CAPTION_MM + 2.0;
        let id = doc.add_image(&raw(picture));
        ops.push(Op::UseXobject {
            id,
            transform: XObjectTransform {
                translate_x: Some(Mm(x as f32).into()),
                translate_y: Some(Mm(y as f32).into()),
                dpi: Some(dpi),
                ..Default::default()
            },
        });
        text(&mut ops, x, y - 4.5, 9.0, &format!("{}. {caption}", k + 1));
        frames.push([(x, y), (x + pw, y), (x + pw, y + ph), (x, y + ph)]);
    }
    // Thin grey frames round the pictures: their light backgrounds print near white.
    ops.push(Op::SetOutlineThickness { pt: Pt(0.3) });
    ops.push(Op::SetOutlineColor {
        col: super::rgb(0.6, 0.6, 0.6),
    });
    for corners in frames {
        for j in 0..4 {
            ops.push(line(corners[j], corners[(j + 1) % 4]));
        }
    }
    PdfPage::new(Mm(w as f32), Mm(h as f32), ops)
}

fn raw(picture: Picture) -> RawImage {
    RawImage {
        pixels: RawImageData::U8(picture.rgb),
        width: picture.width as usize,
        height: picture.height as usize,
        data_format: RawImageFormat::RGB8,
        tag: Vec::new(),
    }
}
