//! What an interrupt reports: `abandon_staged` says, per output folder, what is on disk (issue
//! 35: a SIGINT while the finished folder was moved in said "left as it was" while the folder
//! held the new run). Its own test binary: abandonment is process-wide.

use output::files::{FolderLock, LeftBehind, StagedDir, abandon_staged};

#[test]
fn abandon_reports_finished_restored_and_in_place_folders() {
    let parent = std::env::temp_dir().join(format!("lgres-left-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&parent);
    std::fs::create_dir_all(&parent).expect("temp folder");
    // Canonical: the folders are reported by their absolute paths.
    let parent = std::fs::canonicalize(&parent).expect("canonical");
    let finished = StagedDir::begin(&parent.join("finished")).expect("stages");
    std::fs::write(finished.path().join("summary.json"), "{}").expect("writes");
    let finished = finished.commit().expect("commits");
    let staged = StagedDir::begin(&parent.join("staged")).expect("stages");
    let in_place = FolderLock::take(&parent.join("sweep")).expect("locks");
    let left = abandon_staged();
    assert_eq!(
        left,
        [
            LeftBehind::Finished(finished.clone()),
            LeftBehind::AsItWas(parent.join("staged")),
            LeftBehind::WrittenSoFar(parent.join("sweep")),
        ]
    );
    assert!(
        left[0].to_string().contains("finished output"),
        "{}",
        left[0]
    );
    assert!(
        left[1].to_string().contains("left as it was"),
        "{}",
        left[1]
    );
    assert!(finished.join("summary.json").is_file());
    drop((staged, in_place));
    let mut names: Vec<_> = std::fs::read_dir(&parent)
        .expect("lists")
        .map(|e| e.expect("entry").file_name())
        .collect();
    names.sort();
    assert_eq!(names, ["finished"], "no staging folder or lock left");
    std::fs::remove_dir_all(&parent).ok();
}
