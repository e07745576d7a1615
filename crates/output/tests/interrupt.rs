//! An interrupted output: once `abandon_staged` (the CLI's SIGINT/SIGTERM handler) has removed
//! the staging folders, writer threads still running (a study's scene runs) must not re-create
//! them. Before, `AtomicFile::create` re-made the folder it was writing into, and a third of
//! interrupted `study --jobs 2` runs left `.<out>.staging-<pid>/` behind. Its own test binary:
//! abandonment is process-wide.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use output::files::{AtomicFile, StagedDir, abandon_staged};

#[test]
fn writers_cannot_recreate_an_abandoned_staging_folder() {
    let parent = std::env::temp_dir().join(format!("lgres-interrupt-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&parent);
    std::fs::create_dir_all(&parent).expect("temp folder");
    let staged = StagedDir::begin(&parent.join("out")).expect("stages");
    let staging = staged.path().to_path_buf();
    let stop = Arc::new(AtomicBool::new(false));
    let committed = Arc::new(AtomicUsize::new(0));
    let writers: Vec<_> = (0..2)
        .map(|w| {
            let (staging, stop, committed) =
                (staging.clone(), Arc::clone(&stop), Arc::clone(&committed));
            std::thread::spawn(move || {
                let mut written = 0;
                for i in 0.. {
                    if stop.load(Ordering::SeqCst) {
                        break;
                    }
                    // Each file in a scene sub-folder of its own, as a study writes them.
                    let path = staging.join(format!("scene{w}-{i}")).join("summary.json");
                    if let Ok(mut file) = AtomicFile::create(&path) {
                        use std::io::Write;
                        let _ = file.write_all(b"{}");
                        if file.commit().is_ok() {
                            written += 1;
                            committed.fetch_add(1, Ordering::SeqCst);
                        }
                    }
                }
                written
            })
        })
        .collect();
    // The interrupt lands while the writers are writing: after their first files (however
    // busy the machine), not at a fixed time.
    let started = Instant::now();
    while committed.load(Ordering::SeqCst) < 4 && started.elapsed() < Duration::from_secs(30) {
        std::thread::sleep(Duration::from_millis(5));
    }
    std::thread::sleep(Duration::from_millis(20));
    abandon_staged();
    std::thread::sleep(Duration::from_millis(100));
    stop.store(true, Ordering::SeqCst);
    let written: usize = writers.into_iter().map(|w| w.join().expect("joins")).sum();
    assert!(written > 0, "the writers wrote before the interrupt");
    assert!(!staging.exists(), "{} re-created", staging.display());
    drop(staged);
    let left: Vec<_> = std::fs::read_dir(&parent)
        .expect("lists")
        .filter_map(Result::ok)
        .map(|e| e.file_name())
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
    std::fs::remove_dir_all(&parent).ok();
}
