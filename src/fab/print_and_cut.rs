//! Print-then-cut: the sheet is printed on paper with registration marks, and the cutter
//! finds the marks with its optical sensor and cuts in their frame.
//!
//! **Silhouette (Type 1 marks)**, as inkscape-silhouette draws them
//! (`render_silhouette_regmarks.py`) and drives a Cameo to find them (`Graphtec.py`,
//! `TB123`): a filled 5 mm square whose top-left corner is the frame's origin, and two
//! L-shaped corner marks of 0.3 mm lines with 20 mm arms, at the frame's top-right and
//! bottom-left corners. Its defaults put the origin 15 mm from the page's left edge and
//! 20 mm from its top, and the frame 180 × 230 mm (an A4 page: 15 mm free on the right,
//! 47 mm at the bottom); crease keeps those insets on any page. After registration the
//! cutter's (0, 0) is the origin, x runs right and y down, and it cuts nothing outside
//! the frame. The 20 × 20 mm corners at the three marks (and 2 mm beyond) are kept free
//! of print, so the sensor sees the marks alone.
//!
//! **Cricut (Print Then Cut)**: Design Space prints its own frame around the image and
//! finds it itself; its geometry is not published and is not drawn here. The image
//! Design Space takes is at most 6.75 × 9.25 in, so the sheet is laid out within that.

use super::advice::{Advice, FabOption};
use super::layout::{layout, LayoutError, Media, Sheet, Sizing};
use super::lines::CreaseLine;
use crate::mesh::Vec2;

/// Side of the Silhouette origin square, mm.
pub const SQUARE_MM: f64 = 5.0;
/// Length of an arm of a Silhouette corner mark, mm.
pub const ARM_MM: f64 = 20.0;
/// Width of a corner mark's lines, mm (thicker marks register worse).
pub const LINE_MM: f64 = 0.3;
/// Print-free distance beyond a mark's 20 mm corner, mm.
pub const KEEP_OUT_MM: f64 = 2.0;
/// The frame origin's distance from the page's left edge, mm.
pub const ORIGIN_LEFT_MM: f64 = 15.0;
/// The frame origin's distance from the page's top edge, mm.
pub const ORIGIN_TOP_MM: f64 = 20.0;
/// Page left free right of the frame, mm.
pub const RIGHT_MM: f64 = 15.0;
/// Page left free below the frame, mm (where the page's caption is printed).
pub const BOTTOM_MM: f64 = 47.0;
/// The largest image Cricut Design Space prints for Print Then Cut, mm (6.75 × 9.25 in).
pub const CRICUT_IMAGE_MM: [f64; 2] = [171.45, 234.95];

/// The Cricut image's distance from the page's top, mm.
pub const CRICUT_TOP_MM: f64 = 10.0;
/// Room kept below a print-and-cut sheet for the page's caption and scale bar, mm.
pub const CAPTION_BAND_MM: f64 = 30.0;

/// Whose registration marks a print-and-cut sheet carries (a profile's `print_and_cut`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MarkFamily {
    /// Silhouette Type 1: a square and two corner marks, drawn by crease.
    Silhouette,
    /// Cricut Print Then Cut: a frame Design Space draws itself.
    Cricut,
}

impl MarkFamily {
    /// The name a profile gives it.
    pub fn name(self) -> &'static str {
        match self {
            MarkFamily::Silhouette => "silhouette",
            MarkFamily::Cricut => "cricut",
        }
    }

    /// Where the maker goes next.
    pub fn software(self) -> &'static str {
        match self {
            MarkFamily::Silhouette => "the printer, then the cutter",
            MarkFamily::Cricut => "Cricut Design Space (Print Then Cut)",
        }
    }

    /// What the maker does, in order; `jobs` are the cutter's files written.
    pub fn steps(self, jobs: &[(String, Vec<u8>)]) -> Vec<String> {
        let job = jobs.first().map_or("sheet.gpgl", |j| j.0.as_str());
        match self {
            MarkFamily::Silhouette => vec![
                "Print page 1 of sheet.pdf at 100% (actual size, not fit to page), marks in solid black on white paper.".into(),
                "Lay the print on the cutting mat with the black square at the top left and load the mat.".into(),
                format!("crease plot OUT --port /dev/usb/lp0 sends {job}: the cutter first searches for the square and the two corner marks, and cuts nothing if it cannot find them."),
            ],
            MarkFamily::Cricut => vec![
                "In Design Space: Upload > Upload Image, choose sheet.svg and add it to the canvas; do not resize it.".into(),
                "Ungroup it. Select the Print layer and Flatten it (it becomes a Print Then Cut image), then select it with the Cut and Score layers and Attach.".into(),
                "Make It: Send to Printer with Add Bleed off, load the printed sheet on the mat, and cut. Design Space prints its own frame around the image and finds it.".into(),
            ],
        }
    }

    /// The lines printed under the sheet.
    pub fn caption(self) -> Vec<String> {
        match self {
            MarkFamily::Silhouette => vec![
                "Silhouette print-and-cut: print at 100%; the cutter finds the square and the two corner marks.".into(),
                "Keep the marks clean and the corners around them free of ink.".into(),
            ],
            MarkFamily::Cricut => vec![
                "Cricut Print Then Cut: print from Design Space (it adds its own frame), not from this PDF.".into(),
                "This page shows the image as Design Space takes it, at 100%.".into(),
            ],
        }
    }
}

/// A rectangle on the page, mm, y up (the sheet's coordinates).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Bottom-left corner.
    pub lo: Vec2,
    /// Top-right corner.
    pub hi: Vec2,
}

impl Rect {
    /// Width and height.
    pub fn size(&self) -> Vec2 {
        self.hi - self.lo
    }

    /// Whether `other` lies inside, to within `slack` mm.
    pub fn holds(&self, other: &Rect, slack: f64) -> bool {
        other.lo.x >= self.lo.x - slack
            && other.lo.y >= self.lo.y - slack
            && other.hi.x <= self.hi.x + slack
            && other.hi.y <= self.hi.y + slack
    }

    /// Whether the two overlap by more than `slack` mm on both axes.
    pub fn overlaps(&self, other: &Rect, slack: f64) -> bool {
        self.lo.x < other.hi.x - slack
            && other.lo.x < self.hi.x - slack
            && self.lo.y < other.hi.y - slack
            && other.lo.y < self.hi.y - slack
    }
}

/// `report.json`'s `print_and_cut`: the layout a print-and-cut sheet was made with
/// ([`PrintLayout::report`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PrintReport {
    /// The marks' family ([`MarkFamily::name`]).
    pub family: String,
    /// The page the sheet is printed on.
    pub page: Media,
    /// The Silhouette marks; none for Cricut, whose frame Design Space draws.
    pub marks: Option<MarksReport>,
}

/// Where the Silhouette marks are printed and how large ([`MarkFrame`]), mm.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MarksReport {
    /// The frame's origin (the square's top-left corner) from the page's top-left
    /// corner, x right and y down.
    pub origin_from_top_left_mm: [f64; 2],
    /// The frame's width and length ([`MarkFrame::size`]).
    pub frame_mm: [f64; 2],
    /// The origin square's side ([`SQUARE_MM`]).
    pub square_mm: f64,
    /// The corner marks' arms ([`ARM_MM`]).
    pub arm_mm: f64,
    /// The marks' line width ([`LINE_MM`]).
    pub line_mm: f64,
}

/// The Silhouette marks' frame on a page.
#[derive(Clone, Debug, PartialEq)]
pub struct MarkFrame {
    /// The printed page.
    pub page: Media,
    /// The frame's top-left corner (the origin square's top-left corner), page mm, y up.
    pub origin: Vec2,
    /// The frame's width (origin to the top-right mark) and length (origin to the
    /// bottom-left mark), mm: what `TB123` is told.
    pub size: [f64; 2],
}

impl MarkFrame {
    /// The frame on `page` at inkscape-silhouette's insets; a page too small to leave a
    /// frame of 100 × 100 mm is refused.
    pub fn silhouette(page: &Media) -> Result<MarkFrame, String> {
        let size = [
            page.width - ORIGIN_LEFT_MM - RIGHT_MM,
            page.height - ORIGIN_TOP_MM - BOTTOM_MM,
        ];
        if size[0] < 100.0 || size[1] < 100.0 {
            return Err(format!(
                "{} ({} × {} mm) is too small for Silhouette registration marks: they need a page of at least {} × {} mm (a4 or letter)",
                page.name,
                crate::limits::short(page.width),
                crate::limits::short(page.height),
                100.0 + ORIGIN_LEFT_MM + RIGHT_MM,
                100.0 + ORIGIN_TOP_MM + BOTTOM_MM
            ));
        }
        Ok(MarkFrame {
            page: page.clone(),
            origin: Vec2::new(ORIGIN_LEFT_MM, page.height - ORIGIN_TOP_MM),
            size,
        })
    }

    /// The filled origin square.
    pub fn square(&self) -> Rect {
        Rect {
            lo: self.origin - Vec2::new(0.0, SQUARE_MM),
            hi: self.origin + Vec2::new(SQUARE_MM, 0.0),
        }
    }

    /// The two corner marks, each as (corner, end of its horizontal arm, end of its
    /// vertical arm): top-right, then bottom-left.
    pub fn corner_marks(&self) -> [[Vec2; 3]; 2] {
        let [w, l] = self.size;
        let top_right = self.origin + Vec2::new(w, 0.0);
        let bottom_left = self.origin - Vec2::new(0.0, l);
        [
            [
                top_right,
                top_right - Vec2::new(ARM_MM, 0.0),
                top_right - Vec2::new(0.0, ARM_MM),
            ],
            [
                bottom_left,
                bottom_left + Vec2::new(ARM_MM, 0.0),
                bottom_left + Vec2::new(0.0, ARM_MM),
            ],
        ]
    }

    /// The frame itself (where the cutter cuts).
    pub fn frame(&self) -> Rect {
        let [w, l] = self.size;
        Rect {
            lo: self.origin - Vec2::new(0.0, l),
            hi: self.origin + Vec2::new(w, 0.0),
        }
    }

    /// The print-free corners at the three marks.
    pub fn keep_out(&self) -> [Rect; 3] {
        let f = self.frame();
        let c = ARM_MM + KEEP_OUT_MM;
        let corner = |x: f64, y: f64| Rect {
            lo: Vec2::new(x.min(x + c), y.min(y + c)),
            hi: Vec2::new(x.max(x + c), y.max(y + c)),
        };
        [
            corner(f.lo.x, f.hi.y - c),
            corner(f.hi.x - c, f.hi.y - c),
            corner(f.lo.x, f.lo.y),
        ]
    }

    /// The two largest rectangles inside the frame that keep [`KEEP_OUT_MM`] from its
    /// edges and miss the marked corners: the frame's full width between the corner
    /// bands, and its full length between them. A sheet centred in either is clear of
    /// every mark.
    pub fn regions(&self) -> [Rect; 2] {
        let f = self.frame();
        let (k, c) = (KEEP_OUT_MM, ARM_MM + KEEP_OUT_MM);
        [
            Rect {
                lo: f.lo + Vec2::new(k, c),
                hi: f.hi - Vec2::new(k, c),
            },
            Rect {
                lo: f.lo + Vec2::new(c, k),
                hi: f.hi - Vec2::new(c, k),
            },
        ]
    }

    /// A page point (mm, y up) in the cutter's coordinates after registration: mm right
    /// of the origin and mm down from it.
    pub fn to_cutter(&self, p: Vec2) -> Vec2 {
        Vec2::new(p.x - self.origin.x, self.origin.y - p.y)
    }
}

/// Where a print-and-cut sheet may go on its page: inside the Silhouette marks' frame and
/// clear of the marks, or within the image Cricut Design Space prints, centred.
#[derive(Clone, Debug, PartialEq)]
pub struct PrintLayout {
    /// Whose marks.
    pub family: MarkFamily,
    /// The printed page.
    pub page: Media,
    /// The Silhouette marks; none for Cricut, whose frame Design Space draws.
    pub frame: Option<MarkFrame>,
    /// Rectangles the sheet may be centred in.
    pub regions: Vec<Rect>,
}

impl PrintLayout {
    /// The layout of `family`'s marks on `page`.
    pub fn new(family: MarkFamily, page: &Media) -> Result<PrintLayout, String> {
        match family {
            MarkFamily::Silhouette => {
                let frame = MarkFrame::silhouette(page)?;
                Ok(PrintLayout {
                    family,
                    page: page.clone(),
                    regions: frame.regions().to_vec(),
                    frame: Some(frame),
                })
            }
            MarkFamily::Cricut => {
                let [w, h] = CRICUT_IMAGE_MM;
                if page.width < w || page.height < h + CRICUT_TOP_MM + CAPTION_BAND_MM {
                    return Err(format!(
                        "{} ({} × {} mm) is too small for the {w} × {h} mm image Cricut Print Then Cut prints and its caption: use letter or a4",
                        page.name,
                        crate::limits::short(page.width),
                        crate::limits::short(page.height)
                    ));
                }
                let lo = Vec2::new((page.width - w) / 2.0, page.height - CRICUT_TOP_MM - h);
                Ok(PrintLayout {
                    family,
                    page: page.clone(),
                    frame: None,
                    regions: vec![Rect {
                        lo,
                        hi: lo + Vec2::new(w, h),
                    }],
                })
            }
        }
    }

    /// What report.json says of the layout: the marks' family, the page, and for
    /// Silhouette the frame (origin from the page's top-left corner, mm) and mark sizes.
    pub fn report(&self) -> PrintReport {
        PrintReport {
            family: self.family.name().to_string(),
            page: self.page.clone(),
            marks: self.frame.as_ref().map(|f| MarksReport {
                origin_from_top_left_mm: [f.origin.x, self.page.height - f.origin.y],
                frame_mm: f.size,
                square_mm: SQUARE_MM,
                arm_mm: ARM_MM,
                line_mm: LINE_MM,
            }),
        }
    }

    /// The flat pattern laid out in one of the regions (`--fit`: the one that allows the
    /// largest sheet; otherwise the first it fits), on the page.
    pub fn place(
        &self,
        flat: &[Vec2],
        lines: &[CreaseLine],
        sizing: Sizing,
    ) -> Result<Sheet, Advice> {
        let mut placed: Vec<Sheet> = Vec::new();
        for r in &self.regions {
            let size = r.size();
            let region = Media {
                name: self.page.name.clone(),
                width: size.x,
                height: size.y,
            };
            match layout(flat, lines, &region, 0.0, sizing) {
                Ok(sheet) => placed.push(sheet.moved(self.page.clone(), r.lo)),
                Err(LayoutError::TooLarge { .. }) => {}
                Err(e) => return Err(e.advice()),
            }
        }
        let best = match sizing {
            Sizing::Fit => placed
                .into_iter()
                .max_by(|a, b| a.scale.total_cmp(&b.scale)),
            _ => placed.into_iter().next(),
        };
        best.ok_or_else(|| {
            let rooms: Vec<String> = self
                .regions
                .iter()
                .map(|r| {
                    format!(
                        "{} × {} mm",
                        crate::limits::short(r.size().x),
                        crate::limits::short(r.size().y)
                    )
                })
                .collect();
            Advice::text(format!(
                "the pattern does not fit the print-and-cut area of {}: there is room for {}; use ",
                self.page.name,
                rooms.join(" or ")
            ))
            .option(FabOption::Fit)
            .then(" or a smaller ")
            .option(FabOption::Width)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn a4() -> MarkFrame {
        MarkFrame::silhouette(&Media::parse("a4").unwrap()).unwrap()
    }

    #[test]
    fn on_a4_the_frame_is_inkscape_silhouettes_default() {
        // Its defaults: origin 15 mm from the left, 20 mm from the top; marks 180 mm
        // apart across and 230 mm down.
        let f = a4();
        assert_eq!(f.size, [180.0, 230.0]);
        assert_eq!(f.origin, Vec2::new(15.0, 277.0));
        assert_eq!(f.to_cutter(f.origin), Vec2::new(0.0, 0.0));
        assert_eq!(
            f.to_cutter(f.corner_marks()[0][0]),
            Vec2::new(180.0, 0.0),
            "the top-right mark is W to the right"
        );
        assert_eq!(f.to_cutter(f.corner_marks()[1][0]), Vec2::new(0.0, 230.0));
    }

    #[test]
    fn the_regions_lie_in_the_frame_and_miss_every_mark() {
        let f = a4();
        for r in f.regions() {
            assert!(f.frame().holds(&r, 0.0));
            for k in f.keep_out() {
                assert!(!r.overlaps(&k, 1e-9), "{r:?} meets {k:?}");
            }
            assert!(!r.overlaps(&f.square(), 0.0));
        }
        // The keep-out corners hold the marks.
        assert!(f.keep_out()[0].holds(&f.square(), 0.0));
        for (m, k) in f.corner_marks().iter().zip(&f.keep_out()[1..]) {
            for p in m {
                assert!(k.holds(&Rect { lo: *p, hi: *p }, 1e-9));
            }
        }
    }

    #[test]
    fn a_page_too_small_is_refused_by_name() {
        let e = MarkFrame::silhouette(&Media::parse("100x150mm").unwrap()).unwrap_err();
        assert!(e.contains("100x150mm") && e.contains("too small"), "{e}");
    }
}
