//! Placing a flat pattern on the media: scale (design units are mm unless a width is
//! asked for), turn to the orientation of least bounding area that fits, centre within
//! the margins.

use super::advice::{Advice, FabOption};
use super::lines::CreaseLine;
use crate::mesh::{bounds, Vec2};

/// A sheet of media.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Media {
    /// Name as given ("a4", "300x200mm").
    pub name: String,
    /// Width in mm.
    pub width: f64,
    /// Height in mm.
    pub height: f64,
}

/// The paper sizes media can be named by, portrait, mm, smallest first: what a printer
/// takes (the PDF template chooses among them) and what `--media` names.
pub const PAPER_SIZES: [(&str, f64, f64); 5] = [
    ("a5", 148.0, 210.0),
    ("letter", 215.9, 279.4),
    ("a4", 210.0, 297.0),
    ("legal", 215.9, 355.6),
    ("a3", 297.0, 420.0),
];

impl Media {
    /// Parses `a4`, `a3`, `letter`, `12x12in`, `WxHmm` (or `WxH`, in mm).
    pub fn parse(text: &str) -> Result<Media, String> {
        let t = text.trim().to_ascii_lowercase();
        let paper = PAPER_SIZES.iter().find(|(name, _, _)| *name == t);
        let (w, h) = match paper {
            Some(&(_, w, h)) => (w, h),
            None => {
                let (dims, unit) = if let Some(d) = t.strip_suffix("mm") {
                    (d, 1.0)
                } else if let Some(d) = t.strip_suffix("in") {
                    (d, 25.4)
                } else if let Some(d) = t.strip_suffix("cm") {
                    (d, 10.0)
                } else {
                    (t.as_str(), 1.0)
                };
                let bad = || {
                    format!(
                        "unknown media \"{text}\" (a4, a3, a5, letter, legal, 12x12in or WxHmm)"
                    )
                };
                let (a, b) = dims.split_once('x').ok_or_else(bad)?;
                let (a, b): (f64, f64) = (
                    a.trim().parse().map_err(|_| bad())?,
                    b.trim().parse().map_err(|_| bad())?,
                );
                let side = |v: f64| {
                    crate::limits::MEDIA_SIDE
                        .check(format!("media \"{}\"", text.trim()), v * unit)
                        .map_err(|e| e.to_string())
                };
                (side(a)?, side(b)?)
            }
        };
        Ok(Media {
            name: text.to_string(),
            width: w,
            height: h,
        })
    }
}

/// The pattern placed on the media.
#[derive(Clone, Debug)]
pub struct Sheet {
    /// The media.
    pub media: Media,
    /// Margin kept clear on every side (mm).
    pub margin: f64,
    /// Scale applied to the design (1 = design millimetres).
    pub scale: f64,
    /// Rotation applied, radians.
    pub rotation: f64,
    /// Crease lines in media coordinates (mm, origin bottom-left, y up).
    pub lines: Vec<CreaseLine>,
    /// The pattern's vertices in media coordinates.
    pub vertices: Vec<Vec2>,
    /// Size of the pattern's bounding box on the media (mm).
    pub size: [f64; 2],
    /// Words printed on the template at places of the sheet (a tube's seam numbers): the
    /// PDF draws them, no cutter receives them.
    pub labels: Vec<SheetLabel>,
}

/// A word printed on the template, centred on `at` (media mm).
#[derive(Clone, Debug, PartialEq)]
pub struct SheetLabel {
    /// Where (the middle of its baseline).
    pub at: Vec2,
    /// What.
    pub text: String,
}

impl Sheet {
    /// The sheet moved by `by` onto `media` (a sheet laid out in a region of a page, put
    /// on the page).
    pub fn moved(self, media: Media, by: Vec2) -> Sheet {
        Sheet {
            media,
            lines: self
                .lines
                .into_iter()
                .map(|l| l.mapped(|p| p + by))
                .collect(),
            vertices: self.vertices.into_iter().map(|p| p + by).collect(),
            labels: self
                .labels
                .into_iter()
                .map(|l| SheetLabel { at: l.at + by, ..l })
                .collect(),
            ..self
        }
    }

    /// The pattern's bounding box on the media (bottom-left, top-right): its vertices and
    /// the ends of its lines (a tube's glue tab reaches past the paper's vertices).
    pub fn bounds(&self) -> (Vec2, Vec2) {
        let ends: Vec<Vec2> = self.lines.iter().flat_map(|l| [l.a, l.b]).collect();
        let (a, b) = bounds(&self.vertices);
        let (c, d) = bounds(&ends);
        (a.inf(&c), b.sup(&d))
    }
}

/// Why a pattern does not go on the media.
#[derive(Debug, thiserror::Error)]
pub enum LayoutError {
    /// Too big for the media.
    #[error("{}", self.advice())]
    TooLarge {
        /// Needed width.
        need_w: f64,
        /// Needed height.
        need_h: f64,
        /// Media name.
        media: String,
        /// Media width.
        media_w: f64,
        /// Media height.
        media_h: f64,
    },
    /// Options that do not make a layout together, or one outside its range.
    #[error("{0}")]
    Bad(Advice),
}

impl LayoutError {
    /// What is wrong and which options would change it, for a face to name.
    pub fn advice(&self) -> Advice {
        match self {
            LayoutError::TooLarge {
                need_w,
                need_h,
                media,
                media_w,
                media_h,
            } => Advice::text(format!(
                "the pattern needs {need_w:.1} × {need_h:.1} mm with margins, but {media} is {media_w:.1} × {media_h:.1} mm; use a larger "
            ))
            .option(FabOption::Media)
            .then(", a smaller ")
            .option(FabOption::Width)
            .then(", or ")
            .option(FabOption::Tile),
            LayoutError::Bad(advice) => advice.clone(),
        }
    }
}

fn rotate(p: Vec2, angle: f64) -> Vec2 {
    let (s, c) = angle.sin_cos();
    Vec2::new(c * p.x - s * p.y, s * p.x + c * p.y)
}

/// Convex hull (Andrew's monotone chain), counter-clockwise.
fn hull(points: &[Vec2]) -> Vec<Vec2> {
    let mut p: Vec<Vec2> = points.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: Vec2, a: Vec2, b: Vec2| (a - o).perp(&(b - o));
    let mut lower: Vec<Vec2> = Vec::new();
    for &q in &p {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], q) <= 0.0 {
            lower.pop();
        }
        lower.push(q);
    }
    let mut upper: Vec<Vec2> = Vec::new();
    for &q in p.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], q) <= 0.0 {
            upper.pop();
        }
        upper.push(q);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// How large the pattern is placed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Sizing {
    /// As designed (design units are mm).
    #[default]
    Natural,
    /// Scaled so the laid-out sheet, after it is turned, is this wide (mm).
    Width(f64),
    /// As large as fits within the media's margins, in the orientation that allows most.
    Fit,
}

/// Places `vertices` and `lines` (flat pattern, mm) on `media` within `margin`, turned to
/// the fitting orientation of least area and sized by `sizing` (a width is the width of
/// the turned sheet, not of the design before it turns).
pub fn layout(
    vertices: &[Vec2],
    lines: &[CreaseLine],
    media: &Media,
    margin: f64,
    sizing: Sizing,
) -> Result<Sheet, LayoutError> {
    let (lo, hi) = bounds(vertices);
    check_sizes(sizing, margin)?;
    let usable = Vec2::new(media.width - 2.0 * margin, media.height - 2.0 * margin);
    if usable.x <= 0.0 || usable.y <= 0.0 {
        return Err(LayoutError::Bad(Advice::text(format!(
            "the margin of {margin} mm leaves no room on {} ({} × {} mm)",
            media.name, media.width, media.height
        ))));
    }
    let options = turns(vertices, sizing, usable);
    let fits = |s: Vec2| s.x <= usable.x + 1e-9 && s.y <= usable.y + 1e-9;
    let best = options.iter().copied().filter(|(_, _, s)| fits(*s)).min_by(
        |(a1, k1, s1), (a2, k2, s2)| {
            let (x, y) = match sizing {
                // Larger is better: compare the scales' inverses.
                Sizing::Fit => (1.0 / k1, 1.0 / k2),
                _ => (s1.x * s1.y, s2.x * s2.y),
            };
            // Within 0.1%, the smaller turn wins (keeps the design upright).
            if (x - y).abs() <= 1e-3 * x.max(y) {
                a1.abs().total_cmp(&a2.abs())
            } else {
                x.total_cmp(&y)
            }
        },
    );
    let Some((angle, scale, size)) = best else {
        let (_, _, s) = options
            .iter()
            .copied()
            .min_by(|a, b| (a.2.x * a.2.y).total_cmp(&(b.2.x * b.2.y)))
            .unwrap_or((0.0, 1.0, hi - lo));
        return Err(LayoutError::TooLarge {
            need_w: s.x + 2.0 * margin,
            need_h: s.y + 2.0 * margin,
            media: media.name.clone(),
            media_w: media.width,
            media_h: media.height,
        });
    };
    Ok(place_sheet(
        vertices,
        lines,
        media,
        margin,
        (angle, scale, size),
    ))
}

/// Refuses a width or margin that is not a length.
fn check_sizes(sizing: Sizing, margin: f64) -> Result<(), LayoutError> {
    use crate::limits::{MARGIN, SHEET_WIDTH};
    let refused = |option: FabOption| {
        move |e: crate::limits::OutOfRange| LayoutError::Bad(Advice::out_of_range(option, &e))
    };
    if let Sizing::Width(w) = sizing {
        SHEET_WIDTH
            .check("width", w)
            .map_err(refused(FabOption::Width))?;
    }
    MARGIN
        .check("margin", margin)
        .map_err(refused(FabOption::Margin))?;
    Ok(())
}

/// Candidate turns of the pattern, each as (angle, scale, laid-out size): every hull edge
/// laid flat (the least-area box is among them), each also turned a quarter. Each gets
/// its own scale: a width is measured after turning, and --fit fills `usable`.
fn turns(vertices: &[Vec2], sizing: Sizing, usable: Vec2) -> Vec<(f64, f64, Vec2)> {
    let (lo, _) = bounds(vertices);
    let unit: Vec<Vec2> = vertices.iter().map(|p| p - lo).collect();
    let h = hull(&unit);
    let mut candidates = vec![0.0, std::f64::consts::FRAC_PI_2];
    for i in 0..h.len() {
        let d = h[(i + 1) % h.len()] - h[i];
        let a = -d.y.atan2(d.x);
        candidates.extend([a, a + std::f64::consts::FRAC_PI_2]);
    }
    let unit_size = |angle: f64| {
        let turned: Vec<Vec2> = h.iter().map(|&p| rotate(p, angle)).collect();
        let (a, b) = bounds(&turned);
        b - a
    };
    let scale_at = |s: Vec2| match sizing {
        Sizing::Natural => 1.0,
        Sizing::Width(w) => w / s.x.max(f64::MIN_POSITIVE),
        Sizing::Fit => (usable.x / s.x).min(usable.y / s.y),
    };
    candidates
        .iter()
        .map(|&a| {
            let s = unit_size(a);
            let k = scale_at(s);
            (a, k, s * k)
        })
        .collect()
}

/// Places the pattern turned by `angle` and scaled, centred on `media`.
fn place_sheet(
    vertices: &[Vec2],
    lines: &[CreaseLine],
    media: &Media,
    margin: f64,
    (angle, scale, size): (f64, f64, Vec2),
) -> Sheet {
    let (lo, _) = bounds(vertices);
    let unit: Vec<Vec2> = vertices.iter().map(|p| p - lo).collect();
    let scaled: Vec<Vec2> = unit.iter().map(|&p| p * scale).collect();
    let turned: Vec<Vec2> = scaled.iter().map(|&p| rotate(p, angle)).collect();
    let (tlo, _) = bounds(&turned);
    let offset = Vec2::new(media.width - size.x, media.height - size.y) / 2.0 - tlo;
    let place = |p: Vec2| rotate((p - lo) * scale, angle) + offset;
    let placed_lines = lines.iter().map(|l| l.mapped(place)).collect();
    Sheet {
        media: media.clone(),
        margin,
        scale,
        rotation: angle,
        lines: placed_lines,
        vertices: vertices.iter().map(|&p| place(p)).collect(),
        size: [size.x, size.y],
        labels: Vec::new(),
    }
}

/// Pages (columns, rows) of `page` that show a sheet of `size`, each page's window inside
/// `margin`, neighbours overlapping by `overlap` mm.
pub fn tile_grid(size: [f64; 2], page: &Media, margin: f64, overlap: f64) -> (usize, usize) {
    let (uw, uh) = (page.width - 2.0 * margin, page.height - 2.0 * margin);
    // A micrometre of slack: the virtual sheet is padded by that much so it holds the
    // pattern, and must not cost a row of pages.
    let count = |total: f64, usable: f64, step: f64| {
        ((((total - usable) / step) - 1e-6).ceil().max(0.0) as usize) + 1
    };
    (
        count(size[0], uw, uw - overlap),
        count(size[1], uh, uh - overlap),
    )
}

/// Lays a pattern too large for `page` out for tiling: turned to need the fewest pages
/// (then the least area, then the smallest turn), on a virtual sheet just large enough.
pub fn layout_tiled(
    vertices: &[Vec2],
    lines: &[CreaseLine],
    page: &Media,
    margin: f64,
    overlap: f64,
    sizing: Sizing,
) -> Result<Sheet, LayoutError> {
    check_sizes(sizing, margin)?;
    let usable = Vec2::new(page.width - 2.0 * margin, page.height - 2.0 * margin);
    if usable.x <= overlap || usable.y <= overlap {
        return Err(LayoutError::Bad(
            Advice::text(format!(
                "tiled pages of {} keep a margin of {margin} mm (room for each page's label, scale bar and legend) and overlap by {overlap} mm: that leaves no room for the sheet; tile over larger pages (",
                page.name
            ))
            .option(FabOption::Media)
            .then(" a4)"),
        ));
    }
    let pages = |s: Vec2| {
        let (c, r) = tile_grid(
            [s.x + 2.0 * margin, s.y + 2.0 * margin],
            page,
            margin,
            overlap,
        );
        c.saturating_mul(r)
    };
    let best = turns(vertices, sizing, usable)
        .into_iter()
        .min_by(|x, y| {
            (pages(x.2), x.2.x * x.2.y, x.0.abs())
                .partial_cmp(&(pages(y.2), y.2.x * y.2.y, y.0.abs()))
                .expect("finite sizes")
        })
        .expect("at least two turns");
    // Each page is drawn in full: their count bounds the PDF's size and the work.
    let needed = pages(best.2);
    if crate::limits::PAGES
        .check_count("tile", needed as u64)
        .is_err()
    {
        return Err(LayoutError::Bad(
            Advice::text("")
                .option(FabOption::Tile)
                .then(format!(
                    ": the sheet would need {} pages of {}, more than {}: use larger ",
                    crate::limits::short(needed as f64),
                    page.name,
                    crate::limits::PAGES.max
                ))
                .option(FabOption::Media)
                .then(", a smaller ")
                .option(FabOption::Width)
                .then(" or a smaller ")
                .option(FabOption::Margin),
        ));
    }
    let size = best.2;
    let sheet_media = Media {
        name: format!(
            "{:.0}x{:.0}mm (tiled over {})",
            size.x + 2.0 * margin,
            size.y + 2.0 * margin,
            page.name
        ),
        width: size.x + 2.0 * margin + 1e-6,
        height: size.y + 2.0 * margin + 1e-6,
    };
    Ok(place_sheet(vertices, lines, &sheet_media, margin, best))
}
