//! Helpers shared by the `wearsim` binary's test files. Each test file compiles this module on
//! its own and uses part of it, hence `dead_code` allowed.
#![allow(dead_code)]

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

/// A fresh, empty temporary folder named after `tag` and this test process.
pub fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("wearsim-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

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

/// `wearsim run SCENE --out OUT`.
pub fn run_into(scene: &str, out: &Path) -> Output {
    wearsim(&["run", scene, "--out", out.to_str().unwrap()])
}

pub fn write_scene(dir: &Path, text: &str) -> PathBuf {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    path
}
