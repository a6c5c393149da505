//! Errors keep their causes as typed values a caller can inspect (`source()`), and say the
//! same one line they said when the causes were strings.

use crease::generate::{generate, GenerateError, Params, PatternKind};
use crease::io::{self, FileCause};
use crease::limits::OutOfRange;
use crease::mesh::MeshError;
use crease::pipeline::{FabError, PipelineError};
use std::error::Error as _;
use std::path::Path;

#[test]
fn a_missing_file_keeps_the_systems_refusal() {
    let path = Path::new("no-such-dir-for-crease/design.fold");
    let e = io::read(path).expect_err("nothing there");
    let io_error = e
        .source()
        .and_then(|s| s.downcast_ref::<FileCause>())
        .and_then(|c| match c {
            FileCause::Io(io) => Some(io),
            _ => None,
        })
        .expect("the cause is the system's error");
    assert_eq!(io_error.kind(), std::io::ErrorKind::NotFound);
    let line = e.to_string();
    assert!(
        line.starts_with("no-such-dir-for-crease/design.fold: "),
        "{line}"
    );
    assert!(!line.contains('\n'), "{line}");
}

#[test]
fn bad_fold_json_keeps_the_parsers_position() {
    let e = io::read_bytes(
        Path::new("bad.fold"),
        b"{\"vertices_coords\": [[0, 0],".to_vec(),
    )
    .expect_err("truncated JSON is refused");
    let FileCause::Json(json) = &e.cause else {
        panic!("not a JSON cause: {e}")
    };
    assert!(json.is_eof(), "{json}");
    assert!(
        e.to_string().starts_with("bad.fold: not valid FOLD JSON: "),
        "{e}"
    );
}

#[test]
fn a_fold_file_of_a_broken_mesh_names_the_face() {
    // A triangle of three collinear points: only the mesh's own validation sees it.
    let text = r#"{"vertices_coords": [[0,0],[1,0],[2,0]], "faces_vertices": [[0,1,2]],
                  "edges_vertices": [[0,1],[1,2],[2,0]], "edges_assignment": ["B","B","B"]}"#;
    let e =
        io::read_bytes(Path::new("broken.fold"), text.as_bytes().to_vec()).expect_err("refused");
    match &e.cause {
        FileCause::Mesh(MeshError::DegenerateFace { face, .. }) => assert_eq!(*face, 0),
        other => panic!("not the mesh's error: {other:?}"),
    }
}

#[test]
fn an_absurd_size_is_a_range_error_with_its_value() {
    let mut p = Params::square(PatternKind::Resch, 4, 10.0);
    p.size = 1e308;
    match generate(&p) {
        Err(GenerateError::Range(OutOfRange { value, input, .. })) => {
            assert_eq!(value, 1e308);
            assert_eq!(input, "size");
        }
        other => panic!("not a range error: {:?}", other.err()),
    }
}

#[test]
fn a_scripts_unreadable_base_is_a_file_error_and_bad_input() {
    let script = crease::pipeline::Script::parse("base = \"missing.fold\"\n").unwrap();
    let dir = crate::common::Scratch::new("errors");
    let e = crease::pipeline::DesignJob::from_script(&script, &dir, None).expect_err("no base");
    assert!(matches!(e, PipelineError::File(_)), "{e:?}");
    assert!(e.is_input_error());
    assert!(e.to_string().contains("missing.fold"), "{e}");
}

#[test]
fn a_width_out_of_range_is_bad_input_not_a_refused_design() {
    let mesh = generate(&Params::square(PatternKind::Miura, 2, 20.0)).unwrap();
    let machine = crease::machine::Machine::load("generic-hpgl").unwrap();
    let options = crease::pipeline::FabOptions {
        width: Some(1e9),
        ..Default::default()
    };
    let e = crease::pipeline::fabricate(&mesh, &machine, &options)
        .err()
        .expect("refused");
    // Bad input naming the width as an option each face names its own way.
    assert!(
        matches!(&e, FabError::Input(a) if a.options().eq([crease::fab::FabOption::Width])),
        "{e:?}"
    );
    assert!(e.is_input());
    let flagged = e.naming(&|o| format!("--{}", o.word()));
    assert!(flagged.starts_with("--width = 1e9: "), "{flagged}");
}

#[test]
fn profile_and_material_files_keep_what_went_wrong() {
    use crease::machine::{Machine, MachineError, Material, MaterialError};
    let dir = crate::common::Scratch::new("errors");
    // Not UTF-8: the system's read refuses it, and that refusal is the cause.
    let binary = dir.join("binary.toml");
    std::fs::write(&binary, [0xff, 0xfe, 0x00]).unwrap();
    let name = binary.to_str().unwrap();
    match Material::load(name) {
        Err(MaterialError::Unreadable { source, .. }) => {
            assert_eq!(source.kind(), std::io::ErrorKind::InvalidData)
        }
        other => panic!("not unreadable: {:?}", other.err()),
    }
    match Machine::load(name) {
        Err(e @ MachineError::Unreadable { .. }) => {
            assert!(e.source().is_some());
            assert!(e.to_string().starts_with(name), "{e}");
        }
        other => panic!("not unreadable: {:?}", other.err()),
    }
    // Readable but wrong: the message names the key.
    let thin = dir.join("thin.toml");
    std::fs::write(
        &thin,
        "name = \"thin\"\nthickness_mm = 0\nclearance_mm = 0.1\nforce_scale = 1\nspeed_scale = 1\n[dash]\nmountain = [1, 1]\nvalley = [1, 1]\n",
    )
    .unwrap();
    match Material::load(thin.to_str().unwrap()) {
        Err(MaterialError::Invalid { cause, path }) => {
            assert_eq!(path, thin);
            assert!(cause.contains("thickness_mm"), "{cause}");
        }
        other => panic!("not invalid: {:?}", other.err()),
    }
}
