//! Helpers of the checkpoint tests: run or spawn a render, wait for its checkpoint, stop it
//! (SIGKILL, SIGINT, SIGTERM), resume it and compare its bytes with the uninterrupted
//! render's, read the counts a checkpoint or a partial EXR records.

use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use super::{mcrender, stderr};

/// Run `mcrender` with `args` then `extra` in `dir`, to its end.
pub fn run(dir: &Path, args: &[String], extra: &[&str]) -> Output {
    let mut a: Vec<&str> = args.iter().map(String::as_str).collect();
    a.extend(extra);
    mcrender(&a, dir)
}

/// The bytes of `file` in `dir` written by a render with `args` (which must succeed).
pub fn rendered(dir: &Path, args: &[String], file: &str) -> Vec<u8> {
    let o = run(dir, args, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::read(dir.join(file)).unwrap()
}

/// Start `mcrender` with `args` then `extra` in `dir` (standard error piped).
pub fn spawn(dir: &Path, args: &[String], extra: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_mcrender"))
        .args(args)
        .args(extra)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("mcrender starts")
}

/// Wait until the render `child` has written the checkpoint `path`.
pub fn wait_for(path: &Path, child: &mut Child) {
    let start = Instant::now();
    while !path.exists() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the render ended before its first checkpoint"
        );
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no checkpoint after 2 minutes"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Wait for a checkpoint at `path` that records some progress (`samples_done` > 0 in its
/// header: a render of its own driver may save one before its first sample, e.g. after
/// MLT's bootstrap).
pub fn wait_for_progress(path: &Path, child: &mut Child) {
    let start = Instant::now();
    loop {
        wait_for(path, child);
        let bytes = std::fs::read(path).unwrap_or_default();
        let text = String::from_utf8_lossy(&bytes[..bytes.len().min(1 << 16)]).into_owned();
        let done: u64 = text
            .split("\"samples_done\":")
            .nth(1)
            .and_then(|rest| rest.split(|c: char| !c.is_ascii_digit()).next())
            .and_then(|n| n.parse().ok())
            .unwrap_or(0);
        if done > 0 {
            return;
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no progress checkpointed after 2 minutes"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// SIGKILL the render `child` and check it died of it (it had not finished).
pub fn kill(mut child: Child) {
    child.kill().unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(9), "{status:?}");
}

/// SIGKILL the render `child` once it has written the checkpoint `path`.
pub fn kill_at_checkpoint(mut child: Child, path: &Path) {
    wait_for(path, &mut child);
    kill(child);
}

/// Send `sig` (`-INT`, `-TERM`) to `child`.
pub fn signal(child: &Child, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(ok.success());
}

/// Send `sig` to the render `child` in `dir`, check it exits with `code` leaving no
/// temporary file, and return its standard error.
pub fn interrupt(child: Child, sig: &str, code: i32, dir: &Path) -> String {
    signal(&child, sig);
    let o = child.wait_with_output().unwrap();
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(code), "{err}");
    assert_eq!(temp_files(dir), Vec::<String>::new());
    err
}

/// Names in `dir` that look like temporary files.
pub fn temp_files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.') || n.contains("tmp"))
        .collect()
}

/// `mcrender render --resume CKPT -q` with `extra` in `dir`.
pub fn resume(dir: &Path, ckpt: &str, extra: &[&str]) -> Output {
    let mut a = vec!["render", "--resume", ckpt, "-q"];
    a.extend(extra);
    mcrender(&a, dir)
}

/// Resume the checkpoint `ckpt` in `dir` with `extra`, check it succeeds and that its
/// `out.exr` is `reference` byte for byte, and return its standard error.
pub fn assert_resumes_to(dir: &Path, ckpt: &str, extra: &[&str], reference: &[u8]) -> String {
    let o = resume(dir, ckpt, extra);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(dir.join("out.exr")).unwrap(), reference);
    stderr(&o)
}

/// The resume continued the saved state (it did not start again): the `unit` (iteration,
/// mutation) it continued from, between 1 and `total` - 1.
pub fn assert_continued(err: &str, unit: &str, total: u64) -> u64 {
    let k: u64 = err
        .split(&format!("continued from {unit} "))
        .nth(1)
        .and_then(|rest| rest.split(')').next())
        .and_then(|k| k.parse().ok())
        .unwrap_or_else(|| panic!("the resume says where it continued from: {err}"));
    assert!((1..total).contains(&k), "{err}");
    k
}

/// The count under `key` in an EXR's header.
pub fn exr_count(path: &Path, key: &str) -> u64 {
    let meta = mcrender_formats::image_io::read_exr_metadata(path).unwrap();
    meta.iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.parse().unwrap())
        .unwrap_or_else(|| panic!("{key} in the EXR header: {meta:?}"))
}

/// Check that the partial image `path` is `width` x `height` and, when `lit`, that some
/// pixel has light.
pub fn assert_partial(path: &Path, (width, height): (u32, u32), lit: bool) {
    let partial = mcrender_formats::image_io::read_exr(path).unwrap();
    assert_eq!((partial.width, partial.height), (width, height));
    if lit {
        assert!(
            partial.pixels.iter().any(|p| p.r > 0.0),
            "the partial image has content"
        );
    }
}
