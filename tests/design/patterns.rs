//! The files in `patterns/` are exactly what the generators produce with their defaults,
//! so they never drift from the code. Regenerate with
//! `crease generate NAME -o patterns/NAME.fold`.

use crease::generate::{generate, Params, PatternKind};
use std::path::Path;

#[test]
fn bundled_starting_patterns_match_the_generators_byte_for_byte() {
    for kind in PatternKind::ALL {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("patterns")
            .join(format!("{}.fold", kind.name()));
        let on_disk =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mesh = generate(&Params::defaults(kind)).unwrap();
        let fresh = crease::io::fold::to_string(&mesh);
        assert!(
            on_disk == fresh,
            "{} differs from the generator; run `crease generate {} -o {}`",
            path.display(),
            kind.name(),
            path.display()
        );
        // And it reads back to the same mesh.
        let back = crease::io::read(&path).unwrap();
        assert_eq!(back.positions(), mesh.positions());
        assert_eq!(back.crease_pattern(), mesh.crease_pattern());
        assert_eq!(back.edges(), mesh.edges());
        assert_eq!(back.faces(), mesh.faces());
    }
}

#[test]
fn closed_resch_matches_the_generator_and_keeps_its_coincidence_groups() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/resch-closed.fold");
    let mut p = Params::defaults(PatternKind::Resch);
    p.fold = Some(1.0);
    let mesh = generate(&p).unwrap();
    assert!(!mesh.coincident.is_empty());
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        crease::io::fold::to_string(&mesh),
        "run `crease generate resch --fold 1 -o patterns/resch-closed.fold`"
    );
    let back = crease::io::read(&path).unwrap();
    assert_eq!(back.coincident, mesh.coincident);
    for g in &back.coincident {
        for &v in g {
            assert!((back.positions()[v] - back.positions()[g[0]]).norm() < 1e-9);
        }
    }
}
