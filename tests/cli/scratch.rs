//! The scratch folders every test crate writes in (`common::Scratch`): a test that
//! passes leaves nothing behind, one that fails keeps what it wrote.

use crate::common::{Scratch, ScratchFile};

#[test]
fn a_scratch_folder_goes_when_its_test_passes_and_stays_when_it_fails() {
    // Passed: dropped while not panicking, the folder and its files are gone.
    let (dir, file) = {
        let scratch = Scratch::new("scratch-pass");
        let file = scratch.file("a.txt", "kept until the end");
        assert!(file.is_file() && file.starts_with(&*scratch));
        (scratch.to_path_buf(), file)
    };
    assert!(
        !file.exists() && !dir.exists(),
        "{} was left",
        dir.display()
    );
    // Two folders of one name, as two tests running at once make, are two folders.
    let (a, b) = (Scratch::new("scratch-twice"), Scratch::new("scratch-twice"));
    assert_ne!(a.to_path_buf(), b.to_path_buf());
    // Failed: a test thread that panics keeps its folder for a look.
    let kept = std::thread::spawn(|| {
        let lone = ScratchFile::new("scratch-fail", "job.hpgl", "IN;");
        let path = lone.to_path_buf();
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let _held = lone;
            panic!("a failing test");
        }))
        .expect_err("the closure panics");
        path
    })
    .join()
    .unwrap();
    assert_eq!(std::fs::read_to_string(&kept).unwrap(), "IN;");
    std::fs::remove_dir_all(kept.parent().unwrap()).unwrap();
}
