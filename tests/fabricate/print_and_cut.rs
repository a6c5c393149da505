//! Print-then-cut (`fab --print-and-cut`): the marks are found in the printed PDF where
//! docs/guide.md says they are, and the cutter's job — read back after quantisation, moved
//! into the page by the marks' origin — cuts along the printed outline.

use crate::common;

use common::fabbing::{distance_to_segment, output, output_text, patterns};
use crease::fab::{LineKind, Stroke};
use crease::machine::Machine;
use crease::mesh::Vec2;
use crease::pipeline::{fabricate, FabOptions, FabOutput};

fn print_and_cut(design: &str, machine: &str, extra: FabOptions) -> FabOutput {
    let mesh = crease::io::read(&patterns()[0].with_file_name(design)).unwrap();
    let machine = Machine::load(machine).unwrap();
    let options = FabOptions {
        print_and_cut: true,
        ..extra
    };
    fabricate(&mesh, &machine, &options).unwrap_or_else(|e| panic!("{design}: {e}"))
}

fn mm(pt: f32) -> f64 {
    f64::from(pt) * 25.4 / 72.0
}

/// What page 1 of a PDF draws, read back by printpdf's parser: black filled polygons,
/// and lines with their stroke colour (RGB bytes), width (mm) and ends (mm, y up).
struct Printed {
    filled: Vec<(Vec<Vec2>, [u8; 3])>,
    lines: Vec<([u8; 3], f64, Vec2, Vec2)>,
    size: Vec2,
}

fn printed_page(pdf: &[u8]) -> Printed {
    let doc = printpdf::PdfDocument::parse(pdf, &Default::default(), &mut Vec::new()).unwrap();
    let page = &doc.pages[0];
    let bytes = |c: &printpdf::Color| match c {
        printpdf::Color::Rgb(c) => [c.r, c.g, c.b].map(|v| (v * 255.0).round() as u8),
        other => panic!("a colour that is not RGB: {other:?}"),
    };
    let (mut stroke, mut fill, mut width) = ([0; 3], [0; 3], 0.0);
    let mut out = Printed {
        filled: Vec::new(),
        lines: Vec::new(),
        size: Vec2::new(mm(page.media_box.width.0), mm(page.media_box.height.0)),
    };
    let point = |p: &printpdf::LinePoint| Vec2::new(mm(p.p.x.0), mm(p.p.y.0));
    for op in &page.ops {
        match op {
            printpdf::Op::SetOutlineColor { col } => stroke = bytes(col),
            printpdf::Op::SetFillColor { col } => fill = bytes(col),
            printpdf::Op::SetOutlineThickness { pt } => width = mm(pt.0),
            printpdf::Op::DrawLine { line } => {
                for w in line.points.windows(2) {
                    out.lines.push((stroke, width, point(&w[0]), point(&w[1])));
                }
            }
            printpdf::Op::DrawPolygon { polygon } => {
                for ring in &polygon.rings {
                    out.filled
                        .push((ring.points.iter().map(point).collect(), fill));
                }
            }
            _ => {}
        }
    }
    out
}

/// A GP-GL job read command by command: the mark search's numbers, and every cut
/// (`D`) segment with the pressure it was cut at, in the job's own steps (feed, carriage).
struct Job {
    search: Vec<i64>,
    cuts: Vec<(i64, [i64; 2], [i64; 2])>,
}

fn read_job(text: &str) -> Job {
    let mut job = Job {
        search: Vec::new(),
        cuts: Vec::new(),
    };
    let (mut at, mut force) = ([0i64; 2], 0);
    for cmd in text.split('\u{3}') {
        let cmd = cmd.trim_start_matches("\u{1b}\u{4}");
        let numbers = |s: &str| -> Vec<i64> {
            s.split(',')
                .filter(|t| !t.is_empty())
                .map(|t| t.parse().unwrap())
                .collect()
        };
        if let Some(rest) = cmd.strip_prefix("TB123,") {
            job.search = numbers(rest);
        } else if let Some(rest) = cmd.strip_prefix("FX") {
            force = numbers(rest)[0];
        } else if let Some(rest) = cmd.strip_prefix('M') {
            let n = numbers(rest);
            at = [n[0], n[1]];
        } else if let Some(rest) = cmd.strip_prefix('D') {
            for p in numbers(rest).chunks(2) {
                job.cuts.push((force, at, [p[0], p[1]]));
                at = [p[0], p[1]];
            }
        }
    }
    job
}

/// The Silhouette marks as the PDF prints them: the filled square's top-left corner and
/// side, and the two corner marks (corner, arm lengths), all in page mm, y up.
struct Marks {
    origin: Vec2,
    square: f64,
    corners: Vec<(Vec2, [f64; 2], f64)>,
}

fn find_marks(page: &Printed) -> Marks {
    let squares: Vec<&Vec<Vec2>> = page
        .filled
        .iter()
        .filter(|(_, fill)| *fill == [0, 0, 0])
        .map(|(p, _)| p)
        .collect();
    assert_eq!(squares.len(), 1, "one black filled mark");
    let (lo, hi) = crease::mesh::bounds(squares[0]);
    assert!(
        ((hi - lo).x - (hi - lo).y).abs() < 1e-3,
        "the filled mark is a square"
    );
    // Corner marks: black lines drawn wider than a hairline, meeting in pairs at a corner.
    let arms: Vec<(f64, Vec2, Vec2)> = page
        .lines
        .iter()
        .filter(|(c, w, ..)| *c == [0, 0, 0] && *w > 0.25)
        .map(|&(_, w, a, b)| (w, a, b))
        .filter(|(_, a, b)| (a - b).norm() > 10.0)
        .collect();
    assert_eq!(arms.len(), 4, "two L marks of two arms each");
    let corners = arms
        .chunks(2)
        .map(|pair| {
            let (w, a, b) = pair[0];
            let (_, c, d) = pair[1];
            assert!((a - c).norm() < 1e-3, "the arms of an L meet");
            (a, [(b - a).norm(), (d - c).norm()], w)
        })
        .collect();
    Marks {
        origin: Vec2::new(lo.x, hi.y),
        square: (hi - lo).x,
        corners,
    }
}

#[test]
fn silhouette_marks_print_where_stated_and_the_job_cuts_the_printed_outline() {
    for (design, media, fill, fit) in [
        ("miura-bent.fold", "a4", None, false),
        (
            "waterbomb-curved.fold",
            "letter",
            Some([255, 232, 160]),
            true,
        ),
    ] {
        let out = print_and_cut(
            design,
            "silhouette-cameo",
            FabOptions {
                media: Some(crease::fab::Media::parse(media).unwrap()),
                print_fill: fill,
                fit,
                ..Default::default()
            },
        );
        let page = printed_page(output(&out, "sheet.pdf"));
        let (w, h) = (page.size.x, page.size.y);
        let marks = find_marks(&page);
        // As docs/guide.md states (inkscape-silhouette's Type 1 marks): a 5 mm square whose
        // top-left corner is 15 mm from the page's left and 20 mm from its top; L marks of
        // 0.3 mm lines with 20 mm arms at the frame's top-right (15 mm from the right
        // edge) and bottom-left (47 mm from the bottom edge).
        let what = format!("{design} on {media}");
        assert!(
            (marks.origin - Vec2::new(15.0, h - 20.0)).norm() < 0.01,
            "{what}"
        );
        assert!((marks.square - 5.0).abs() < 0.01, "{what}");
        let top_right = Vec2::new(w - 15.0, h - 20.0);
        let bottom_left = Vec2::new(15.0, 47.0);
        for (corner, arms, width) in &marks.corners {
            assert!(
                (corner - top_right).norm() < 0.01 || (corner - bottom_left).norm() < 0.01,
                "{what}: a corner mark at {corner:?}"
            );
            assert!(arms.iter().all(|a| (a - 20.0).abs() < 0.01), "{what}");
            assert!((width - 0.3).abs() < 0.01, "{what}: {width} mm lines");
        }
        // The job searches for those marks: frame length and width, and where to start
        // (10 mm before the origin), in 0.05 mm steps.
        let job = read_job(output_text(&out, "sheet.gpgl"));
        let step = 0.05;
        let frame = top_right - bottom_left;
        let steps = |v: f64| (v / step).round() as i64;
        assert_eq!(
            job.search,
            vec![
                steps(frame.y),
                steps(frame.x),
                steps(h - marks.origin.y - 10.0),
                steps(marks.origin.x - 10.0)
            ],
            "{what}"
        );
        // The job's cuts (the pressure of the profile's cut tool), moved into the page by
        // the origin the PDF shows, lie on the printed outline within 0.1 mm, and cover it.
        let cut_force = Machine::load("silhouette-cameo").unwrap().tools[&LineKind::Cut]
            .force
            .unwrap() as i64;
        let to_page = |[feed, carriage]: [i64; 2]| {
            Vec2::new(
                marks.origin.x + carriage as f64 * step,
                marks.origin.y - feed as f64 * step,
            )
        };
        let outline: Vec<Stroke> = page
            .lines
            .iter()
            .filter(|(c, w, ..)| *c == [0, 0, 0] && *w < 0.25)
            .filter(|(_, _, a, b)| a.y > bottom_left.y && b.y > bottom_left.y)
            .map(|&(_, _, a, b)| Stroke::straight(LineKind::Cut, a, b, 0))
            .collect();
        assert!(!outline.is_empty(), "{what}: the outline is printed");
        let cuts: Vec<(Vec2, Vec2)> = job
            .cuts
            .iter()
            .filter(|(f, ..)| *f == cut_force)
            .map(|&(_, a, b)| (to_page(a), to_page(b)))
            .collect();
        let off = |p: Vec2| {
            outline
                .iter()
                .map(|s| distance_to_segment(p, s))
                .fold(f64::INFINITY, f64::min)
        };
        let worst = cuts
            .iter()
            .flat_map(|&(a, b)| [a, b, (a + b) / 2.0])
            .map(off)
            .fold(0.0, f64::max);
        assert!(worst < 0.1, "{what}: a cut {worst:.3} mm off the print");
        let cut_len: f64 = cuts.iter().map(|(a, b)| (b - a).norm()).sum();
        let printed_len: f64 = outline.iter().map(Stroke::length).sum();
        assert!(
            (cut_len - printed_len).abs() < 0.1 * outline.len() as f64,
            "{what}: {cut_len:.2} mm cut along {printed_len:.2} mm printed"
        );
        // Everything printed for the sheet lies inside the frame and clear of the 22 mm
        // corners at the three marks.
        let keep_out = [marks.origin, top_right, bottom_left];
        for (c, wd, a, b) in &page.lines {
            if *c == [0, 0, 0] && *wd > 0.25 || a.y < bottom_left.y - 1.0 {
                continue; // a mark, or the caption's scale bar below the frame
            }
            for p in [*a, *b] {
                assert!(
                    p.x > bottom_left.x
                        && p.x < top_right.x
                        && p.y > bottom_left.y
                        && p.y < top_right.y,
                    "{what}: {p:?} outside the frame"
                );
                for k in keep_out {
                    let d = p - k;
                    assert!(
                        d.x.abs() >= 22.0 - 1e-6 || d.y.abs() >= 22.0 - 1e-6,
                        "{what}: {p:?} within 22 mm of the mark at {k:?}"
                    );
                }
            }
        }
        // A fill colour, when given, is printed under the sheet.
        let filled = page.filled.iter().filter(|(_, c)| Some(*c) == fill).count();
        assert_eq!(filled > 0, fill.is_some(), "{what}");
        // As report.json writes it.
        let report = serde_json::to_value(out.report.print_and_cut.as_ref().unwrap()).unwrap();
        assert_eq!(report["family"], "silhouette");
        assert_eq!(report["marks"]["origin_from_top_left_mm"][1], 20.0);
    }
}

/// One `<path>` of an SVG: its layer's id, its class, and its segments (mm, y down).
type SvgPath = (String, String, Vec<(Vec2, Vec2)>);

/// The `<path>`s of each layer of an SVG, read with the svg crate's parser.
fn svg_layers(text: &str) -> Vec<SvgPath> {
    use svg::node::element::path::{Command, Data, Position};
    use svg::node::element::tag::Type;
    use svg::parser::Event;
    let mut layer = String::new();
    let mut out = Vec::new();
    for event in svg::read(text).unwrap() {
        match event {
            Event::Tag("g", Type::Start, attrs) => {
                layer = attrs.get("id").map(|v| v.to_string()).unwrap_or_default()
            }
            Event::Tag("path", _, attrs) => {
                let data = Data::parse(&attrs["d"]).unwrap();
                let (mut at, mut start) = (Vec2::zeros(), Vec2::zeros());
                let mut segments = Vec::new();
                for c in data.iter() {
                    match c {
                        Command::Move(Position::Absolute, p) => {
                            at = Vec2::new(f64::from(p[0]), f64::from(p[1]));
                            start = at;
                        }
                        Command::Line(Position::Absolute, p) => {
                            let q = Vec2::new(f64::from(p[0]), f64::from(p[1]));
                            segments.push((at, q));
                            at = q;
                        }
                        Command::Close => {
                            segments.push((at, start));
                            at = start;
                        }
                        other => panic!("unexpected path command {other:?}"),
                    }
                }
                let class = attrs
                    .get("class")
                    .map(|v| v.to_string())
                    .unwrap_or_default();
                out.push((layer.clone(), class, segments));
            }
            _ => {}
        }
    }
    out
}

#[test]
fn a_cricut_print_then_cut_file_cuts_the_printed_outline_inside_design_spaces_image() {
    // Design Space prints its own frame (not drawn by crease); sheet.svg carries the
    // image to print (layer Print: the paper's colour and every crease) and the Cut and
    // Score layers in the same frame. Read with the svg crate: the cut lies on the
    // printed outline within 0.1 mm, and all of it within the 6.75 × 9.25 in image Design
    // Space prints, placed as the report says.
    let out = print_and_cut(
        "miura-bent.fold",
        "cricut-maker",
        FabOptions {
            print_fill: Some([200, 230, 255]),
            fit: true,
            ..Default::default()
        },
    );
    let layers = svg_layers(output_text(&out, "sheet.svg"));
    let names: Vec<&str> = layers.iter().map(|l| l.0.as_str()).collect();
    for want in ["Print", "Score", "Cut"] {
        assert!(names.contains(&want), "no {want} layer in {names:?}");
    }
    let printed_outline: Vec<Stroke> = layers
        .iter()
        .filter(|(l, c, _)| l == "Print" && c == "cut")
        .flat_map(|(_, _, s)| s.clone())
        .map(|(a, b)| Stroke::straight(LineKind::Cut, a, b, 0))
        .collect();
    assert!(!printed_outline.is_empty());
    let fills = layers
        .iter()
        .filter(|(l, c, _)| l == "Print" && c.is_empty())
        .count();
    assert_eq!(fills, 1, "the paper's colour under the print");
    let (page_w, image) = (215.9, [171.45, 234.95]);
    let (x0, y0) = ((page_w - image[0]) / 2.0, 10.0);
    let mut cut_len = 0.0;
    for (layer, _, segments) in &layers {
        for &(a, b) in segments {
            for p in [a, b] {
                // The svg crate reads numbers as f32: 1 µm of slack.
                assert!(
                    p.x >= x0 - 1e-3
                        && p.x <= x0 + image[0] + 1e-3
                        && p.y >= y0 - 1e-3
                        && p.y <= y0 + image[1] + 1e-3,
                    "{layer}: {p:?} outside the printed image"
                );
            }
            if layer == "Cut" {
                cut_len += (b - a).norm();
                for p in [a, b, (a + b) / 2.0] {
                    let off = printed_outline
                        .iter()
                        .map(|s| distance_to_segment(p, s))
                        .fold(f64::INFINITY, f64::min);
                    assert!(off < 0.1, "a cut {off:.3} mm off the print");
                }
            }
        }
    }
    let printed_len: f64 = printed_outline.iter().map(Stroke::length).sum();
    assert!(
        (cut_len - printed_len).abs() < 0.01,
        "{cut_len} against {printed_len}"
    );
    let report = out.report.print_and_cut.as_ref().unwrap();
    assert_eq!(report.family, "cricut");
    assert!(
        report.marks.is_none(),
        "Design Space draws the Cricut frame"
    );
}

#[test]
fn print_and_cut_is_refused_clearly_where_it_cannot_work() {
    let mesh = crease::io::read(&patterns()[0].with_file_name("miura-bent.fold")).unwrap();
    let fab = |machine: &str, options: FabOptions| {
        let m = Machine::load(machine).unwrap();
        match fabricate(&mesh, &m, &options) {
            Ok(_) => panic!("{machine}: accepted"),
            // Named as the command line names the options.
            Err(e) => e.naming(&|o| format!("--{}", o.word())),
        }
    };
    let pc = || FabOptions {
        print_and_cut: true,
        ..Default::default()
    };
    let e = fab("generic-hpgl", pc());
    assert!(
        e.contains("no print-and-cut marks") && e.contains("silhouette-cameo"),
        "{e}"
    );
    let e = fab("silhouette-cameo", FabOptions { tile: true, ..pc() });
    assert!(e.contains("--tile"), "{e}");
    let e = fab(
        "silhouette-cameo",
        FabOptions {
            media: Some(crease::fab::Media::parse("100x150mm").unwrap()),
            ..pc()
        },
    );
    assert!(e.contains("100x150mm") && e.contains("too small"), "{e}");
    let e = fab(
        "silhouette-cameo",
        FabOptions {
            width: Some(400.0),
            ..pc()
        },
    );
    assert!(
        e.contains("print-and-cut area") && e.contains("--fit"),
        "{e}"
    );
    // A profile naming marks its protocol cannot find is refused naming the key.
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/generic-hpgl.toml"),
    )
    .unwrap();
    let e = Machine::parse(&format!("print_and_cut = \"silhouette\"\n{text}")).unwrap_err();
    assert!(e.contains("print_and_cut") && e.contains("gpgl"), "{e}");
    let e = crease::output::colour::parse_hex("--print-fill", "yellow").unwrap_err();
    assert!(e.contains("--print-fill") && e.contains("#RRGGBB"), "{e}");
    assert_eq!(
        crease::output::colour::parse_hex("--print-fill", "#ffe8a0"),
        Ok([255, 232, 160])
    );
}

/// The printed next steps name the folder fab wrote as the thing to plot, as the maker
/// types it (they said `crease plot OUT`, a placeholder the maker had to replace).
#[test]
fn next_steps_name_the_output_folder_to_plot() {
    let dir = common::Scratch::new("pc-steps");
    let design = format!("{}/patterns/miura.fold", env!("CARGO_MANIFEST_DIR"));
    let (code, _, err) = common::run_crease(&[
        "fab",
        &design,
        "--machine",
        "silhouette-cameo",
        "--print-and-cut",
        "-o",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let step = err
        .lines()
        .find(|l| l.contains("crease plot"))
        .unwrap_or_else(|| panic!("no plot step: {err}"));
    assert!(
        step.contains(&format!("crease plot {} --port", dir.display())),
        "{step}"
    );
    assert!(!err.contains("crease plot OUT"), "{err}");
    assert!(dir.join("sheet.gpgl").exists());
}
