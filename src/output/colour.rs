//! The one colour of each operation, in every file crease writes (SVG, PDF, DXF and the
//! previews): cut black, mountain red, valley blue, flat light grey. Laser and cutter
//! software assigns power, speed or a tool by colour, so no two files may give one colour
//! two meanings.

use crate::fab::LineKind;

/// sRGB of a kind's strokes.
pub fn rgb(kind: LineKind) -> [u8; 3] {
    match kind {
        LineKind::Cut => [0, 0, 0],
        LineKind::Mountain => [255, 0, 0],
        LineKind::Valley => [0, 0, 255],
        LineKind::Flat => [192, 192, 192],
    }
}

/// The same colour as `#rrggbb`.
pub fn hex(kind: LineKind) -> String {
    let [r, g, b] = rgb(kind);
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// The same colour as an AutoCAD colour index (R12 has no true colour): 7 (black on a
/// light background, as laser software shows it), 1 red, 5 blue, 9 light grey (192, 192,
/// 192).
pub fn aci(kind: LineKind) -> u8 {
    match kind {
        LineKind::Cut => 7,
        LineKind::Mountain => 1,
        LineKind::Valley => 5,
        LineKind::Flat => 9,
    }
}

/// A colour given as `#RRGGBB` (or `RRGGBB`); anything else is refused naming `what`.
pub fn parse_hex(what: &str, text: &str) -> Result<[u8; 3], String> {
    let hex = text.trim().trim_start_matches('#');
    let bad = || format!("{what} \"{text}\" is not a colour: give #RRGGBB, e.g. #ffe8a0");
    if hex.len() != 6 || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(bad());
    }
    let byte = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).map_err(|_| bad());
    Ok([byte(0)?, byte(2)?, byte(4)?])
}
