//! Helpers shared by the CLI tests: run the built binary, find the repository's scenes;
//! those of the checkpoint tests in [`checkpoint`].
#![allow(dead_code)]

pub mod agreement;
pub mod checkpoint;
#[path = "../../../formats/tests/common/shared_scenes.rs"]
pub mod shared_scenes;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Run `mcrender` with `args` in `dir`.
pub fn mcrender(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mcrender"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("mcrender runs")
}

/// Path of a scene under the repository's `scenes/` directory.
pub fn scene(rel: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(rel)
        .display()
        .to_string()
}

/// The command's standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}
