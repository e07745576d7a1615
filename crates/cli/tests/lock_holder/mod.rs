//! An advisory lock on a lock file held by another process, as a live run holds it. The test
//! process must not hold it itself: a lock is shared with every child another test thread is
//! spawning until that child has replaced itself with its program, so a released lock could
//! still be held for an instant and refuse the next run. Each test file compiles this module
//! on its own and uses part of it, hence `dead_code` allowed.
#![allow(dead_code)]

use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};

/// The environment variable that makes [`hold_lock_helper`] hold the lock on its path.
const HOLD: &str = "WEARSIM_TEST_HOLD_LOCK";

/// A helper process (this test binary, running [`hold_lock_helper`]) holding the lock on a
/// file until dropped.
pub struct LockHolder(Child);

impl LockHolder {
    /// Locks `path` (created if missing, its content kept) in a helper process.
    pub fn take(path: &Path) -> Self {
        let mut child = Command::new(std::env::current_exe().unwrap())
            .args([
                "--exact",
                "lock_holder::hold_lock_helper",
                "--ignored",
                "--nocapture",
            ])
            .env(HOLD, path)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
        assert!(
            lines.any(|l| l.is_ok_and(|l| l == "locked")),
            "the helper took no lock"
        );
        Self(child)
    }

    /// Locks `path` as a live run holds its lock: this process's id written in the file.
    pub fn live(path: &Path) -> Self {
        std::fs::write(path, std::process::id().to_string()).unwrap();
        Self::take(path)
    }

    /// Runs `command` while the lock is held, then releases it: the command must be refused at
    /// once as another run's folder (exit 1). Its output.
    #[track_caller]
    pub fn refuses(self, command: impl FnOnce() -> Output) -> Output {
        let o = command();
        drop(self);
        let said = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{said}");
        assert!(said.contains("another wearsim run"), "{said}");
        o
    }
}

impl Drop for LockHolder {
    fn drop(&mut self) {
        // Its standard input closed, the helper ends and the system releases the lock.
        drop(self.0.stdin.take());
        let _ = self.0.wait();
    }
}

/// Not a test of its own: the helper process of [`LockHolder`] (does nothing without its
/// environment variable).
#[test]
#[ignore = "the helper process of LockHolder"]
fn hold_lock_helper() {
    let Some(path) = std::env::var_os(HOLD) else {
        return;
    };
    let file = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(path)
        .unwrap();
    file.try_lock().unwrap();
    println!("locked");
    let _ = std::io::stdin().read_to_end(&mut Vec::new());
}
