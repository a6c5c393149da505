//! Registration of a two-sided job: the front job cuts three small crosses through the
//! sheet, the maker turns the sheet over left to right, and the back job starts by cutting
//! the same crosses where the turned slits must now lie. On a sheet loaded true the knife
//! runs in the old slits; one that is off, or turned the wrong way, shows a second cross
//! before anything is scored.
//!
//! The crosses sit in a band just inside the machine's margin (the pattern is laid out
//! [`MARK_BAND_MM`] further in), at three corners of the reachable area. Three, not four,
//! and not symmetric about the vertical mid-line: a sheet turned top to bottom instead of
//! left to right puts a slit where the back job has no cross.

use super::{LineKind, Media, Stroke};
use crate::mesh::Vec2;

/// Width of the band kept free for the crosses inside the margin, mm.
pub const MARK_BAND_MM: f64 = 8.0;

/// Length of a cross's arms end to end, mm: large enough to see and align by eye, small
/// enough to leave [`MARK_BAND_MM`] − 5 mm between a cross and the pattern.
pub const MARK_ARM_MM: f64 = 5.0;

/// [`Stroke::line`] of a registration cut: it belongs to no sheet line.
pub const MARK_LINE: usize = usize::MAX;

/// A point as seen once the sheet is turned over left to right on media `width` wide: the
/// back job's coordinates of the front's `p`.
pub fn mirrored(width: f64, p: Vec2) -> Vec2 {
    Vec2::new(width - p.x, p.y)
}

/// Centres of the front job's crosses: bottom-left, bottom-right and top-right corners of
/// the reachable area, half a band in from the margin (top-left is where the template's
/// title and summary are printed).
pub fn front_centres(media: &Media, margin: f64) -> [Vec2; 3] {
    let inset = margin + MARK_BAND_MM / 2.0;
    [
        Vec2::new(inset, inset),
        Vec2::new(media.width - inset, inset),
        Vec2::new(media.width - inset, media.height - inset),
    ]
}

/// Centres of the back job's crosses: where the front's slits lie once the sheet is turned.
pub fn back_centres(media: &Media, margin: f64) -> [Vec2; 3] {
    front_centres(media, margin).map(|p| mirrored(media.width, p))
}

/// The knife strokes of crosses at `centres`: a horizontal then a vertical arm each, in
/// the order given.
pub fn cross_strokes(centres: &[Vec2]) -> Vec<Stroke> {
    let h = MARK_ARM_MM / 2.0;
    centres
        .iter()
        .flat_map(|&c| {
            [
                (c - Vec2::new(h, 0.0), c + Vec2::new(h, 0.0)),
                (c - Vec2::new(0.0, h), c + Vec2::new(0.0, h)),
            ]
        })
        .map(|(from, to)| Stroke::straight(LineKind::Cut, from, to, MARK_LINE))
        .collect()
}

/// What the maker does, in order, for a two-sided job whose files are `front` and `back`
/// (e.g. `sheet.hpgl`, `sheet-back.hpgl`).
pub fn steps(front: &str, back: &str) -> Vec<String> {
    vec![
        format!("1. Load the sheet front side up and run {front}: it cuts three registration crosses, then scores the valleys."),
        "2. Turn the sheet over left to right (about its vertical edge, so the top stays at the top) and load it against the same corner.".to_string(),
        format!("3. Run {back}: its first strokes cut the crosses again. The knife must run in the old slits; if it cuts beside them, stop, realign the sheet and run {back} again."),
        "4. It then scores the mountains and cuts the outline last, so the piece stays held until both sides are scored.".to_string(),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn media() -> Media {
        Media::parse("a4").unwrap()
    }

    #[test]
    fn the_turned_front_crosses_fall_on_the_back_crosses() {
        let m = media();
        let back = back_centres(&m, 10.0);
        for p in front_centres(&m, 10.0) {
            let q = mirrored(m.width, p);
            assert!(back.iter().any(|b| (b - q).norm() < 1e-12));
        }
    }

    #[test]
    fn a_sheet_turned_top_to_bottom_misses_a_cross() {
        let m = media();
        let back = back_centres(&m, 10.0);
        let wrong: Vec<Vec2> = front_centres(&m, 10.0)
            .iter()
            .map(|p| Vec2::new(p.x, m.height - p.y))
            .collect();
        let missed = wrong
            .iter()
            .filter(|q| back.iter().all(|b| (*b - **q).norm() > MARK_ARM_MM))
            .count();
        assert!(missed >= 1);
    }

    #[test]
    fn crosses_stay_inside_the_band() {
        let m = media();
        let margin = 10.0;
        for s in cross_strokes(&front_centres(&m, margin)) {
            for p in [s.from, s.to] {
                let inner = p.x.min(m.width - p.x).min(p.y).min(m.height - p.y);
                assert!(inner >= margin && inner <= margin + MARK_BAND_MM, "{p:?}");
            }
        }
    }
}
