//! Issue 35's doors, through the `wearsim` binary: each test names the door it holds (closed
//! pipes, the lock, bounds on work, `check` against `run`, the sweep's `[run]` table and files,
//! the description, `extends`, a symlinked `--out`).

#![cfg(unix)]

use std::process::{Command, Output, Stdio};

mod common;
use common::{listing, scratch};

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs `wearsim args` with standard output (and, if `stderr_too`, standard error) a pipe
/// whose reading end is already closed: every write fails with a broken pipe.
fn into_closed_pipe(args: &[&str], stderr_too: bool) -> Output {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let err = if stderr_too {
        Stdio::from(writer.try_clone().unwrap())
    } else {
        Stdio::piped()
    };
    Command::new(env!("CARGO_BIN_EXE_wearsim"))
        .args(args)
        .stdout(writer)
        .stderr(err)
        .output()
        .expect("wearsim runs")
}

/// The exit of a program a closed pipe ended (128 + SIGPIPE).
const CLOSED_PIPE: i32 = 141;

#[test]
fn closed_pipes_end_quietly_and_leave_the_output_folder_whole() {
    for args in [&["scenes"][..], &["check", "lgres"]] {
        let o = into_closed_pipe(args, false);
        assert_eq!(
            o.status.code(),
            Some(CLOSED_PIPE),
            "{args:?}: {}",
            stderr(&o)
        );
        assert!(!stderr(&o).contains("panicked"), "{args:?}: {}", stderr(&o));
    }
    // Progress lines and the summary into the same closed pipe (`run … 2>&1 | head -1`).
    let dir = scratch("closed-pipe");
    let out = dir.join("out");
    let o = into_closed_pipe(
        &[
            "run",
            "lgres",
            "--cycles",
            "1",
            "--stages",
            "0",
            "--no-animation",
            "--out",
            out.to_str().unwrap(),
        ],
        true,
    );
    assert_eq!(o.status.code(), Some(CLOSED_PIPE));
    assert_eq!(listing(&dir), ["out"], "nothing beside --out");
    assert!(
        out.join("summary.json").is_file(),
        "the run's folder is whole"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
