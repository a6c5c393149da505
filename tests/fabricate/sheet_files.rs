//! The sheet as other tools read it: DXF through the `dxf` crate, GP-GL and SVG through
//! the tests' own readers, each carrying exactly the toolpath the same way round.

use crate::common;

use common::fabbing::{
    a3, a3_draft, designs_and_anchors, job_pieces, near_pairs, output, output_text, patterns,
    segment_distance,
};
use crease::fab::{verify, Report, Tolerances};
use crease::fab::{LineKind, Stroke};
use crease::machine::Machine;
use crease::mesh::{Mesh, Vec2, Vec3};
use crease::output::hpgl;
use crease::pipeline::{fabricate, fabricate_verified, FabOptions};
use std::path::Path;

#[test]
fn sheet_dxf_read_by_an_independent_parser_carries_exactly_the_toolpath() {
    // The dxf crate (ixmilia) reads sheet.dxf back: one LINE per stroke (a POLYLINE per
    // bent one), on the layer of its operation, ends within a micrometre of the toolpath's (whose y grows upward, as
    // DXF's), in millimetres.
    let machine = Machine::load("generic-hpgl").unwrap();
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &a3_draft()).unwrap();
        let bytes = output(&out, "sheet.dxf");
        let drawing = dxf::Drawing::load(&mut &bytes[..])
            .unwrap_or_else(|e| panic!("{}: sheet.dxf does not parse: {e}", path.display()));
        assert_eq!(drawing.header.version, dxf::enums::AcadVersion::R12);
        let lines: Vec<(String, Vec<Vec2>, bool)> = drawing
            .entities()
            .map(|e| match &e.specific {
                dxf::entities::EntityType::Line(l) => (
                    e.common.layer.clone(),
                    vec![Vec2::new(l.p1.x, l.p1.y), Vec2::new(l.p2.x, l.p2.y)],
                    false,
                ),
                dxf::entities::EntityType::Polyline(p) => (
                    e.common.layer.clone(),
                    p.vertices()
                        .map(|v| Vec2::new(v.location.x, v.location.y))
                        .collect(),
                    true,
                ),
                other => panic!("{}: unexpected entity {other:?}", path.display()),
            })
            .collect();
        let strokes = &out.toolpath.strokes;
        assert_eq!(lines.len(), strokes.len(), "{}", path.display());
        for ((layer, points, polyline), s) in lines.iter().zip(strokes) {
            let expected = match s.kind {
                LineKind::Cut => "CUT",
                LineKind::Mountain => "MOUNTAIN",
                LineKind::Valley => "VALLEY",
                LineKind::Flat => "FLAT",
            };
            assert_eq!(layer, expected);
            // A straight stroke is a LINE between its ends; a bent one a POLYLINE through
            // its chords (whose fidelity to the curve tests/fabricate/scoring.rs measures).
            let want = s.polyline();
            assert_eq!(points.len(), want.len(), "{}", path.display());
            assert_eq!(*polyline, s.bend.is_some());
            for (got, want) in points.iter().zip(&want) {
                assert!(
                    (got - want).abs().max() <= 1e-4,
                    "{}: {got} vs {want}",
                    path.display()
                );
            }
        }
        // Every layer the sheet draws on is declared, with distinct colours, and no other.
        let colours: Vec<_> = drawing.layers().map(|l| l.color.index()).collect();
        let mut unique = colours.clone();
        unique.sort();
        unique.dedup();
        let used: std::collections::BTreeSet<&str> =
            lines.iter().map(|(layer, ..)| layer.as_str()).collect();
        let declared: std::collections::BTreeSet<&str> =
            drawing.layers().map(|l| l.name.as_str()).collect();
        assert_eq!(declared, used, "{}", path.display());
        assert_eq!(unique.len(), colours.len(), "{colours:?}");
    }
}

/// An independent GP-GL reader: the pen-down segments of a job, as (tool holder, from,
/// to) in cutter steps, (feed, carriage) as written.
fn read_gpgl(job: &str) -> Vec<(u32, [i64; 2], [i64; 2])> {
    let body = job
        .strip_prefix("\u{1b}\u{4}")
        .expect("a GP-GL job starts by resetting the cutter (ESC EOT)");
    assert!(body.ends_with('\u{3}'), "every command ends with ETX");
    let numbers = |s: &str| -> Vec<i64> { s.split(',').map(|n| n.parse().unwrap()).collect() };
    let (mut tool, mut at, mut segments) = (0, [0i64, 0], Vec::new());
    for cmd in body.split('\u{3}').filter(|c| !c.is_empty()) {
        assert!(cmd.bytes().all(|b| (0x20..0x7f).contains(&b)), "{cmd:?}");
        if let Some(rest) = cmd.strip_prefix('J') {
            tool = rest.parse().unwrap();
        } else if let Some(rest) = cmd.strip_prefix('M') {
            let p = numbers(rest);
            at = [p[0], p[1]];
        } else if let Some(rest) = cmd.strip_prefix('D') {
            for p in numbers(rest).chunks(2) {
                segments.push((tool, at, [p[0], p[1]]));
                at = [p[0], p[1]];
            }
        }
    }
    segments
}

#[test]
fn sheet_gpgl_read_by_an_independent_reader_carries_exactly_the_toolpath() {
    // Graphtec profile: 20 steps per mm, media feed (the sheet's y) first. Every stroke
    // of the toolpath (every chord of a bent one) is one cut segment with the kind's tool
    // holder, its ends on the nearest step to the stroke's.
    let machine = Machine::load("graphtec-ce").unwrap();
    let units = machine.units_per_mm;
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &a3_draft()).unwrap();
        assert!(!out.files.iter().any(|f| f.0 == "sheet.hpgl"));
        let job = output_text(&out, "sheet.gpgl");
        let segments = read_gpgl(job);
        // The cutter's origin is the media's top-left corner; the toolpath's y grows up.
        let h = out.toolpath.media.height;
        let step = |p: Vec2| {
            [
                ((h - p.y) * units).round() as i64,
                (p.x * units).round() as i64,
            ]
        };
        let pieces = job_pieces(&out.toolpath.strokes, step);
        let strokes: Vec<&Stroke> = pieces.iter().map(|(s, _)| s).collect();
        assert_eq!(segments.len(), strokes.len(), "{}", path.display());
        for ((tool, from, to), s) in segments.iter().zip(&strokes) {
            assert_eq!(*tool, machine.tools[&s.kind].pen);
            for (got, want) in [(from, s.from), (to, s.to)] {
                let want = [(h - want.y) * units, want.x * units];
                assert!(
                    (got[0] as f64 - want[0]).abs() <= 0.5
                        && (got[1] as f64 - want[1]).abs() <= 0.5,
                    "{}: {got:?} vs {want:?}",
                    path.display()
                );
            }
        }
    }
    // Carriage first (as inkcut sends): the same job with each pair swapped.
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/graphtec-ce.toml"),
    )
    .unwrap()
    .replace(
        "axis_order = \"feed-first\"",
        "axis_order = \"carriage-first\"",
    );
    let swapped = Machine::parse(&text).unwrap();
    let mesh = crease::io::read(&patterns()[0]).unwrap();
    let read = |m: &Machine| {
        let out = fabricate(&mesh, m, &a3()).unwrap();
        read_gpgl(output_text(&out, "sheet.gpgl"))
    };
    let flipped: Vec<_> = read(&swapped)
        .into_iter()
        .map(|(t, a, b)| (t, [a[1], a[0]], [b[1], b[0]]))
        .collect();
    assert_eq!(flipped, read(&machine));
}

#[test]
fn a_laser_profile_gets_dxf_and_svg_and_no_cutter_job() {
    let machine = Machine::load("laser-dxf").unwrap();
    let mesh = crease::io::read(&patterns()[0]).unwrap();
    let out = fabricate(&mesh, &machine, &a3_draft()).unwrap();
    let names: Vec<&str> = out.files.iter().map(|f| f.0.as_str()).collect();
    assert!(
        names.contains(&"sheet.dxf") && names.contains(&"sheet.svg"),
        "{names:?}"
    );
    assert!(
        !names
            .iter()
            .any(|n| n.ends_with(".hpgl") || n.ends_with(".gpgl")),
        "{names:?}"
    );
    assert_eq!(out.report.sheet.job_files, Some(Vec::new()));
    assert!(out.report.sheet.plotter.is_none());
}

#[test]
fn every_output_shows_the_sheet_the_same_way_round() {
    // A mirrored file folds into the mirror image of the design. Seen from above with
    // the origin at the media's top-left corner: sheet.svg as drawn (y down), sheet.dxf
    // and sheet.hpgl with y up from the lower edge, sheet.gpgl feed-first from the top.
    // The bird base is laid out asymmetrically enough (its kite lines) that a flip of any
    // one file changes its set of segments.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bird = crease::io::read(&root.join("patterns/bird-base.fold")).unwrap();
    let hpgl_machine = Machine::load("generic-hpgl").unwrap();
    let out = fabricate(&bird, &hpgl_machine, &a3()).unwrap();
    let h = out.toolpath.media.height;
    // The SVG's lines, as drawn.
    let svg = output_text(&out, "sheet.svg");
    let from_svg: Vec<Segment> = svg_segments(svg)
        .into_iter()
        .map(|(_, a, b, _)| (a, b))
        .collect();
    // The DXF, turned to y down.
    let from_dxf = dxf_lines_y_down(output_text(&out, "sheet.dxf"), h);
    // The HP-GL as the plotter draws it.
    let u = hpgl_machine.units_per_mm;
    let drawn = hpgl::interpret(output_text(&out, "sheet.hpgl"))
        .unwrap()
        .segments;
    let from_hpgl: Vec<Segment> = drawn
        .iter()
        .map(|(_, a, b)| {
            let p = |q: [i64; 2]| [q[0] as f64 / u, h - q[1] as f64 / u];
            (p(*a), p(*b))
        })
        .collect();
    // The GP-GL from the top-left origin, feed (down) first.
    let gpgl_machine = Machine::load("graphtec-ce").unwrap();
    let g = fabricate(&bird, &gpgl_machine, &a3()).unwrap();
    let gu = gpgl_machine.units_per_mm;
    let from_gpgl: Vec<Segment> = read_gpgl(output_text(&g, "sheet.gpgl"))
        .into_iter()
        .map(|(_, a, b)| {
            let p = |q: [i64; 2]| [q[1] as f64 / gu, q[0] as f64 / gu];
            (p(a), p(b))
        })
        .collect();
    // Each segment of `other` lies on one of sheet.svg's, ends within 0.1 mm (the
    // cutters' steps are 0.025–0.05 mm), and the counts agree.
    let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) < 0.1;
    let same = |s: &Segment, t: &Segment| {
        (near(s.0, t.0) && near(s.1, t.1)) || (near(s.0, t.1) && near(s.1, t.0))
    };
    let matched = |other: &[Segment]| {
        other
            .iter()
            .filter(|s| from_svg.iter().any(|t| same(s, t)))
            .count()
    };
    let mirrored: Vec<Segment> = from_svg
        .iter()
        .map(|&(p, q)| ([p[0], 2.0 * h - p[1] - h], [q[0], 2.0 * h - q[1] - h]))
        .collect();
    assert!(
        (matched(&mirrored) as f64) < 0.9 * from_svg.len() as f64,
        "the test pattern must not be its own mirror image"
    );
    let agree = |name: &str, other: &Vec<Segment>| {
        assert_eq!(other.len(), from_svg.len(), "{name}");
        assert_eq!(
            matched(other),
            other.len(),
            "{name}: segments off sheet.svg's"
        );
    };
    agree("sheet.dxf", &from_dxf);
    agree("sheet.hpgl", &from_hpgl);
    agree("sheet.gpgl", &from_gpgl);
}

/// A line segment on the sheet, in mm from its top-left corner, y down.
type Segment = ([f64; 2], [f64; 2]);

/// A DXF's LINE entities, turned from y up to y down on a sheet `h` mm high.
fn dxf_lines_y_down(dxf: &str, h: f64) -> Vec<Segment> {
    let drawing = dxf::Drawing::load(&mut dxf.as_bytes()).unwrap();
    drawing
        .entities()
        .filter_map(|e| match &e.specific {
            dxf::entities::EntityType::Line(l) => {
                Some(([l.p1.x, h - l.p1.y], [l.p2.x, h - l.p2.y]))
            }
            _ => None,
        })
        .collect()
}

/// A sheet.svg path's segment: (layer, from, to, a cubic's two control points if it is one).
type SvgSegment = (String, [f64; 2], [f64; 2], Option<[[f64; 2]; 2]>);

/// The segments of a sheet.svg's paths as drawn (y down), closing segments of `Z`
/// included.
fn svg_segments(svg: &str) -> Vec<SvgSegment> {
    let mut out = Vec::new();
    for layer in svg.split("<g ").skip(1) {
        let name = layer
            .split("id=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        for path in layer.split("<path d=\"").skip(1) {
            let d = path.split('"').next().unwrap();
            let mut tokens = d.split_whitespace();
            let (mut at, mut start) = ([0.0f64; 2], [0.0f64; 2]);
            while let Some(t) = tokens.next() {
                let (op, x) = t.split_at(1);
                if op == "Z" {
                    // A close after a curve that already came back draws nothing.
                    if (at[0] - start[0]).hypot(at[1] - start[1]) > 1e-9 {
                        out.push((name.to_string(), at, start, None));
                    }
                    at = start;
                    continue;
                }
                let mut numbers = std::iter::once(x).chain(tokens.by_ref());
                let mut next = || -> [f64; 2] {
                    let mut n = || numbers.next().unwrap().parse::<f64>().unwrap();
                    [n(), n()]
                };
                let p = next();
                let p = match op {
                    "M" => {
                        start = p;
                        p
                    }
                    "L" => {
                        out.push((name.to_string(), at, p, None));
                        p
                    }
                    "C" => {
                        let (c2, end) = (next(), next());
                        out.push((name.to_string(), at, end, Some([p, c2])));
                        end
                    }
                    other => panic!("unexpected path command {other}"),
                };
                at = p;
            }
        }
    }
    out
}

#[test]
fn sheet_svg_holds_only_what_is_cut_or_scored_one_path_per_line() {
    // What cutter and laser software take: no media frame, hairlines, one colour per
    // layer; the outline one closed path; each crease's dashes one path element; and,
    // segment by segment, exactly the toolpath.
    let machine = Machine::load("generic-hpgl").unwrap();
    for path in patterns() {
        let mesh = crease::io::read(&path).unwrap();
        let out = fabricate(&mesh, &machine, &a3_draft()).unwrap();
        let svg = output_text(&out, "sheet.svg");
        let name = path.display();
        assert!(!svg.contains("<rect") && !svg.contains("<line"), "{name}");
        // Every layer drawn in hairlines.
        assert_eq!(
            svg.matches("stroke-width=\"0.0254\"").count(),
            svg.matches("<g ").count(),
            "{name}"
        );
        let strokes = &out.toolpath.strokes;
        for kind in [LineKind::Cut, LineKind::Mountain, LineKind::Valley] {
            let layer = svg.split(&format!("id=\"{}\"", kind.name())).nth(1);
            let ours: Vec<_> = strokes.iter().filter(|s| s.kind == kind).collect();
            let Some(layer) = layer else {
                assert!(ours.is_empty(), "{name}: no {} layer", kind.name());
                continue;
            };
            let layer = layer.split("</g>").next().unwrap();
            let paths = layer.matches("<path").count();
            if kind == LineKind::Cut {
                assert_eq!(paths, 1, "{name}: the outline is one path");
                let d = layer
                    .split("d=\"")
                    .nth(1)
                    .unwrap()
                    .split('"')
                    .next()
                    .unwrap();
                assert_eq!(
                    d.matches('M').count(),
                    d.matches('Z').count(),
                    "{name}: every loop of the outline is closed"
                );
            } else {
                let mut lines: Vec<usize> = ours.iter().map(|s| s.line).collect();
                lines.sort_unstable();
                lines.dedup();
                assert_eq!(
                    paths,
                    lines.len(),
                    "{name}: one path per {} crease",
                    kind.name()
                );
            }
        }
        // Segment by segment the toolpath (the SVG's y runs down the sheet).
        let h = out.toolpath.media.height;
        let drawn = svg_segments(svg);
        assert_eq!(drawn.len(), strokes.len(), "{name}");
        let near = |a: [f64; 2], b: Vec2| (a[0] - b.x).hypot(a[1] - (h - b.y)) < 1e-3;
        // A bent stroke is a cubic with its control points, either way round.
        let controls = |c: &Option<[[f64; 2]; 2]>, s: &Stroke| match (c, s.bend) {
            (None, None) => true,
            (Some([c1, c2]), Some([b1, b2])) => {
                (near(*c1, b1) && near(*c2, b2)) || (near(*c1, b2) && near(*c2, b1))
            }
            _ => false,
        };
        for s in strokes {
            assert!(
                drawn.iter().any(|(layer, a, b, c)| layer == s.kind.name()
                    && controls(c, s)
                    && ((near(*a, s.from) && near(*b, s.to))
                        || (near(*a, s.to) && near(*b, s.from)))),
                "{name}: stroke {s:?} missing from sheet.svg"
            );
        }
    }
}

/// What a cutter receives, read back by the tests' own readers: pen-down segments in
/// steps, as written, and every tool-setting command that changed nothing.
struct Job {
    segments: Vec<([i64; 2], [i64; 2])>,
    settings_sent: usize,
    redundant: Vec<String>,
}

/// Tracks tool-setting commands: each must change the value it sets.
#[derive(Default)]
struct Settings(
    std::collections::HashMap<String, String>,
    usize,
    Vec<String>,
);

impl Settings {
    fn set(&mut self, name: &str, value: &str) {
        self.1 += 1;
        if self.0.insert(name.into(), value.into()).as_deref() == Some(value) {
            self.2.push(format!("{name}{value}"));
        }
    }
}

/// An HP-GL/1 reader for what crease writes: `IN`, `PA`/`PR`, `PU`/`PD` with coordinate
/// lists, `SP`, `VS`, `FS`.
fn read_hpgl(job: &str) -> Job {
    let (mut at, mut relative, mut segments) = ([0i64, 0], false, Vec::new());
    let mut settings = Settings::default();
    for cmd in job.split(';').map(str::trim).filter(|c| !c.is_empty()) {
        let (name, args) = cmd.split_at(2);
        let numbers: Vec<i64> = args
            .split(',')
            .filter(|n| !n.is_empty())
            .map(|n| n.parse().unwrap())
            .collect();
        match name {
            "IN" => (at, relative) = ([0, 0], false),
            "PA" => relative = false,
            "PR" => relative = true,
            "PU" | "PD" => {
                for p in numbers.chunks(2) {
                    let next = if relative {
                        [at[0] + p[0], at[1] + p[1]]
                    } else {
                        [p[0], p[1]]
                    };
                    if name == "PD" {
                        segments.push((at, next));
                    }
                    at = next;
                }
            }
            "SP" | "VS" | "FS" => settings.set(name, args),
            other => panic!("unexpected HP-GL command {other} in {cmd:?}"),
        }
    }
    let Settings(_, settings_sent, redundant) = settings;
    Job {
        segments,
        settings_sent,
        redundant,
    }
}

/// A GP-GL reader (independent of the crate's interpreter): `M`/`D` absolute, `J`, `!`,
/// `FX` and `FC` set the tool.
fn read_gpgl_job(job: &str) -> Job {
    let body = job.strip_prefix("\u{1b}\u{4}").expect("ESC EOT first");
    let mut settings = Settings::default();
    let (mut at, mut segments) = ([0i64, 0], Vec::new());
    let numbers = |s: &str| -> Vec<i64> { s.split(',').map(|n| n.parse().unwrap()).collect() };
    for cmd in body.split('\u{3}').filter(|c| !c.is_empty()) {
        if let Some(name) = ["FX", "FC", "J", "!"]
            .into_iter()
            .find(|n| cmd.starts_with(n))
        {
            settings.set(name, &cmd[name.len()..]);
        } else if let Some(rest) = cmd.strip_prefix('M') {
            let p = numbers(rest);
            at = [p[0], p[1]];
        } else if let Some(rest) = cmd.strip_prefix('D') {
            for p in numbers(rest).chunks(2) {
                segments.push((at, [p[0], p[1]]));
                at = [p[0], p[1]];
            }
        }
    }
    let Settings(_, settings_sent, redundant) = settings;
    Job {
        segments,
        settings_sent,
        redundant,
    }
}

/// A PNG read back by the `png` crate: (width, height, RGB pixels).
fn read_png(bytes: &[u8]) -> (u32, u32, Vec<[u8; 3]>) {
    let mut decoder = png::Decoder::new(bytes);
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder.read_info().unwrap();
    let mut buffer = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buffer).unwrap();
    let channels = info.color_type.samples();
    let pixels = buffer[..info.buffer_size()]
        .chunks(channels)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    (info.width, info.height, pixels)
}

/// sheet.png and design.png of one run: the sheet picture is the media at the report's
/// scale, and each operation's colour (docs/guide.md's: cut black, mountain red, valley
/// blue) covers what its strokes do at the stated width; the design picture is its
/// stated size and shows paper and, where the design has them, red and blue creases.
fn check_previews(out: &crease::pipeline::FabOutput, mesh: &Mesh, what: &str) {
    let previews = &out.report.previews;
    let scale = previews.sheet.px_per_mm;
    let width = previews.sheet.stroke_px;
    let (w, h, pixels) = read_png(output(out, "sheet.png"));
    let media = &out.toolpath.media;
    assert_eq!(
        (w, h),
        (
            (media.width * scale).ceil() as u32,
            (media.height * scale).ceil() as u32
        ),
        "{what}: sheet.png"
    );
    for (kind, colour) in [
        (LineKind::Cut, [0, 0, 0]),
        (LineKind::Mountain, [255, 0, 0]),
        (LineKind::Valley, [0, 0, 255]),
    ] {
        // A slit's two sides are one line on the sheet: counted once.
        let mut seen = std::collections::HashSet::new();
        let length: f64 = out
            .toolpath
            .strokes
            .iter()
            .filter(|s| s.kind == kind)
            .filter(|s| {
                let key = |p: Vec2| [(p.x * 1e4).round() as i64, (p.y * 1e4).round() as i64];
                let (a, b) = (key(s.from), key(s.to));
                seen.insert(if a < b { (a, b) } else { (b, a) })
            })
            .map(|s| s.length())
            .sum();
        let expected = length * scale * width;
        let counted = pixels.iter().filter(|&&p| p == colour).count() as f64;
        // Rasterising a short dash can gain or lose a pixel row at either end: 20% on
        // the few-pixel sheets, far less on the large ones.
        assert!(
            expected < 30.0 || (counted / expected - 1.0).abs() <= 0.2,
            "{what}: sheet.png has {counted} px of {} where its strokes cover {expected:.0}",
            kind.name()
        );
    }
    let (w, h, pixels) = read_png(output(out, "design.png"));
    assert_eq!([w, h], previews.design.size_px, "{what}: design.png");
    let background = pixels[0];
    let paper = pixels.iter().filter(|&&p| p != background).count();
    assert!(
        paper as f64 > 0.1 * f64::from(w * h),
        "{what}: design.png shows {paper} px of paper"
    );
    let has = |a| mesh.edges().iter().any(|e| e.assignment == a);
    let reddish = |p: &[u8; 3]| p[0] > 200 && p[1] < 80 && p[2] < 80;
    let bluish = |p: &[u8; 3]| p[2] > 200 && p[0] < 80 && p[1] < 80;
    if has(crease::mesh::Assignment::Mountain) {
        assert!(
            pixels.iter().any(reddish),
            "{what}: no mountain in design.png"
        );
    }
    if has(crease::mesh::Assignment::Valley) {
        assert!(pixels.iter().any(bluish), "{what}: no valley in design.png");
    }
}

/// The cutter profiles (those that write a job for the machine).
fn cutter_profiles() -> Vec<Machine> {
    let profiles: Vec<Machine> = crease::machine::known_machines()
        .iter()
        .map(|name| Machine::load(name).unwrap())
        .filter(|m| m.protocol.is_cutter_job())
        .collect();
    assert!(profiles.len() >= 5, "{} cutter profiles", profiles.len());
    profiles
}

/// Checks one design's job on one machine; returns (closed cut runs, short mountain marks).
fn check_job(
    path: &Path,
    design: &(Mesh, Report),
    machine: &Machine,
) -> (usize, usize, Vec<String>) {
    // Every fault of a job is listed, not only the first.
    let mut problems: Vec<String> = Vec::new();
    macro_rules! check {
        ($ok:expr, $($message:tt)+) => {{
            let ok: bool = $ok;
            if !ok && problems.len() < 10 {
                problems.push(format!($($message)+));
            }
        }};
    }
    use crease::fab::toolpath::DISTINCT_MM;
    let (mesh, verification) = design;
    // At the machine's own media, as a maker runs it; scaled to fit where the design is
    // larger. Cut even where verification objects: the job is what is measured here.
    // The full route search on one profile of each protocol (the job a maker cuts by
    // default); the draft route on the others, whose writers quantise the same strokes.
    let route = if matches!(machine.name.as_str(), n if n.starts_with("Generic HP-GL") || n.contains("Cameo"))
    {
        crease::fab::RouteSearch::Full
    } else {
        crease::fab::RouteSearch::Draft
    };
    let run = |fit| {
        let options = FabOptions {
            force: true,
            fit,
            route,
            // The job is what is measured; the folding guide has its own test.
            guide: crease::pipeline::Guide::Never,
            ..Default::default()
        };
        fabricate_verified(mesh, verification.clone(), machine, &options)
    };
    let out = run(false)
        .or_else(|_| run(true))
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let what = format!("{} on {}", path.display(), machine.name);
    if machine.name.starts_with("Generic HP-GL") {
        check_previews(&out, mesh, &what);
    }
    let u = machine.units_per_mm;
    let gpgl = machine.protocol == crease::machine::Protocol::Gpgl;
    let job = if gpgl {
        read_gpgl_job(output_text(&out, "sheet.gpgl"))
    } else {
        read_hpgl(output_text(&out, "sheet.hpgl"))
    };
    check!(
        job.redundant.is_empty(),
        "{what}: {:?} set nothing new",
        job.redundant
    );
    check!(job.settings_sent >= 2, "{what}: no tool set");
    // The toolpath in the job's steps, exact (GP-GL: feed down the sheet first).
    let h = out.toolpath.media.height;
    let exact = |p: Vec2| {
        if gpgl {
            [(h - p.y) * u, p.x * u]
        } else {
            [p.x * u, p.y * u]
        }
    };
    let nearest = |p: Vec2| exact(p).map(|v| v.round() as i64);
    // Each stroke as the segments the writer sends: itself, or a bent stroke's chords;
    // those shorter than a step go. Each remembers its stroke.
    let pieces = job_pieces(&out.toolpath.strokes, nearest);
    let strokes: Vec<&Stroke> = pieces.iter().map(|(s, _)| s).collect();
    assert_eq!(job.segments.len(), strokes.len(), "{what}");
    // Every end within half a step of the toolpath's, on each axis.
    for ((from, to), s) in job.segments.iter().zip(&strokes) {
        for (got, want) in [(from, exact(s.from)), (to, exact(s.to))] {
            check!(
                (0..2).all(|i| (got[i] as f64 - want[i]).abs() <= 0.5 + 1e-9),
                "{what}: {got:?} vs {want:?}"
            );
        }
    }
    // Every run the toolpath closes (an outline, a hole) closes exactly on the grid: the
    // job's run ends on the very step it started from. A run is a stretch of cut strokes
    // each starting where the one before ended.
    let mut runs: Vec<(Vec2, Vec2, [i64; 2], [i64; 2])> = Vec::new();
    for ((from, to), s) in job.segments.iter().zip(&strokes) {
        if s.kind != LineKind::Cut {
            continue;
        }
        match runs.last_mut() {
            Some(run) if (run.1 - s.from).norm() < 1e-9 => (run.1, run.3) = (s.to, *to),
            _ => runs.push((s.from, s.to, *from, *to)),
        }
    }
    let closed: Vec<_> = runs.iter().filter(|r| (r.0 - r.1).norm() < 1e-9).collect();
    for run in &closed {
        check!(
            run.2 == run.3,
            "{what}: a closed outline starts at {:?} and ends at {:?}",
            run.2,
            run.3
        );
    }
    // Nothing is cut twice (a kirigami slit's two sides are one line of the sheet).
    let mut cut_once = std::collections::HashSet::new();
    for ((from, to), s) in job.segments.iter().zip(&strokes) {
        let twice = !cut_once.insert(if from < to { (from, to) } else { (to, from) });
        check!(
            !twice || s.kind != LineKind::Cut,
            "{what}: {from:?}-{to:?} is cut twice"
        );
    }
    // The job's segments in millimetres on the sheet, with the line each cuts or scores.
    let to_mm = |p: [i64; 2]| {
        if gpgl {
            Vec2::new(p[1] as f64 / u, h - p[0] as f64 / u)
        } else {
            Vec2::new(p[0] as f64 / u, p[1] as f64 / u)
        }
    };
    // Each stroke as cut: from where its first segment starts to where its last ends
    // (a bent one keeps its curve between).
    let mut cut_job: Vec<Stroke> = Vec::new();
    let mut of_stroke: Option<usize> = None;
    for ((a, b), (_, k)) in job.segments.iter().zip(&pieces) {
        if of_stroke == Some(*k) {
            let last = cut_job.len() - 1;
            cut_job[last].to = to_mm(*b);
        } else {
            cut_job.push(Stroke {
                from: to_mm(*a),
                to: to_mm(*b),
                ..out.toolpath.strokes[*k]
            });
            of_stroke = Some(*k);
        }
    }
    let settings = machine.score_settings();
    let dashed = |s: &Stroke| matches!(settings.codes.get(&s.kind), Some(Some(_)));
    // No dash within the clearance of the cut, a solid line or another crease's dash.
    for (i, j) in near_pairs(&cut_job, machine.clearance_mm) {
        let (a, b) = (&cut_job[i], &cut_job[j]);
        {
            if a.line == b.line || !(dashed(a) || dashed(b)) {
                continue;
            }
            let d = segment_distance(a, b);
            check!(
                d >= machine.clearance_mm - 1e-9,
                "{what}: a {} dash of line {} passes {d:.3} mm from a {} stroke of line {}",
                a.kind.name(),
                a.line,
                b.kind.name(),
                b.line
            );
        }
    }
    // Mountains told from valleys by the documented rule (docs/guide.md), on the lengths the cutter cuts; a
    // pen plotter draws them solid, in pens of their own.
    let Some(Some(valley)) = settings.codes.get(&LineKind::Valley) else {
        assert_ne!(
            machine.tools[&LineKind::Mountain].pen,
            machine.tools[&LineKind::Valley].pen,
            "{what}"
        );
        return (closed.len(), 0, problems);
    };
    let valley = valley.cut;
    let slack = std::f64::consts::SQRT_2 / u;
    let in_pair = |s: &Stroke| {
        s.length() < valley / 2.0
            && cut_job.iter().any(|o| {
                o != s
                    && o.line == s.line
                    && o.length() < valley / 2.0
                    && [o.from, o.to].iter().any(|p| {
                        (p - s.from).norm().min((p - s.to).norm())
                            <= s.length().max(o.length()) + slack
                    })
            })
    };
    let mut short = 0;
    for s in &cut_job {
        match s.kind {
            LineKind::Mountain => {
                let long = s.length() >= valley + DISTINCT_MM - slack;
                short += usize::from(!long);
                check!(
                    long || in_pair(s),
                    "{what}: a {:.3} mm mountain dash of line {} reads as a valley",
                    s.length(),
                    s.line
                );
            }
            LineKind::Valley => check!(
                s.length() <= valley + slack && !in_pair(s),
                "{what}: a {:.3} mm valley dash of line {} reads as a mountain",
                s.length(),
                s.line
            ),
            _ => {}
        }
    }
    (closed.len(), short, problems)
}

#[test]
fn every_cutter_job_read_back_closes_keeps_ends_and_clearance_and_tells_mountains_from_valleys() {
    // Read back independently, the GP-GL jobs put dash ends up to 0.07 mm off, left the
    // outline open by a step on 7 of 19 designs, came 0.910 mm (GP-GL) and 0.971 mm (HP-GL)
    // close where the clearance is 1 mm, scored a miura-bent mountain as one 0.516 mm dash
    // and sent the tool settings at every change of line kind.
    let designs = designs_and_anchors();
    let profiles = cutter_profiles();
    let (closed_outlines, short_marks, problems) = std::thread::scope(|scope| {
        let halves: Vec<_> = designs
            .chunks(designs.len().div_ceil(2))
            .map(|part| {
                let profiles = &profiles;
                scope.spawn(move || {
                    let mut totals = (0, 0, Vec::new());
                    for path in part {
                        let mesh = crease::io::read(path).unwrap();
                        let verification = verify(&mesh, None, Tolerances::default());
                        let design = (mesh, verification);
                        for machine in profiles {
                            let (o, s, problems) = check_job(path, &design, machine);
                            totals.0 += o;
                            totals.1 += s;
                            totals.2.extend(problems);
                        }
                    }
                    totals
                })
            })
            .collect();
        halves
            .into_iter()
            .map(|h| h.join().unwrap())
            .fold((0, 0, Vec::new()), |mut a, b| {
                a.2.extend(b.2);
                (a.0 + b.0, a.1 + b.1, a.2)
            })
    });
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(closed_outlines > 100, "{closed_outlines} closed outlines");
    assert!(
        short_marks > 0,
        "no short mountain mark: the rule is not exercised"
    );
}

/// The colour CAD and laser software shows for an AutoCAD colour index (the standard
/// palette's first entries; 7 is drawn black on a light background).
fn aci_rgb(index: u8) -> [u8; 3] {
    match index {
        1 => [255, 0, 0],
        2 => [255, 255, 0],
        3 => [0, 255, 0],
        4 => [0, 255, 255],
        5 => [0, 0, 255],
        6 => [255, 0, 255],
        7 => [0, 0, 0],
        8 => [128, 128, 128],
        9 => [192, 192, 192],
        other => panic!("colour index {other} is not one an operation should have"),
    }
}

#[test]
fn every_file_gives_each_operation_the_same_colour_and_name() {
    // DXF layers were CUT red, MOUNTAIN blue, VALLEY green, while SVG and PDF drew cut
    // black, mountain red, valley blue: a laser user mapping by colour cut the mountains.
    // Read back: the SVG's layers (an XML reader), the DXF's (the dxf crate) and the
    // PDF's stroke colours (printpdf's parser) agree, kind by kind.
    let machine = Machine::load("generic-hpgl").unwrap();
    let mesh = crease::io::read(&patterns()[0].with_file_name("miura-bent.fold")).unwrap();
    let mut options = a3();
    options.fit = true;
    let out = fabricate(&mesh, &machine, &options).unwrap();
    let kinds: std::collections::BTreeSet<LineKind> =
        out.toolpath.strokes.iter().map(|s| s.kind).collect();
    assert!(kinds.len() >= 3, "{kinds:?}");
    let hex = |[r, g, b]: [u8; 3]| format!("#{r:02x}{g:02x}{b:02x}");
    // SVG: one layer per kind, labelled with its name, stroked in its colour.
    let svg = output_text(&out, "sheet.svg");
    let mut svg_layers = std::collections::BTreeMap::new();
    for event in svg::read(svg).unwrap() {
        if let svg::parser::Event::Tag("g", svg::node::element::tag::Type::Start, a) = event {
            let label = a.get("inkscape:label").map(|v| v.to_string()).unwrap();
            svg_layers.insert(label, a.get("stroke").map(|v| v.to_string()).unwrap());
        }
    }
    // DXF: the layer of that name, in its colour index.
    let drawing = dxf::Drawing::load(&mut output(&out, "sheet.dxf")).unwrap();
    let dxf_layers: std::collections::BTreeMap<String, u8> = drawing
        .layers()
        .map(|l| (l.name.to_lowercase(), l.color.index().unwrap()))
        .collect();
    assert_eq!(svg_layers.len(), kinds.len(), "{svg_layers:?}");
    assert_eq!(dxf_layers.len(), kinds.len(), "{dxf_layers:?}");
    // PDF: every colour a line is stroked in on the sheet's page.
    let pdf = printpdf::PdfDocument::parse(
        output(&out, "sheet.pdf"),
        &Default::default(),
        &mut Vec::new(),
    )
    .unwrap();
    let mut pdf_colours = std::collections::BTreeSet::new();
    for op in &pdf.pages[0].ops {
        if let printpdf::Op::SetOutlineColor {
            col: printpdf::Color::Rgb(c),
        } = op
        {
            let byte = |v: f32| (v * 255.0).round() as u8;
            pdf_colours.insert(hex([byte(c.r), byte(c.g), byte(c.b)]));
        }
    }
    // The legend names every kind of line the page draws (flat lines were drawn, unnamed).
    let texts = common::fabbing::pdf_texts(&pdf.pages[0]);
    let drawn: std::collections::BTreeSet<LineKind> =
        out.sheet.lines.iter().map(|l| l.kind).collect();
    assert!(drawn.contains(&LineKind::Flat), "miura-bent has flat lines");
    for kind in &drawn {
        assert!(
            texts.iter().any(|t| t == kind.name()),
            "the legend does not name {} lines: {texts:?}",
            kind.name()
        );
    }
    for kind in kinds {
        let svg_colour = &svg_layers[kind.name()];
        let dxf_colour = hex(aci_rgb(dxf_layers[kind.name()]));
        assert_eq!(svg_colour, &dxf_colour, "{}: SVG vs DXF", kind.name());
        assert!(
            pdf_colours.contains(svg_colour),
            "{}: {svg_colour} is not among the PDF's {pdf_colours:?}",
            kind.name()
        );
    }
}

#[test]
fn design_png_shows_a_flat_sheet_at_its_projected_area() {
    // A flat 4 × 4-cell plane of 20 mm cells in the xy-plane, seen orthographically from
    // the unit view v, covers its area × |v_z| × (px per mm)² pixels: the closed form the
    // painted picture must match (edges anti-aliased: within 1%).
    use crease::generate::{generate, Params, PatternKind};
    use crease::output::png;
    let mut params = Params::square(PatternKind::Plane, 4, 20.0);
    params.fold = Some(0.0);
    let mut mesh = generate(&params).unwrap();
    let flat: Vec<_> = mesh
        .positions()
        .iter()
        .map(|p| Vec3::new(p.x, p.y, 0.0))
        .collect();
    mesh.set_positions(flat);
    let area: f64 = mesh
        .faces()
        .iter()
        .map(|&[a, b, c]| {
            let x = mesh.positions();
            (x[b] - x[a]).cross(&(x[c] - x[a])).norm() / 2.0
        })
        .sum();
    assert!(area > 1000.0, "{area}");
    let camera = png::DesignCamera::framing(mesh.positions());
    let expected = area * png::design_view().z.abs() * camera.px_per_mm.powi(2);
    let (w, h, pixels) = read_png(&png::design(&mesh).unwrap());
    assert_eq!([w, h], png::DESIGN_SIZE_PX);
    let paper = pixels
        .iter()
        .filter(|&&p| p != png::DESIGN_BACKGROUND)
        .count() as f64;
    assert!(
        (paper / expected - 1.0).abs() < 0.01,
        "{paper} px of paper, {expected:.0} expected"
    );
}

#[test]
fn a_cricut_job_is_an_svg_with_a_cut_layer_and_a_score_layer_of_continuous_lines() {
    // Cricut Design Space scores with a wheel or stylus drawing a line: every mountain and
    // valley of miura-bent must be in the Score layer once, as one unbroken line from end
    // to end, the outline in the Cut layer, all on the 12 × 12 in mat inside its quarter
    // inch; read back with the svg crate's parser.
    let machine = Machine::load("cricut-maker").unwrap();
    assert_eq!(machine.protocol, crease::machine::Protocol::Svg);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura-bent.fold");
    let mesh = crease::io::read(&path).unwrap();
    let out = fabricate(&mesh, &machine, &FabOptions::default()).unwrap();
    assert!(
        !out.files
            .iter()
            .any(|f| f.0.ends_with(".hpgl") || f.0.ends_with(".gpgl")),
        "no cutter job: Design Space takes the SVG"
    );
    let next = out.next_steps.as_ref().expect("the steps for Design Space");
    assert_eq!(next.software, "Cricut Design Space");
    assert!(next.steps.iter().any(|s| s.contains("Score")));
    let svg = output_text(&out, "sheet.svg");
    let mat = 12.0 * 25.4;
    let inside = 0.25 * 25.4 - 1e-6;
    // (layer, kind class, points of one path), y turned up as the sheet's.
    let mut layer = String::new();
    let mut paths: Vec<(String, String, Vec<Vec2>)> = Vec::new();
    for event in svg::read(svg).unwrap() {
        use svg::node::element::tag::Type;
        use svg::parser::Event;
        match event {
            Event::Tag("svg", Type::Start, a) => {
                assert_eq!(a.get("width").unwrap().to_string(), "304.8mm");
                assert_eq!(a.get("height").unwrap().to_string(), "304.8mm");
            }
            Event::Tag("g", Type::Start, a) => {
                layer = a.get("inkscape:label").unwrap().to_string();
            }
            Event::Tag("path", _, a) => {
                let data = svg::node::element::path::Data::parse(&a.get("d").unwrap().to_string())
                    .unwrap();
                let mut points = Vec::new();
                for command in data.iter() {
                    use svg::node::element::path::{Command, Position};
                    match command {
                        Command::Move(Position::Absolute, p) => {
                            assert!(points.is_empty(), "{layer}: a path with a gap");
                            points.push(Vec2::new(p[0] as f64, mat - p[1] as f64));
                        }
                        Command::Line(Position::Absolute, p) => {
                            points.push(Vec2::new(p[0] as f64, mat - p[1] as f64))
                        }
                        Command::Close => points.push(points[0]),
                        other => panic!("unexpected {other:?}"),
                    }
                }
                let class = a.get("class").map(|c| c.to_string()).unwrap_or_default();
                paths.push((layer.clone(), class, points));
            }
            _ => {}
        }
    }
    let layers: std::collections::BTreeSet<&str> = paths.iter().map(|p| p.0.as_str()).collect();
    assert_eq!(layers, ["Cut", "Score"].into_iter().collect());
    for (_, _, points) in &paths {
        for p in points {
            assert!(
                p.x >= inside && p.y >= inside && p.x <= mat - inside && p.y <= mat - inside,
                "{p:?} is off the mat's cutting area"
            );
        }
    }
    // Every scored crease once: one straight path from one end of its line to the other.
    let creases: Vec<_> = out
        .sheet
        .lines
        .iter()
        .filter(|l| matches!(l.kind, LineKind::Mountain | LineKind::Valley))
        .collect();
    let scores: Vec<_> = paths.iter().filter(|p| p.0 == "Score").collect();
    assert_eq!(scores.len(), creases.len());
    for line in creases {
        let ends_match = |points: &Vec<Vec2>| {
            points.len() == 2
                && ((points[0] - line.a).norm() < 1e-3 && (points[1] - line.b).norm() < 1e-3
                    || (points[0] - line.b).norm() < 1e-3 && (points[1] - line.a).norm() < 1e-3)
        };
        let found: Vec<_> = scores.iter().filter(|p| ends_match(&p.2)).collect();
        assert_eq!(
            found.len(),
            1,
            "{} line {:?}-{:?}",
            line.kind.name(),
            line.a,
            line.b
        );
        assert_eq!(found[0].1, line.kind.name());
    }
    // The outline is cut as closed runs.
    let cuts: Vec<_> = paths.iter().filter(|p| p.0 == "Cut").collect();
    assert!(!cuts.is_empty() && cuts.iter().all(|p| p.2.first() == p.2.last()));
}

#[test]
fn the_pdf_page_as_cut_draws_exactly_the_dashes_of_sheet_svg() {
    // The PDF's first page draws whole fold lines in styles to fold by; its last page
    // draws what the knife cuts. Read back with printpdf's parser, that page's segments
    // are sheet.svg's (read by this file's own reader), kind by kind (told by colour:
    // cut black, mountain red, valley blue), each within 2 µm, none left over.
    let machine = Machine::load("generic-hpgl").unwrap();
    let mesh = crease::io::read(&patterns()[0].with_file_name("miura-bent.fold")).unwrap();
    let out = fabricate(&mesh, &machine, &a3_draft()).unwrap();
    let h = out.toolpath.media.height;
    let mut from_svg: Vec<(String, [f64; 2], [f64; 2])> =
        svg_segments(output_text(&out, "sheet.svg"))
            .into_iter()
            .map(|(kind, a, b, _)| (kind, [a[0], h - a[1]], [b[0], h - b[1]]))
            .collect();
    assert!(from_svg.len() > 100);
    let doc = printpdf::PdfDocument::parse(
        output(&out, "sheet.pdf"),
        &Default::default(),
        &mut Vec::new(),
    )
    .unwrap();
    let page = doc.pages.last().unwrap();
    let mm = |pt: f32| f64::from(pt) * 25.4 / 72.0;
    let mut kind = String::new();
    let mut from_pdf = Vec::new();
    for op in &page.ops {
        match op {
            printpdf::Op::SetOutlineColor {
                col: printpdf::Color::Rgb(c),
            } => {
                kind = match [c.r, c.g, c.b].map(|v| (v * 255.0).round() as u8) {
                    [0, 0, 0] => "cut",
                    [255, 0, 0] => "mountain",
                    [0, 0, 255] => "valley",
                    [192, 192, 192] => "flat",
                    other => panic!("a stroke colour no operation has: {other:?}"),
                }
                .to_string()
            }
            printpdf::Op::DrawLine { line } => {
                let p = |i: usize| [mm(line.points[i].p.x.0), mm(line.points[i].p.y.0)];
                from_pdf.push((kind.clone(), p(0), p(1)));
            }
            _ => {}
        }
    }
    assert_eq!(from_pdf.len(), from_svg.len());
    let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) < 2e-3;
    for (k, a, b) in from_pdf {
        let i = from_svg
            .iter()
            .position(|(k2, c, d)| {
                *k2 == k && (near(a, *c) && near(b, *d) || near(a, *d) && near(b, *c))
            })
            .unwrap_or_else(|| panic!("the PDF's {k} segment {a:?}-{b:?} is not in sheet.svg"));
        from_svg.swap_remove(i);
    }
}

#[test]
fn design_side_png_looks_along_the_axis_a_sheet_is_bent_about() {
    // A plane rolled onto a cylinder (radius 60 mm) about the y axis, then about the x
    // axis: every face normal is perpendicular to the axis, so the paper shows least
    // seen along it; the side view is that axis, raised 12°, and its picture shows the
    // arch's rise: the painted rows span the form's height × px per mm, seen at 12°.
    use crease::generate::{generate, Params, PatternKind};
    use crease::output::png;
    let mut params = Params::square(PatternKind::Plane, 6, 20.0);
    params.fold = Some(0.0);
    let plane = generate(&params).unwrap();
    let r = 60.0;
    for axis in [Vec3::y(), Vec3::x()] {
        let mut mesh = plane.clone();
        let rolled: Vec<Vec3> = mesh
            .positions()
            .iter()
            .map(|p| {
                let (across, along) = if axis == Vec3::y() {
                    (p.x - 60.0, p.y)
                } else {
                    (p.y - 60.0, p.x)
                };
                let (a, z) = (r * (across / r).sin(), r * (1.0 - (across / r).cos()));
                if axis == Vec3::y() {
                    Vec3::new(a, along, -z)
                } else {
                    Vec3::new(along, a, -z)
                }
            })
            .collect();
        mesh.set_positions(rolled);
        let view = png::design_side_view(&mesh);
        let horizontal = Vec3::new(view.x, view.y, 0.0).normalize();
        assert!(
            horizontal.dot(&axis).abs() > 0.999,
            "{axis:?}: seen from {view:?}"
        );
        assert!((view.z.asin().to_degrees() - 12.0).abs() < 1e-9, "{view:?}");
        let (w, h, pixels) = read_png(&png::design_side(&mesh).unwrap());
        assert_eq!([w, h], png::DESIGN_SIZE_PX);
        let painted_rows: Vec<usize> = (0..h as usize)
            .filter(|&row| {
                pixels[row * w as usize..(row + 1) * w as usize]
                    .iter()
                    .any(|&p| p != png::DESIGN_BACKGROUND)
            })
            .collect();
        let rows = (painted_rows.last().unwrap() - painted_rows[0] + 1) as f64;
        let camera = png::DesignCamera::framing_from(mesh.positions(), view);
        let (lo, hi) = mesh.bounding_box();
        // The rise (z) seen at 12° plus the depth along the axis foreshortened by sin 12°.
        let rise = (hi.z - lo.z) * 12f64.to_radians().cos()
            + (hi - lo).dot(&axis).abs() * 12f64.to_radians().sin();
        let expected = rise * camera.px_per_mm;
        assert!(
            (rows / expected - 1.0).abs() < 0.03,
            "{axis:?}: {rows} rows painted, {expected:.0} expected"
        );
    }
}
