//! Helpers shared by the `wearsim` binary's test files. Each test file compiles this module on
//! its own and uses part of it, hence `dead_code` allowed.
#![allow(dead_code)]

use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `wearsim args`, run to the end.
pub fn wearsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wearsim"))
        .args(args)
        .output()
        .expect("wearsim runs")
}

/// A command's standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A temporary folder that a test removes at its end. A failing test leaves it, to be looked
/// at; a passing one fails if the folder cannot be removed (something left unremovable in it).
pub struct Scratch(PathBuf);

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            std::fs::remove_dir_all(&self.0).expect("scratch folder removed");
        }
    }
}

/// A fresh, empty temporary folder named after `tag` and this test process.
pub fn scratch(tag: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("wearsim-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    Scratch(dir)
}

/// A [`scratch`] folder and the path `out` in it (nothing there yet), where the test's
/// commands write their folder.
pub fn scratch_out(tag: &str) -> (Scratch, PathBuf) {
    let dir = scratch(tag);
    let out = dir.join("out");
    (dir, out)
}

/// `o` ended with exit code `code` and its standard error says `needle` (a failure shows the
/// standard error).
#[track_caller]
pub fn assert_exit(o: &Output, code: i32, needle: &str) {
    assert_eq!(o.status.code(), Some(code), "{}", stderr(o));
    assert!(stderr(o).contains(needle), "{}", stderr(o));
}

/// [`assert_exit`] for `case` of a table of cases, named on failure.
#[track_caller]
pub fn assert_case_exit(case: &str, o: &Output, code: i32, needle: &str) {
    assert_eq!(o.status.code(), Some(code), "{case}: {}", stderr(o));
    assert!(stderr(o).contains(needle), "{case}: {}", stderr(o));
}

/// The arguments of the quickest `precision` run into `out`: one method, one tolerance, one
/// repeat of 0.02 s of the LGRES.
pub fn quick_precision(out: &str) -> [&str; 12] {
    [
        "precision",
        "lgres",
        "--methods",
        "bdf",
        "--rtols",
        "1e-3",
        "--repeats",
        "1",
        "--duration",
        "0.02",
        "--out",
        out,
    ]
}

/// The quickest `study` (its wear stages stand for 1e4 cycles, one cycle a run): its arguments
/// before `--out`.
pub const QUICK_STUDY: [&str; 8] = [
    "study",
    "wear-stages",
    "--stage-cycles",
    "1e4",
    "--cycles",
    "1",
    "--cycles-per-stage",
    "1",
];

/// Names in `dir` (hidden ones included), sorted.
pub fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// A copy of the default scene with `from` replaced by `to`, in a temporary file.
pub fn edited_scene(tag: &str, from: &str, to: &str) -> PathBuf {
    let text = lgres::scenes::source("lgres").unwrap();
    assert!(text.contains(from));
    let path = std::env::temp_dir().join(format!("wearsim-{tag}-{}.toml", std::process::id()));
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path
}

/// `wearsim args --out OUT`.
pub fn wearsim_out(args: &[&str], out: &Path) -> Output {
    wearsim(&[args, &["--out", out.to_str().unwrap()]].concat())
}

/// `wearsim run SCENE --out OUT`.
pub fn run_into(scene: &str, out: &Path) -> Output {
    wearsim_out(&["run", scene], out)
}

/// `text` as a file `name` in `dir`.
pub fn write_file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// The default scene changed by the TOML `patch` (a scene that extends it), as
/// `scene.toml` in `dir`.
pub fn lgres_with(dir: &Path, patch: &str) -> PathBuf {
    write_scene(dir, &format!("extends = \"lgres\"\n{patch}"))
}

/// `wearsim check` on the scene file `scene`.
pub fn check(scene: &Path) -> Output {
    wearsim(&["check", scene.to_str().unwrap()])
}

/// `text` as `scene.toml` in `dir`.
pub fn write_scene(dir: &Path, text: &str) -> PathBuf {
    write_file(dir, "scene.toml", text)
}
