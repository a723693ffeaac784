//! Where the shared test scenes are (`cornell-box/`, `coffee/`, `veach-mis/`, ...), for the
//! tests of every crate that reads them: this file is included by `#[path]` from
//! `crates/formats/tests/pbrt_scenes.rs` and `crates/cli/tests/common/mod.rs`, so the
//! lookup and its failure are written once.

use std::path::{Path, PathBuf};

/// The shared scene directory: `MCRENDER_SCENES`, else `shared/scenes` beside the clone.
/// Without either the test `test` fails, unless `MCRENDER_SKIP_SHARED_SCENES` is set: then
/// it is skipped with a visible `SKIPPED` line (issue 10: skipped tests used to report "ok"
/// in 0.00 s when the scenes were missing, the skip message swallowed by the test harness).
pub fn shared_scenes_dir(test: &str) -> Option<PathBuf> {
    // Written to stderr directly (not eprintln!) so that the test harness does not capture
    // it: a skipped test must be seen.
    use std::io::Write as _;
    if let Some(dir) = std::env::var_os("MCRENDER_SCENES") {
        return Some(PathBuf::from(dir));
    }
    // Beside a clone, as CI lays it out (`.ci/run` sets MCRENDER_SCENES the same way); the
    // including crate is `crates/NAME`, two levels below the clone.
    let beside = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes");
    if beside.is_dir() {
        return Some(beside);
    }
    if std::env::var_os("MCRENDER_SKIP_SHARED_SCENES").is_some() {
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED {test}: MCRENDER_SCENES is not set and MCRENDER_SKIP_SHARED_SCENES is"
        );
        return None;
    }
    panic!(
        "{test} needs the shared scenes: set MCRENDER_SCENES to the directory holding cornell-box/, coffee/ and veach-mis/ (or set MCRENDER_SKIP_SHARED_SCENES=1 to skip these tests on purpose)"
    );
}
