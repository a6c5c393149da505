//! The physical range of every quantity a user can type, in one place: a flag, a profile
//! key, a studio parameter and a generator option that mean the same quantity are checked
//! against the same [`Range`] here, before anything is sized from them. Messages name the
//! input, the allowed range and the value, printed short ([`short`]: `1e308`, not 309
//! digits).

/// The allowed closed interval of one quantity, in its unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// What the quantity is ("cell size").
    pub what: &'static str,
    /// Its unit ("mm"), or "" for a pure number.
    pub unit: &'static str,
    /// Smallest allowed value.
    pub min: f64,
    /// Largest allowed value.
    pub max: f64,
}

/// A value outside its [`Range`], or not a number.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{input}{}", self.after_input())]
pub struct OutOfRange {
    /// The input that gave it: a flag (`--size`), a key (`machines/x.toml: clearance_mm`).
    pub input: String,
    /// The quantity.
    pub what: &'static str,
    /// The value given.
    pub value: f64,
    /// Its range.
    pub range: Range,
}

impl OutOfRange {
    /// The message after the input's name: " = VALUE: WHAT must be RANGE".
    pub fn after_input(&self) -> String {
        format!(
            " = {}: {} must be {}",
            short(self.value),
            self.what,
            self.range.span()
        )
    }
}

impl Range {
    /// The value when it lies in the range, else the error naming `input`.
    pub fn check(&self, input: impl Into<String>, value: f64) -> Result<f64, OutOfRange> {
        if value.is_finite() && value >= self.min && value <= self.max {
            Ok(value)
        } else {
            Err(OutOfRange {
                input: input.into(),
                what: self.what,
                value,
                range: *self,
            })
        }
    }

    /// A whole number in the range.
    pub fn check_count(&self, input: impl Into<String>, value: u64) -> Result<u64, OutOfRange> {
        self.check(input, value as f64).map(|_| value)
    }

    /// "from 0.01 to 1e4 mm".
    fn span(&self) -> String {
        let unit = if self.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", self.unit)
        };
        format!("from {} to {}{unit}", short(self.min), short(self.max))
    }
}

/// A number printed in at most about a dozen characters: plain when it reads so
/// (`12.5`, `0.001`), else in exponent form (`1e308`, `-3.2e-9`).
pub fn short(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if x == 0.0 || (1e-3..1e6).contains(&a) {
        let s = format!("{x:.6}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        return s.to_string();
    }
    let s = format!("{x:.3e}");
    let (mantissa, exp) = s.split_once('e').unwrap_or((&s, "0"));
    let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
    format!("{mantissa}e{exp}")
}

/// A text quoted in a message, cut to 60 characters (a hostile header or value may be
/// megabytes long).
pub fn short_text(text: &str) -> String {
    const MAX: usize = 60;
    if text.chars().count() <= MAX {
        return text.to_string();
    }
    let cut: String = text.chars().take(MAX).collect();
    format!("{cut}…")
}

/// A length drawn on a sheet or a pattern's cell edge: from a hundredth of a millimetre
/// (below any blade's resolution) to 10 m.
pub const LENGTH: Range = Range {
    what: "a length on the sheet",
    unit: "mm",
    min: 0.01,
    max: 10_000.0,
};

/// A margin, gap or offset on the sheet: zero allowed.
pub const MARGIN: Range = Range {
    what: "a margin",
    unit: "mm",
    min: 0.0,
    max: 1_000.0,
};

/// One side of the media: a 1 mm label up to a 50 m roll.
pub const MEDIA_SIDE: Range = Range {
    what: "a side of the media",
    unit: "mm",
    min: 1.0,
    max: 50_000.0,
};

/// The width a design is scaled to: at least 5 mm (below that every crease is shorter
/// than a blade's dash) and at most a 50 m roll.
pub const SHEET_WIDTH: Range = Range {
    what: "the sheet's width",
    unit: "mm",
    min: 5.0,
    max: 50_000.0,
};

/// Cells along one side of a generated pattern.
pub const CELLS: Range = Range {
    what: "cells along one side",
    unit: "",
    min: 1.0,
    max: 2_000.0,
};

/// Cells along one side of a pattern generated in the studio: 200 × 200 cells is over
/// 40k vertices, already past interactive speed (the command line takes [`CELLS`]).
pub const STUDIO_CELLS: Range = Range {
    what: "cells along one side in the studio",
    unit: "",
    min: 1.0,
    max: 200.0,
};

/// How far a wished position may lie from where it pulls, in sizes of the design (its
/// bounding box's diagonal): a studio drag's target from its vertex, a script's design-
/// mode target from the fixed vertices. Farther is a slip or a hostile request.
pub const DRAG_REACH_IN_SIZES: f64 = 10.0;

/// How far a fit target may be offset along its normals, as a fraction of its extent
/// (its bounding box's diagonal): more turns the surface inside out.
pub const TARGET_OFFSET_OF_EXTENT: f64 = 0.5;

/// A tolerance given to `verify --tol`, used as given for every condition (radians for
/// angles, mm or a relative error for lengths): positive, and no looser than 1000, past
/// which every condition passes and the verdict says nothing.
pub const VERIFY_TOL: Range = Range {
    what: "a tolerance",
    unit: "",
    min: 1e-15,
    max: 1e3,
};

/// Cells of a generated pattern in all (nx × ny): what its memory and time grow with.
/// Up to 100,000, so the 315 × 315 Miura-ori (99,856 vertices) that the solver's aim of
/// 3 steps/s at 100k vertices is measured on (`CREASE_BENCH_LARGE=1 cargo bench --bench
/// solver`) can be generated.
pub const CELLS_IN_ALL: Range = Range {
    what: "the number of cells (nx × ny)",
    unit: "",
    min: 1.0,
    max: 100_000.0,
};

/// The widest a generated pattern may be (nx or ny cells of `size`).
pub const PATTERN_EXTENT: Range = Range {
    what: "the pattern's extent (cells × size)",
    unit: "mm",
    min: 0.01,
    max: 100_000.0,
};

/// The falloff radius of a drag (how far round the dragged vertex the wish reaches).
pub const RADIUS: Range = Range {
    what: "the drag radius",
    unit: "mm",
    min: 0.01,
    max: 100_000.0,
};

/// Solver steps of one command.
pub const STEPS: Range = Range {
    what: "the number of steps",
    unit: "",
    min: 1.0,
    max: 100_000.0,
};

/// Steps of a folding motion (`crease animate --frames`): its frames are these and the
/// flat sheet.
pub const FRAMES: Range = Range {
    what: "the number of frames",
    unit: "",
    min: 1.0,
    max: 1_000.0,
};

/// A serial line's rate.
pub const BAUD: Range = Range {
    what: "the baud rate",
    unit: "baud",
    min: 50.0,
    max: 4_000_000.0,
};

/// A profile's plotter units per millimetre (HP-GL's 40, GP-GL's 20, a laser's 100).
pub const UNITS_PER_MM: Range = Range {
    what: "the plotter units per mm",
    unit: "",
    min: 1.0,
    max: 1_000.0,
};

/// A tool's or the pen-up travel's speed: positive, up to 10 m/s.
pub const SPEED: Range = Range {
    what: "a speed",
    unit: "mm/s",
    min: 1e-3,
    max: 10_000.0,
};

/// A tool's force, in the machine's own units: positive.
pub const FORCE: Range = Range {
    what: "a force",
    unit: "",
    min: 1e-6,
    max: 1e6,
};

/// A drag knife's offset: 0 (a pen) to 2.5 mm.
pub const BLADE_OFFSET: Range = Range {
    what: "the blade offset",
    unit: "mm",
    min: 0.0,
    max: 2.5,
};

/// A cut or a gap of a dash code: a blade makes none shorter than 0.1 mm.
pub const DASH: Range = Range {
    what: "a dash's cut or gap",
    unit: "mm",
    min: 0.1,
    max: 1_000.0,
};

/// A plotter's input buffer.
pub const BUFFER: Range = Range {
    what: "the buffer",
    unit: "bytes",
    min: 1.0,
    max: 16_777_216.0,
};

/// How fast an emulated plotter draws the job's bytes.
pub const DRAW_RATE: Range = Range {
    what: "the drawing rate",
    unit: "bytes/s",
    min: 1.0,
    max: 1_000_000.0,
};

/// The distance a scored line stops short of a vertex or another line (0 for a pen).
pub const CLEARANCE: Range = Range {
    what: "the clearance",
    unit: "mm",
    min: 0.0,
    max: 50.0,
};

/// A fraction of the way, as for fold amounts.
pub const FRACTION: Range = Range {
    what: "a fraction",
    unit: "",
    min: 0.0,
    max: 1.0,
};

/// The twist allowance α of a facet line (§2.4), in [0, 1).
pub const ALPHA: Range = Range {
    what: "alpha",
    unit: "",
    min: 0.0,
    max: 0.999,
};

/// The remeshing threshold (§4): a fraction of the mean edge, in (0, 1).
pub const REMESH: Range = Range {
    what: "the remesh threshold (a fraction of the mean edge)",
    unit: "",
    min: 0.001,
    max: 0.999,
};

/// The Miura parallelogram angle γ, degrees (strictly between 0 and 90).
pub const MIURA_ANGLE: Range = Range {
    what: "the parallelogram angle",
    unit: "degrees",
    min: 0.1,
    max: 89.9,
};

/// Strokes (cuts and dashes) of one sheet: the router's time and memory grow with them
/// (50,000 take about 7 s and 0.8 GB).
pub const STROKES: Range = Range {
    what: "the number of strokes",
    unit: "",
    min: 0.0,
    max: 50_000.0,
};

/// Pages a tiled sheet may be split into.
pub const PAGES: Range = Range {
    what: "the number of tiled pages",
    unit: "",
    min: 1.0,
    max: 500.0,
};

/// The extent (bounding-box diagonal) of a target surface for `crease fit`: a sheet is
/// fitted to objects from a millimetre to a façade; a kilometre is no sheet's target.
pub const TARGET_EXTENT: Range = Range {
    what: "a target surface's extent",
    unit: "mm",
    min: 1.0,
    max: 100_000.0,
};

/// Triangles of a target surface: its hierarchy costs about 100 bytes a triangle.
pub const TARGET_TRIANGLES: Range = Range {
    what: "the number of triangles",
    unit: "",
    min: 1.0,
    max: 4_000_000.0,
};

/// Triangles along one side of a generated target surface.
pub const SURFACE_RESOLUTION: Range = Range {
    what: "triangles along a side",
    unit: "",
    min: 1.0,
    max: 1_000.0,
};

/// A fit's distance goal (`--within`), in mm.
pub const FIT_GOAL: Range = Range {
    what: "the distance goal",
    unit: "mm",
    min: 1e-6,
    max: 100_000.0,
};

/// A shift of a target surface (the studio's placement), per axis.
pub const TARGET_SHIFT: Range = Range {
    what: "a shift of the target",
    unit: "mm",
    min: -100_000.0,
    max: 100_000.0,
};

/// A turn about one axis.
pub const TURN: Range = Range {
    what: "a turn",
    unit: "degrees",
    min: -360.0,
    max: 360.0,
};

/// The recorded rounding of a converted file's coordinates (`crease:coordinatePrecision`):
/// half a millimetre is a file rounded to whole millimetres; more would excuse anything.
pub const COORDINATE_PRECISION: Range = Range {
    what: "a coordinate precision",
    unit: "mm",
    min: 0.0,
    max: 0.5,
};

/// The time a layer-order search takes unless told otherwise (`verify --budget`'s
/// default, and `convert --assign`'s).
pub const DEFAULT_SEARCH_TIME: std::time::Duration = std::time::Duration::from_secs(60);

/// The time a layer-order search may take (`verify --budget`), in seconds.
pub const SEARCH_TIME: Range = Range {
    what: "the layer search's time",
    unit: "s",
    min: 0.1,
    max: 86_400.0,
};

/// The memory the layer-order problem may take (`verify --memory`, and `convert
/// --assign`'s and `fold --flat`'s), in MB: from what a small design needs to 200 GB,
/// below where the problem's 32-bit numbering of its constraints would end (4.3 billion
/// at [`crate::fab::budget::BYTES_PER_CONSTRAINT`] each, 275 GB); the default is
/// [`crate::fab::budget::DEFAULT_LAYER_MEMORY_MB`].
pub const LAYER_MEMORY: Range = Range {
    what: "the layer search's memory",
    unit: "MB",
    min: 10.0,
    max: 2e5,
};

/// The states `verify --count` enumerates in one independent group before it stops
/// (Flat-Folder stops at 10,000).
pub const STATE_CAP: Range = Range {
    what: "the states counted in one group",
    unit: "",
    min: 1.0,
    max: 1e12,
};

/// An SVG opacity (`opacity`, `stroke-opacity`): Origami Simulator draws a crease's
/// fold as a fraction of its full fold by it.
pub const OPACITY: Range = Range {
    what: "an opacity",
    unit: "",
    min: 0.0,
    max: 1.0,
};

/// Most `faceOrders` entries a FOLD file may hold: one per overlapping pair of faces,
/// and the 16 × 16 waterbomb folded flat has 400,000 such pairs of triangles.
pub const MAX_FACE_ORDERS: usize = 2_000_000;

/// Ear clipping's work on one file, as the sum over its polygon faces of their corner
/// counts squared (clipping a face of n corners costs O(n²): 12,000 corners take 2.6 s,
/// 30,000 took 18 s). A crease pattern's faces have tens of corners, a curved strip's
/// a few hundred; 5·10⁷ allows one face of 7,000 corners (under a second), or any
/// number of small ones.
pub const TRIANGULATION_WORK: u64 = 50_000_000;

/// The planar arrangement's work on one drawing (`.cp`, `.svg`, `.opx`, an edges-only
/// FOLD), each of two counts checked before its work is done: the pairs of lines whose
/// x-spans overlap (each tested for a crossing), and the points tested against the
/// lines whose x-spans hold them. About 20 ns apiece with the bookkeeping, so both
/// together stay under half a second. The largest of the 443 anchor files (Flat-Folder's
/// chess26, General Grievous) count 10⁵; 80,000 overlapping lines on one row counted
/// 2·10⁹ (27 s), 3,000 random lines crossing a million times 10⁹ (21 s, 600 MB).
pub const ARRANGEMENT_WORK: u64 = 10_000_000;

/// Lines a drawing may hold before it is arranged: the largest real designs in
/// Flat-Folder's examples have about 10,000; a million tiny lines took 5 s and 630 MB
/// only to be refused by [`ARRANGEMENT_WORK`].
pub const DRAWING_LINES: Range = Range {
    what: "the number of lines",
    unit: "",
    min: 1.0,
    max: 200_000.0,
};

/// Points of a drawing's arrangement (ends of lines and their crossings): the largest
/// anchor designs have about 5,000; 3,000 random lines crossing a million times took
/// 0.8 s and 120 MB only to be refused later by [`ARRANGEMENT_WORK`].
pub const DRAWING_POINTS: usize = 250_000;

/// Largest file crease reads from disk (a pattern, a target, a script, a job, a
/// profile): a binary STL of [`TARGET_TRIANGLES`] is 200 MB. Counted as the bytes are
/// read, not taken from the size a file reports (a FIFO or a device reports none).
pub const MAX_FILE_BYTES: u64 = 256 << 20;

/// Largest file the studio opens, and so the largest request body its HTTP side reads.
pub const MAX_UPLOAD: usize = 64 << 20;

/// Largest request head (request line and headers) the studio reads: a browser's are a
/// kilobyte or two.
pub const HEAD_BYTES: usize = 16 << 10;

/// Most header lines in one request.
pub const MAX_HEADERS: usize = 64;

/// Connections the studio serves at once, each on a thread of its own; past them a
/// connection is answered 503 and closed. A page holds two to six; the cap bounds the
/// threads and their memory whatever a client opens.
pub const MAX_CONNECTIONS: usize = 48;

/// Long-polls for the next frame that wait at once; past them a poll is answered with the
/// current frame straight away, so held polls cannot take every connection.
pub const MAX_WAITING_POLLS: usize = 8;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_print_short_and_read_back_close() {
        for (x, s) in [
            (1e308, "1e308"),
            (12.5, "12.5"),
            (0.001, "0.001"),
            (-3.25e-9, "-3.25e-9"),
            (0.0, "0"),
            (2000.0, "2000"),
            (1e-308, "1e-308"),
            (f64::NAN, "NaN"),
        ] {
            assert_eq!(short(x), s);
        }
        for k in -300..300 {
            let x = 1.2345678 * 10f64.powi(k);
            let s = short(x);
            assert!(s.len() <= 12, "{s}");
            let back: f64 = s.parse().unwrap();
            assert!((back - x).abs() <= 1e-3 * x.abs(), "{x} printed {s}");
        }
    }

    #[test]
    fn a_range_admits_its_ends_and_refuses_past_them_with_a_short_message() {
        assert_eq!(LENGTH.check("--size", 0.01), Ok(0.01));
        assert_eq!(LENGTH.check("--size", 10_000.0), Ok(10_000.0));
        for bad in [1e308, -1.0, 0.0, f64::NAN, f64::INFINITY, 0.009_999] {
            let e = LENGTH.check("--size", bad).unwrap_err().to_string();
            assert!(e.starts_with("--size = "), "{e}");
            assert!(e.contains("from 0.01 to 10000 mm"), "{e}");
            assert!(e.len() < 200, "{e}");
        }
        let e = CELLS.check_count("--nx", u64::MAX).unwrap_err().to_string();
        assert!(e.contains("1.845e19"), "{e}");
    }
}
