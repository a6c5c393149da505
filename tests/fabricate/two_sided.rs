//! Two-sided jobs: mountains scored from the back in a mirrored second job that registers
//! with the first through crosses both jobs cut, the outline cut last, and the order and
//! the turn printed for the maker.

use crate::common;

use crease::fab::{LineKind, Stroke};
use crease::machine::Machine;
use crease::mesh::Vec2;
use crease::pipeline::{fabricate, FabError, FabOptions};
use std::path::Path;

fn design(name: &str) -> crease::mesh::Mesh {
    crease::io::read(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("patterns")
            .join(name),
    )
    .unwrap()
}

fn two_sided() -> FabOptions {
    FabOptions {
        mountains_from_back: true,
        ..Default::default()
    }
}

/// The same segment, either way round.
fn same(a: (Vec2, Vec2), b: (Vec2, Vec2)) -> bool {
    ((a.0 - b.0).norm() < 1e-9 && (a.1 - b.1).norm() < 1e-9)
        || ((a.0 - b.1).norm() < 1e-9 && (a.1 - b.0).norm() < 1e-9)
}

/// The leading knife strokes of a job: the registration crosses.
fn leading_cuts(strokes: &[Stroke]) -> &[Stroke] {
    let n = strokes
        .iter()
        .position(|s| s.kind != LineKind::Cut)
        .unwrap_or(strokes.len());
    &strokes[..n]
}

fn segment_distance(a: (Vec2, Vec2), b: (Vec2, Vec2)) -> f64 {
    let point = |p: Vec2, (s, e): (Vec2, Vec2)| {
        let d = e - s;
        let t = ((p - s).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
        (s + d * t - p).norm()
    };
    // Non-crossing segments are nearest at an end of one of them; the test's strokes
    // never cross the crosses (checked by the distance being positive).
    point(a.0, b)
        .min(point(a.1, b))
        .min(point(b.0, a))
        .min(point(b.1, a))
}

#[test]
fn mountains_from_the_back_are_mirrored_into_a_second_job() {
    let machine = Machine::load("generic-hpgl").unwrap();
    let mesh = design("miura.fold");
    let plain = fabricate(&mesh, &machine, &FabOptions::default()).unwrap();
    let split = fabricate(&mesh, &machine, &two_sided()).unwrap();
    let back = split.back.as_ref().unwrap();
    let front_marks = leading_cuts(&split.toolpath.strokes).len();
    let back_marks = leading_cuts(&back.strokes).len();
    // After its crosses the front job scores valleys only; the back job scores the
    // mountains and then cuts the outline, so the piece stays in the sheet until both
    // sides are scored.
    assert!(split.toolpath.strokes[front_marks..]
        .iter()
        .all(|s| s.kind == LineKind::Valley));
    let body = &back.strokes[back_marks..];
    let first_cut = body.iter().position(|s| s.kind == LineKind::Cut).unwrap();
    assert!(body[..first_cut]
        .iter()
        .all(|s| s.kind == LineKind::Mountain));
    assert!(body[first_cut..].iter().all(|s| s.kind == LineKind::Cut));
    let back_cut: f64 = body[first_cut..].iter().map(|s| s.length()).sum();
    let plain_cut: f64 = plain
        .toolpath
        .strokes
        .iter()
        .filter(|s| s.kind == LineKind::Cut)
        .map(|s| s.length())
        .sum();
    assert!((back_cut - plain_cut).abs() < 1e-6);
    let w = plain.sheet.media.width;
    let front_mountains: Vec<&Stroke> = plain
        .toolpath
        .strokes
        .iter()
        .filter(|s| s.kind == LineKind::Mountain)
        .collect();
    assert_eq!(front_mountains.len(), first_cut);
    // Each back mountain is a front mountain mirrored left to right (miura's natural size
    // leaves room for the registration band, so the layout is the plain run's).
    for s in &body[..first_cut] {
        let m = (
            Vec2::new(w - s.from.x, s.from.y),
            Vec2::new(w - s.to.x, s.to.y),
        );
        assert!(front_mountains.iter().any(|f| same((f.from, f.to), m)));
    }
    assert!(matches!(
        fabricate(
            &mesh,
            &machine,
            &FabOptions {
                width: Some(-3.0),
                ..two_sided()
            }
        ),
        Err(e) if e.is_input()
    ));
}

/// Both jobs start with the same registration crosses as seen on the turned sheet, clear
/// of everything else either job cuts or scores; the plain job has none; the PDF, the
/// report and the summary say which job runs first and how to turn the sheet.
#[test]
fn the_two_jobs_register_through_crosses_both_cut_first() {
    for (machine, name) in [
        ("generic-hpgl", "miura.fold"),
        ("graphtec-ce", "waterbomb-curved.fold"),
        ("laser-dxf", "resch.fold"),
    ] {
        let machine = Machine::load(machine).unwrap();
        let mesh = design(name);
        let fit = FabOptions {
            fit: true,
            ..Default::default()
        };
        let out = fabricate(
            &mesh,
            &machine,
            &FabOptions {
                mountains_from_back: true,
                ..fit.clone()
            },
        )
        .unwrap();
        let plain = fabricate(&mesh, &machine, &fit).unwrap();
        let back = out.back.as_ref().unwrap();
        let media = &out.sheet.media;
        let margin = machine.margin_mm;
        let front = leading_cuts(&out.toolpath.strokes);
        let marks = leading_cuts(&back.strokes);
        // Three crosses of two arms each, in each job, and none in a one-sided job.
        assert_eq!((front.len(), marks.len()), (6, 6), "{name}");
        assert!(!plain.toolpath.strokes.iter().any(|s| front
            .iter()
            .chain(marks)
            .any(|c| same((c.from, c.to), (s.from, s.to)))));
        assert_crosses_meet_when_turned_left_to_right(front, marks, media.width, media.height);
        // Crosses lie inside the reachable area and keep the profile's clearance from
        // every other stroke of their job.
        let clearance = machine.score_settings().clearance;
        for (crosses, job) in [(front, &out.toolpath.strokes), (marks, &back.strokes)] {
            for c in crosses {
                for p in [c.from, c.to] {
                    assert!(p.x >= margin && p.x <= media.width - margin, "{p:?}");
                    assert!(p.y >= margin && p.y <= media.height - margin, "{p:?}");
                }
                for s in &job[crosses.len()..] {
                    let d = segment_distance((c.from, c.to), (s.from, s.to));
                    assert!(d >= clearance, "{name}: a cross {d:.2} mm from a stroke");
                }
            }
        }
        // The order and the turn, in the summary, the report and the PDF's second page.
        let (first, second) = match machine.job_file("sheet") {
            Some(f) => (f, machine.job_file("sheet-back").unwrap()),
            None => ("sheet.svg".to_string(), "sheet-back.svg".to_string()),
        };
        let steps = out.steps.join("\n");
        assert!(
            steps.find(&first).unwrap() < steps.find(&second).unwrap(),
            "{steps}"
        );
        assert!(steps.contains("left to right"));
        let report = out.report.sheet.two_sided.as_ref().unwrap();
        assert_eq!(report.steps, out.steps);
        assert!(report.front_marks_mm != report.back_marks_mm);
        assert!(plain.report.sheet.two_sided.is_none());
        // report.json reads back as the report written, through the one type.
        let text = &out.files.iter().find(|f| f.0 == "report.json").unwrap().1;
        let read = crease::pipeline::FabReport::from_text(std::str::from_utf8(text).unwrap());
        assert_eq!(read.unwrap(), out.report);
        let pdf = &out.files.iter().find(|f| f.0 == "sheet.pdf").unwrap().1;
        let doc = printpdf::PdfDocument::parse(pdf, &Default::default(), &mut Vec::new()).unwrap();
        // Folding template, steps, a page of notes when the pattern leaves the title no
        // room, the front job as cut, and the folding guide where the summary says so
        // (its last page: the guide's own test reads its pictures).
        let guide = out
            .guide_note
            .as_ref()
            .is_some_and(|n| n.contains("ends with a folding guide"));
        let pages = doc.pages.len() - usize::from(guide);
        assert!((3..=4).contains(&pages), "{} pages", doc.pages.len());
        if guide {
            let last = pdf_page_text(doc.pages.last().unwrap());
            assert!(last.contains("how it folds"), "{last}");
        }
        // The last page is titled as cut, or the notes say it is.
        let said = doc.pages[2..]
            .iter()
            .any(|p| pdf_page_text(p).contains(crease::output::pdf::AS_CUT_TITLE));
        assert!(said, "no page says which shows the cut");
        let page_text = pdf_page_text(&doc.pages[1]);
        assert!(page_text.contains(&second) && page_text.contains("Turn the sheet over"));
        let files: Vec<&str> = out.files.iter().map(|f| f.0.as_str()).collect();
        assert!(files.contains(&"sheet-back.svg") && files.contains(&"sheet-back.dxf"));
    }
}

/// Turned over left to right, every front slit lies under a back cross stroke; turned top
/// to bottom instead, some slit lies under no cross (the crosses tell the two turns apart).
fn assert_crosses_meet_when_turned_left_to_right(
    front: &[Stroke],
    marks: &[Stroke],
    width: f64,
    height: f64,
) {
    for f in front {
        let turned = (
            Vec2::new(width - f.from.x, f.from.y),
            Vec2::new(width - f.to.x, f.to.y),
        );
        assert!(marks.iter().any(|b| same((b.from, b.to), turned)));
    }
    assert!(front.iter().any(|f| {
        let wrong = (
            Vec2::new(f.from.x, height - f.from.y),
            Vec2::new(f.to.x, height - f.to.y),
        );
        !marks.iter().any(|b| same((b.from, b.to), wrong))
    }));
}

/// The text a PDF page shows, its pieces joined by spaces.
fn pdf_page_text(page: &printpdf::PdfPage) -> String {
    common::fabbing::pdf_texts(page).join(" ")
}

/// A sheet that fits one-sided but not with the registration band is refused, saying why.
#[test]
fn a_two_sided_sheet_that_leaves_no_room_for_the_crosses_says_so() {
    let machine = Machine::load("generic-hpgl").unwrap();
    let mesh = design("miura.fold");
    // The usable A4 width is 190 mm; 185 fits one-sided, not inside the 8 mm band.
    let width = FabOptions {
        width: Some(185.0),
        ..Default::default()
    };
    assert!(fabricate(&mesh, &machine, &width).is_ok());
    match fabricate(
        &mesh,
        &machine,
        &FabOptions {
            mountains_from_back: true,
            ..width
        },
    ) {
        Err(FabError::Rejected(r)) => assert!(r.0.to_string().contains("registration"), "{}", r.0),
        other => panic!("expected a refusal, got {:?}", other.map(|o| o.job_line)),
    }
}
