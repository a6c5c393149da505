//! The folding motion (issue 49): every frame of `fold_motion` checked against the flat
//! sheet, the design and the sheet's edge lengths; its glTF checked by the Khronos glTF
//! validator and read back by the `gltf` crate; its multi-frame FOLD opened by Rabbit Ear
//! (both installed by tests/run into tests/js); its animated PNG decoded by the png crate.

use crate::common;
use crate::common::js::node;
use crease::mesh::{Mesh, Vec3};
use crease::pipeline::{fold_motion, motion_files, Motion};
use std::path::{Path, PathBuf};

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

fn motion_of(rel: &str, steps: usize) -> (Mesh, Motion) {
    let design = crease::io::read(&repo(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"));
    let motion =
        fold_motion(&design, steps, &mut |_, _, _| {}).unwrap_or_else(|e| panic!("{rel}: {e}"));
    (design, motion)
}

/// The largest difference of the distances between every two vertices of `a` and of `b`:
/// zero exactly when the two are the same up to a rigid motion (or a reflection).
fn congruence_gap(a: &[Vec3], b: &[Vec3]) -> f64 {
    let mut worst: f64 = 0.0;
    for i in 0..a.len() {
        for j in i + 1..a.len() {
            worst = worst.max(((a[i] - a[j]).norm() - (b[i] - b[j]).norm()).abs());
        }
    }
    worst
}

/// Writes `motion` as `name` in a scratch folder; the main file's path (with the files
/// beside it, removed with the guard).
fn written(motion: &Motion, name: &str) -> common::ScratchFile {
    let path = common::scratch_file("animate", name, "");
    for (file, bytes) in motion_files(motion, &path).unwrap() {
        std::fs::write(file, bytes).unwrap();
    }
    path
}

#[test]
fn the_motion_starts_flat_ends_at_the_design_and_keeps_every_length() {
    // A Miura-ori bent in design mode, the folded waterbomb, a curved crease and a tube
    // (folded as its strip, whose seam closes at the end).
    for rel in [
        "patterns/miura-bent.fold",
        "patterns/waterbomb-folded.fold",
        "patterns/arc.fold",
        "patterns/waterbomb-tube-bent.fold",
    ] {
        let (design, motion) = motion_of(rel, 10);
        let report = motion
            .report
            .as_ref()
            .unwrap_or_else(|e| panic!("{rel}: {e}"));
        assert!(report.is_clear(), "{rel}: {report}");
        assert_eq!(motion.frames.len(), 11, "{rel}");
        let sheet = &motion.sheet;
        let flat: Vec<Vec3> = sheet
            .crease_pattern()
            .unwrap()
            .iter()
            .map(|p| Vec3::new(p.x, p.y, 0.0))
            .collect();
        let first = &motion.frames[0];
        assert!(
            congruence_gap(first, &flat) < 1e-6,
            "{rel}: frame 0 is not the flat sheet"
        );
        let last = motion.frames.last().unwrap();
        let end = last
            .iter()
            .zip(sheet.positions())
            .map(|(p, q)| (p - q).norm())
            .fold(0.0, f64::max);
        assert!(
            end < 1e-6,
            "{rel}: the last frame is {end} mm from the design"
        );
        if design.is_tube() {
            // The strip's two copies of each seam vertex meet again.
            assert!(sheet.vertex_count() > design.vertex_count(), "{rel}");
        } else {
            assert_eq!(sheet.positions(), design.positions(), "{rel}");
        }
        for (k, x) in motion.frames.iter().enumerate() {
            for edge in sheet.edges() {
                let [a, b] = edge.vertices;
                let now = (x[a] - x[b]).norm();
                let drawn = (flat[a] - flat[b]).norm();
                assert!(
                    (now - drawn).abs() <= 1e-6 * drawn,
                    "{rel}: frame {k} stretches edge {a}-{b}: {now} mm, drawn {drawn} mm"
                );
            }
        }
    }
}

#[test]
fn the_gltf_validates_and_reads_back_as_the_frames() {
    // The designs of the motion test: a bent Miura-ori, the folded waterbomb, a curved
    // crease and a tube's strip.
    for rel in [
        "patterns/miura-bent.fold",
        "patterns/waterbomb-folded.fold",
        "patterns/arc.fold",
        "patterns/waterbomb-tube-bent.fold",
    ] {
        gltf_validates_and_reads_back(rel);
    }
}

fn gltf_validates_and_reads_back(rel: &str) {
    let (_, motion) = motion_of(rel, 8);
    let stem = Path::new(rel).file_stem().unwrap().to_str().unwrap();
    for name in [format!("{stem}.glb"), format!("{stem}.gltf")] {
        let path = written(&motion, &name);
        let report = node("validate-gltf.mjs", &path);
        assert_eq!(report["errors"], 0, "{name}: {report}");
        assert_eq!(report["warnings"], 0, "{name}: {report}");
        assert_eq!(report["animations"], 1, "{name}: {report}");
        assert_eq!(report["morphed"], true, "{name}: {report}");
    }
    let bytes = std::fs::read(written(&motion, &format!("{stem}.glb"))).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    let blob = gltf.blob.clone().unwrap();
    let node = gltf.nodes().find(|n| n.mesh().is_some()).unwrap();
    let t = node.transform().decomposed().0;
    let centre = Vec3::new(t[0] as f64, t[1] as f64, t[2] as f64);
    let mesh = node.mesh().unwrap();
    // Single precision about the centre: each coordinate within a few units in the last
    // place of the sheet's extent (the frame is its base plus its target, both rounded).
    let extent = motion
        .frames
        .iter()
        .flatten()
        .map(|p| (p - centre).norm())
        .fold(0.0, f64::max);
    let allowed = 4.0 * f64::from(f32::EPSILON) * extent;
    let mut sides = Vec::new();
    for primitive in mesh.primitives() {
        let reader = primitive.reader(|_| Some(&blob));
        let base: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        let targets: Vec<Vec<[f32; 3]>> = reader
            .read_morph_targets()
            .map(|(p, _, _)| p.unwrap().collect())
            .collect();
        assert_eq!(targets.len(), motion.frames.len() - 1);
        for (k, frame) in motion.frames.iter().enumerate() {
            for (v, want) in frame.iter().enumerate() {
                let mut got = Vec3::new(base[v][0].into(), base[v][1].into(), base[v][2].into());
                if k > 0 {
                    let d = targets[k - 1][v];
                    got += Vec3::new(d[0].into(), d[1].into(), d[2].into());
                }
                let err = (got + centre - want).norm();
                assert!(
                    err <= allowed,
                    "frame {k} vertex {v}: {err} mm off (allowed {allowed})"
                );
            }
        }
        if primitive.mode() == gltf::mesh::Mode::Triangles {
            let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
            sides.push((primitive.material().name().unwrap().to_string(), indices));
        }
    }
    // Both sides of the paper, each face once, wound opposite ways.
    assert_eq!(sides.len(), 2);
    let faces = motion.sheet.faces().len();
    assert_eq!((sides[0].1.len(), sides[1].1.len()), (3 * faces, 3 * faces));
    assert_eq!(
        sides[0].1[0..3],
        [sides[1].1[0], sides[1].1[2], sides[1].1[1]]
    );
    assert_ne!(sides[0].0, sides[1].0);
    // The animation holds frame k at key k: one target weighs 1 there.
    let animation = gltf.animations().next().unwrap();
    let channel = animation.channels().next().unwrap();
    let reader = channel.reader(|_| Some(&blob));
    let times: Vec<f32> = reader.read_inputs().unwrap().collect();
    assert_eq!(times.len(), motion.frames.len());
    let Some(gltf::animation::util::ReadOutputs::MorphTargetWeights(weights)) =
        reader.read_outputs()
    else {
        panic!("the animation drives the morph weights");
    };
    let weights: Vec<f32> = weights.into_f32().collect();
    let n = motion.frames.len() - 1;
    for k in 0..=n {
        let row = &weights[k * n..(k + 1) * n];
        let ones: Vec<usize> = (0..n).filter(|&j| row[j] == 1.0).collect();
        let want: Vec<usize> = if k == 0 { vec![] } else { vec![k - 1] };
        assert_eq!(ones, want, "key {k}");
        assert_eq!(
            row.iter().filter(|&&w| w != 0.0).count(),
            want.len(),
            "key {k}"
        );
    }
}

#[test]
fn the_multi_frame_fold_opens_in_rabbit_ear_crease_pattern_first() {
    let (design, motion) = motion_of("patterns/waterbomb-folded.fold", 6);
    let path = written(&motion, "waterbomb.fold");
    let frames = node("read-fold-frames.cjs", &path);
    let frames = frames.as_array().unwrap();
    assert_eq!(frames.len(), motion.frames.len() + 1);
    let flat = motion.sheet.crease_pattern().unwrap();
    let cp = &frames[0];
    assert_eq!(cp["classes"], serde_json::json!(["creasePattern"]), "{cp}");
    assert_eq!(cp["folded"], false);
    assert_eq!(cp["valid"]["summary"], "valid", "{}", cp["valid"]);
    assert!(cp["faces"].as_u64().unwrap() > 0);
    for (v, p) in cp["vertices"].as_array().unwrap().iter().enumerate() {
        let p: Vec<f64> = serde_json::from_value(p.clone()).unwrap();
        assert_eq!(p.len(), 2, "frame 0 is flat, two coordinates a vertex");
        assert!((p[0] - flat[v].x).abs() < 1e-9 && (p[1] - flat[v].y).abs() < 1e-9);
    }
    for (k, frame) in frames[1..].iter().enumerate() {
        assert_eq!(frame["folded"], true, "frame {}", k + 1);
        assert_eq!(frame["valid"]["summary"], "valid");
        assert_eq!(
            frame["edges"],
            cp["edges"],
            "frame {} inherits the edges",
            k + 1
        );
        for (v, p) in frame["vertices"].as_array().unwrap().iter().enumerate() {
            let p: Vec<f64> = serde_json::from_value(p.clone()).unwrap();
            let want = motion.frames[k][v];
            assert!(
                (Vec3::new(p[0], p[1], p[2]) - want).norm() < 1e-9,
                "frame {}",
                k + 1
            );
        }
    }
    // crease reads the motion back as the design it ends at, with its crease pattern.
    let back = crease::io::read(&path).unwrap();
    let gap = back
        .positions()
        .iter()
        .zip(design.positions())
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max);
    assert!(gap < 1e-9, "{gap}");
    assert_eq!(back.crease_pattern().unwrap(), flat);
}

#[test]
fn a_design_written_crease_pattern_first_reads_back_the_same() {
    let design = crease::io::read(&repo("patterns/miura-bent.fold")).unwrap();
    let text = crease::io::fold::to_string_crease_pattern_first(&design);
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(value["frame_classes"], serde_json::json!(["creasePattern"]));
    assert_eq!(
        value["file_frames"][0]["frame_classes"],
        serde_json::json!(["foldedForm"])
    );
    let back = crease::io::fold::parse(&text).unwrap();
    assert_eq!(back.positions(), design.positions());
    assert_eq!(back.crease_pattern(), design.crease_pattern());
    assert_eq!(back.edges().len(), design.edges().len());
}

#[test]
fn the_folded_form_read_is_the_last_frame_with_coordinates_of_its_own() {
    // crease's order, then a folded frame that only inherits the crease pattern's
    // coordinates (it says nothing new: the 3D form stays), then one with its own.
    let design = crease::io::read(&repo("patterns/miura-bent.fold")).unwrap();
    let mut value: serde_json::Value =
        serde_json::from_str(&crease::io::fold::to_string(&design)).unwrap();
    value["file_frames"]
        .as_array_mut()
        .unwrap()
        .push(serde_json::json!(
            {"frame_inherit": true, "frame_parent": 1, "frame_classes": ["foldedForm"]}
        ));
    let back = crease::io::fold::parse(&value.to_string()).unwrap();
    assert_eq!(back.positions(), design.positions());
    let lifted: Vec<[f64; 3]> = design
        .positions()
        .iter()
        .map(|p| [p.x, p.y, p.z + 1.0])
        .collect();
    value["file_frames"].as_array_mut().unwrap().push(serde_json::json!(
        {"frame_inherit": true, "frame_parent": 0, "frame_classes": ["foldedForm"], "vertices_coords": lifted}
    ));
    let back = crease::io::fold::parse(&value.to_string()).unwrap();
    assert!((back.positions()[0].z - design.positions()[0].z - 1.0).abs() < 1e-9);
}

#[test]
fn a_blocked_path_ends_the_motion_where_the_flaps_collide() {
    // Two flaps, both mountain to 170°, swing behind the middle panel and must pass
    // through each other past 90° (see layers.rs's path test).
    let strip = r#"{"file_spec": 1.1, "frame_classes": ["creasePattern"],
 "vertices_coords": [[0,0],[30,0],[40,0],[70,0],[0,10],[30,10],[40,10],[70,10]],
 "faces_vertices": [[0,1,5,4],[1,2,6,5],[2,3,7,6]],
 "edges_vertices": [[0,1],[1,2],[2,3],[3,7],[7,6],[6,5],[5,4],[4,0],[1,5],[2,6]],
 "edges_assignment": ["B","B","B","B","B","B","B","B","M","M"],
 "edges_foldAngle": [0,0,0,0,0,0,0,0,-170,-170]}"#;
    let file = common::scratch_file("animate", "flaps.fold", strip);
    let design = crease::io::read(&file).unwrap();
    let motion = fold_motion(&design, 20, &mut |_, _, _| {}).unwrap();
    let report = motion.report.as_ref().unwrap();
    let hit = report.collision.as_ref().expect("the flaps collide");
    assert_eq!(
        motion.frames.len(),
        hit.step + 1,
        "the motion ends at the blocking frame"
    );
    assert!(hit.step < 20);
    assert_eq!(motion.exit_code(), 1);
    let out = common::scratch_file("animate", "flaps.glb", "");
    let (code, stdout, stderr) = common::run_crease(&[
        "animate",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--frames",
        "20",
    ]);
    assert_eq!(code, 1, "{stdout}{stderr}");
    let named = format!("faces {} and {}", hit.faces.0, hit.faces.1);
    assert!(
        stdout.contains(&named) && stdout.contains("pass through each other"),
        "{stdout}"
    );
    assert!(
        std::fs::metadata(&out).unwrap().len() > 0,
        "the motion up to the block is written"
    );
}

#[test]
fn the_square_twist_bends_its_panels_and_the_miura_ori_folds_rigidly() {
    let (_, twist) = motion_of("tests/data/origamisimulator/singlesquaretwist.svg", 10);
    assert!(twist.report.as_ref().unwrap().panels_bend);
    assert!(!twist.bending.is_rigid(), "{}", twist.bending);
    assert!(twist.bending.deviation_mm > 1.0, "{}", twist.bending);
    assert!(
        twist.summary().contains("not rigid-foldable"),
        "{}",
        twist.summary()
    );
    // The bending measured is the panel's own: its vertices' distance from their plane
    // in the frame named, recomputed here from the frame.
    let panel = crease::pipeline::panels(&twist.sheet)
        .into_iter()
        .find(|(face, _)| *face == twist.bending.face)
        .unwrap();
    let x = &twist.frames[twist.bending.frame];
    let d = crease::geometry::out_of_plane(panel.1.iter().map(|&v| x[v]));
    assert!((d - twist.bending.deviation_mm).abs() < 1e-9);

    let (_, miura) = motion_of("patterns/miura.fold", 10);
    assert!(!miura.report.as_ref().unwrap().panels_bend);
    assert!(miura.bending.is_rigid(), "{}", miura.bending);
    assert!(
        miura.summary().contains("rigid-foldable"),
        "{}",
        miura.summary()
    );
}

#[test]
fn out_of_plane_is_the_distance_from_the_least_squares_plane() {
    // A square whose corners are alternately h above and below its middle plane (a
    // twisted quad, as a panel bent along its diagonal): by symmetry that plane is the
    // least-squares one and every corner is h from it. Turned and moved anywhere, the
    // same; flat, nothing.
    let turn = nalgebra::Rotation3::from_euler_angles(0.3, -1.1, 2.0);
    let shift = Vec3::new(5.0, -40.0, 12.0);
    for h in [0.0, 0.1, 2.0] {
        let corners = [
            Vec3::new(0.0, 0.0, h),
            Vec3::new(10.0, 0.0, -h),
            Vec3::new(10.0, 10.0, h),
            Vec3::new(0.0, 10.0, -h),
        ];
        let d = crease::geometry::out_of_plane(corners.iter().map(|&p| turn * p + shift));
        assert!((d - h).abs() < 1e-12, "h {h}: {d}");
    }
}

#[test]
fn the_animated_png_has_a_frame_for_every_state() {
    let (_, motion) = motion_of("patterns/miura.fold", 5);
    let path = written(&motion, "miura.png");
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let control = reader.info().animation_control.expect("an animated PNG");
    assert_eq!(control.num_frames as usize, motion.frames.len());
    let mut pixels = vec![0; reader.output_buffer_size()];
    let mut drawn = Vec::new();
    for _ in 0..control.num_frames {
        reader.next_frame(&mut pixels).unwrap();
        // Paper and creases cover part of the picture, the rest is background.
        let background = crease::output::png::DESIGN_BACKGROUND;
        let painted = pixels.chunks(4).filter(|p| p[..3] != background).count();
        drawn.push(painted);
    }
    assert!(drawn.iter().all(|&n| n > 1000), "{drawn:?}");
    // The sheet folds: the flat frame and the folded one cover different areas.
    assert_ne!(drawn[0], *drawn.last().unwrap());
}

#[test]
fn bad_animate_requests_are_one_line_errors_and_write_nothing() {
    let design = repo("patterns/miura.fold");
    let design = design.to_str().unwrap();
    let dir = common::scratch_file("animate", "placeholder", "");
    let dir = dir.parent().unwrap();
    for (out, frames, says) in [
        ("motion.obj", "10", "give one of these extensions"),
        ("zero.glb", "0", "--frames"),
        ("huge.glb", "1000000000", "--frames"),
    ] {
        let path = dir.join(out);
        let (code, stdout, stderr) = common::run_crease(&[
            "animate",
            design,
            "-o",
            path.to_str().unwrap(),
            "--frames",
            frames,
        ]);
        assert_eq!(code, 2, "{out}: {stdout}{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.contains(says), "{out}: {stderr}");
        assert!(!path.exists(), "{out} was written");
    }
}

#[test]
fn fab_writes_the_motion_beside_the_previews_when_asked() {
    let design = repo("patterns/miura.fold");
    let dir = common::scratch_file("animate", "placeholder", "");
    let dir = dir.parent().unwrap();
    for motion in [true, false] {
        let out = dir.join(format!("fab-motion-{motion}"));
        let mut args = vec![
            "fab",
            design.to_str().unwrap(),
            "--machine",
            "generic-hpgl",
            "-o",
            out.to_str().unwrap(),
        ];
        if motion {
            args.push("--motion");
        }
        let (code, stdout, stderr) = common::run_crease(&args);
        assert_eq!(code, 0, "{stdout}{stderr}");
        let report: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
        let said = &report["previews"]["motion.png"];
        assert_eq!(out.join("motion.png").exists(), motion);
        if !motion {
            assert!(said.is_null(), "{said}");
            continue;
        }
        assert!(said.as_str().unwrap().contains("rigid-foldable"), "{said}");
        let file = std::fs::File::open(out.join("motion.png")).unwrap();
        let reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .unwrap();
        let frames = reader.info().animation_control.unwrap().num_frames as usize;
        assert_eq!(frames, crease::pipeline::MOTION_PREVIEW_FRAMES + 1);
    }
}

/// A picture a PDF page draws, as lopdf reads it: its pixels (8-bit RGB) and the box it
/// fills on the page (pt, lower-left and upper-right).
struct PlacedImage {
    width: usize,
    height: usize,
    rgb: Vec<u8>,
    area: [f32; 4],
}

/// Every page of `pdf` with the images it draws, in drawing order: each `Do` of an image
/// XObject placed by the transformation matrix in force (`q`, `Q`, `cm`).
fn pdf_images(pdf: &[u8]) -> Vec<Vec<PlacedImage>> {
    let doc = lopdf::Document::load_mem(pdf).expect("lopdf reads sheet.pdf");
    let number = |o: &lopdf::Object| o.as_float().expect("a number");
    doc.get_pages()
        .values()
        .map(|&page| {
            let page_dict = doc.get_dictionary(page).unwrap();
            let xobjects = doc
                .get_dict_in_dict(page_dict, b"Resources")
                .and_then(|r| doc.get_dict_in_dict(r, b"XObject"))
                .ok();
            let content = doc.get_and_decode_page_content(page).unwrap();
            let mut ctm = [1.0f32, 0.0, 0.0, 1.0, 0.0, 0.0];
            let mut saved = Vec::new();
            let mut images = Vec::new();
            for op in &content.operations {
                match op.operator.as_str() {
                    "q" => saved.push(ctm),
                    "Q" => ctm = saved.pop().expect("balanced q/Q"),
                    "cm" => {
                        let m: Vec<f32> = op.operands.iter().map(number).collect();
                        let c = ctm;
                        ctm = [
                            m[0] * c[0] + m[1] * c[2],
                            m[0] * c[1] + m[1] * c[3],
                            m[2] * c[0] + m[3] * c[2],
                            m[2] * c[1] + m[3] * c[3],
                            m[4] * c[0] + m[5] * c[2] + c[4],
                            m[4] * c[1] + m[5] * c[3] + c[5],
                        ];
                    }
                    "Do" => {
                        let name = op.operands[0].as_name().unwrap();
                        let id = xobjects.unwrap().get(name).unwrap().as_reference().unwrap();
                        let stream = doc.get_object(id).unwrap().as_stream().unwrap();
                        if stream.dict.get(b"Subtype").and_then(|s| s.as_name()).ok()
                            != Some(b"Image".as_slice())
                        {
                            continue;
                        }
                        let int = |k: &[u8]| stream.dict.get(k).unwrap().as_i64().unwrap();
                        assert_eq!(int(b"BitsPerComponent"), 8);
                        let (x0, y0) = (ctm[4], ctm[5]);
                        let (x1, y1) = (ctm[0] + ctm[2] + ctm[4], ctm[1] + ctm[3] + ctm[5]);
                        images.push(PlacedImage {
                            width: int(b"Width") as usize,
                            height: int(b"Height") as usize,
                            rgb: stream
                                .decompressed_content()
                                .unwrap_or(stream.content.clone()),
                            area: [x0.min(x1), y0.min(y1), x0.max(x1), y0.max(y1)],
                        });
                    }
                    _ => {}
                }
            }
            images
        })
        .collect()
}

#[test]
fn sheet_pdf_ends_with_a_folding_guide_of_the_motion() {
    use crease::pipeline::{fabricate, FabOptions, Guide, GUIDE_PICTURES};
    let design = crease::io::read(&repo("patterns/miura-bent.fold")).unwrap();
    let machine = crease::machine::Machine::load("generic-hpgl").unwrap();
    let run = |guide| {
        let options = FabOptions {
            guide,
            route: crease::fab::RouteSearch::Draft,
            ..FabOptions::default()
        };
        let out = fabricate(&design, &machine, &options).unwrap();
        let pdf = common::fabbing::output(&out, "sheet.pdf").to_vec();
        (out, pdf)
    };
    let (guided, pdf) = run(Guide::Auto);
    let (plain, plain_pdf) = run(Guide::Never);
    let (pages, plain_pages) = (pdf_images(&pdf), pdf_images(&plain_pdf));
    assert_eq!(pages.len(), plain_pages.len() + 1, "one page more");
    assert!(plain.guide_note.is_none());
    let said = guided.guide_note.as_deref().unwrap();
    assert!(said.contains("ends with a folding guide"), "{said}");
    assert!(plain_pages.iter().all(Vec::is_empty), "no pictures without");

    let images = pages.last().unwrap();
    assert_eq!(images.len(), GUIDE_PICTURES);
    assert!((4..=6).contains(&images.len()), "4–6 frames");
    // Each caption gives how far it is folded: 0% first, the design (100%) last, rising.
    let doc = printpdf::PdfDocument::parse(&pdf, &Default::default(), &mut Vec::new()).unwrap();
    let last = doc.pages.last().unwrap();
    let texts = common::fabbing::pdf_texts(last);
    let percents: Vec<f64> = texts
        .iter()
        .filter_map(|t| {
            let before = t.split('%').next().filter(|_| t.contains('%'))?;
            let n = before.rsplit([' ', '(']).next()?;
            n.parse().ok()
        })
        .collect();
    assert_eq!(percents.len(), images.len(), "{texts:?}");
    assert_eq!(percents.first(), Some(&0.0), "{texts:?}");
    assert_eq!(percents.last(), Some(&100.0), "{texts:?}");
    assert!(percents.windows(2).all(|w| w[0] < w[1]), "{percents:?}");
    // The pictures: each one frame of the sheet (not blank), no two alike, side by side
    // on the page without overlapping, and at least 35 mm wide.
    let (w_pt, h_pt) = (last.media_box.width.0, last.media_box.height.0);
    for image in images {
        assert_eq!(image.rgb.len(), image.width * image.height * 3);
        let background = &image.rgb[..3];
        let painted = image
            .rgb
            .chunks_exact(3)
            .filter(|p| *p != background)
            .count();
        assert!(
            painted * 20 > image.width * image.height,
            "the sheet covers over 5% of each picture ({painted} px)"
        );
        let [x0, y0, x1, y1] = image.area;
        assert!(
            x0 >= 0.0 && y0 >= 0.0 && x1 <= w_pt && y1 <= h_pt,
            "{:?}",
            image.area
        );
        assert!(
            x1 - x0 > 100.0,
            "each picture is over 35 mm wide: {:?}",
            image.area
        );
        let aspect = (x1 - x0) / (y1 - y0);
        let pixels = image.width as f32 / image.height as f32;
        assert!((aspect - pixels).abs() < 0.01, "drawn undistorted");
    }
    for i in 0..images.len() {
        for j in i + 1..images.len() {
            let (a, b) = (&images[i], &images[j]);
            let differ = a
                .rgb
                .chunks_exact(3)
                .zip(b.rgb.chunks_exact(3))
                .filter(|(p, q)| p != q)
                .count();
            assert!(
                differ * 100 > a.rgb.len() / 3,
                "frames {i} and {j} differ in over 1% of their pixels"
            );
            let (p, q) = (a.area, b.area);
            assert!(
                p[2] <= q[0] || q[2] <= p[0] || p[3] <= q[1] || q[3] <= p[1],
                "pictures {i} and {j} overlap"
            );
        }
    }
}

#[test]
fn the_folding_guide_is_left_out_where_the_path_is_not_clear_or_turned_off() {
    // The two-flap strip with its 3D form (both flaps mountain to 170°, crossing): the
    // design fails verification, cut with --force; its path from flat is blocked.
    let (c, s) = (170f64.to_radians().cos(), 170f64.to_radians().sin());
    let cp = [
        [0., 0.],
        [30., 0.],
        [40., 0.],
        [70., 0.],
        [0., 10.],
        [30., 10.],
        [40., 10.],
        [70., 10.],
    ];
    let folded: Vec<[f64; 3]> = cp
        .iter()
        .map(|&[x, y]| match x {
            x if x < 30.0 => [30.0 - (30.0 - x) * c, y, -(30.0 - x) * s],
            x if x > 40.0 => [40.0 + (x - 40.0) * c, y, -(x - 40.0) * s],
            x => [x, y, 0.0],
        })
        .collect();
    let fold = serde_json::json!({
        "file_spec": 1.1, "frame_classes": ["foldedForm"], "frame_attributes": ["3D"],
        "vertices_coords": folded,
        "faces_vertices": [[0,1,5,4],[1,2,6,5],[2,3,7,6]],
        "edges_vertices": [[0,1],[1,2],[2,3],[3,7],[7,6],[6,5],[5,4],[4,0],[1,5],[2,6]],
        "edges_assignment": ["B","B","B","B","B","B","B","B","M","M"],
        "edges_foldAngle": [0,0,0,0,0,0,0,0,-170,-170],
        "file_frames": [{"frame_classes": ["creasePattern"], "frame_inherit": true,
                         "frame_parent": 0, "vertices_coords": cp}]
    });
    let file = common::scratch_file("animate", "flaps-3d.fold", &fold.to_string());
    let dir = file.parent().unwrap().to_path_buf();
    let pages = |out: &Path| {
        let pages = pdf_images(&std::fs::read(out.join("sheet.pdf")).unwrap());
        (pages.len(), pages.iter().map(Vec::len).sum::<usize>())
    };
    let mut counts = Vec::new();
    for (name, extra) in [
        ("flaps-guide", None),
        ("flaps-no-guide", Some("--no-guide")),
    ] {
        let out = dir.join(name);
        let mut args = vec![
            "fab",
            file.to_str().unwrap(),
            "--force",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        let (code, stdout, stderr) = common::run_crease(&args);
        assert_eq!(code, 0, "{stdout}{stderr}");
        let report: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
        let said = &report["previews"]["folding-guide"];
        if extra.is_none() {
            let said = said.as_str().unwrap();
            assert!(
                said.contains("no folding guide") && said.contains("pass through each other"),
                "{said}"
            );
            assert!(stderr.contains(said), "the maker is told: {stderr}");
        } else {
            assert!(said.is_null(), "{said}");
        }
        counts.push(pages(&out));
    }
    assert_eq!(counts[0], counts[1], "no guide page either way");
    assert_eq!(counts[0].1, 0, "no pictures");
}

#[test]
fn on_to_flat_the_miura_ori_folds_flat_through_its_design_keeping_every_length() {
    let design = crease::io::read(&repo("patterns/miura.fold")).unwrap();
    let motion = crease::pipeline::fold_motion_on(&design, 10, 5, &mut |_, _, _| {}).unwrap();
    assert_eq!(motion.frames.len(), 16, "{}", motion.summary());
    assert_eq!(motion.exit_code(), 0, "{}", motion.summary());
    assert!(
        matches!(motion.flat, Some(Ok(None))),
        "{}",
        motion.summary()
    );
    // Frame 10 is the design, in place.
    let gap = motion.frames[10]
        .iter()
        .zip(design.positions())
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max);
    assert!(gap < 1e-6, "the design frame is {gap} mm off the design");
    // Every frame keeps every edge's length; the last lies in one plane (folded flat).
    let sheet = &motion.sheet;
    let flat = sheet.crease_pattern().unwrap();
    for (k, x) in motion.frames.iter().enumerate() {
        for e in sheet.edges() {
            let [a, b] = e.vertices;
            let (l0, l) = ((flat[a] - flat[b]).norm(), (x[a] - x[b]).norm());
            assert!((l - l0).abs() < 1e-6 * l0, "frame {k}: {l0} → {l}");
        }
    }
    let last = motion.frames.last().unwrap();
    let size = sheet
        .crease_pattern()
        .unwrap()
        .iter()
        .map(|p| p.norm())
        .fold(0.0, f64::max);
    let thickness = crease::geometry::out_of_plane(last.iter().copied());
    assert!(
        thickness < 1e-3 * size,
        "folded flat: {thickness} mm out of one plane"
    );
    // It was not flat at the design.
    let at_design = crease::geometry::out_of_plane(motion.frames[10].iter().copied());
    assert!(
        at_design > 1e3 * thickness.max(1e-9),
        "{at_design} mm at the design"
    );
}
