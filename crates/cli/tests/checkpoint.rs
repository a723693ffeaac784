//! Checkpoint, resume and interruption of `mcrender render` (issue 10 items 2 and 3): a
//! render killed with SIGKILL after a checkpoint, or stopped with SIGINT / SIGTERM, resumes
//! to the same bytes as a render never stopped; checkpoints that do not match are refused
//! with exit 2 and nothing overwritten; no temporary file is ever left.

mod common;

use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use common::{mcrender, scene, stderr};

const SPP: &str = "300";
const RES: &str = "24x24";

fn base_args(out: &str) -> Vec<String> {
    [
        &scene("cornell-box/scene-v4.pbrt"),
        "--spp",
        SPP,
        "--resolution",
        RES,
        "-o",
        out,
        "-q",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

/// The uninterrupted render's bytes (rendered once for all tests).
fn reference() -> &'static [u8] {
    static REF: OnceLock<Vec<u8>> = OnceLock::new();
    REF.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let mut a = vec!["render".to_string()];
        a.extend(base_args("ref.exr"));
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        let o = mcrender(&a, dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(dir.path().join("ref.exr")).unwrap()
    })
}

fn spawn(dir: &Path, extra: &[&str]) -> Child {
    let mut args = vec!["render".to_string()];
    args.extend(base_args("out.exr"));
    args.extend(extra.iter().map(|s| s.to_string()));
    Command::new(env!("CARGO_BIN_EXE_mcrender"))
        .args(&args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("mcrender starts")
}

fn wait_for(path: &Path, child: &mut Child) {
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
fn wait_for_progress(path: &Path, child: &mut Child) {
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

fn signal(child: &Child, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(ok.success());
}

/// Names in `dir` that look like temporary files.
fn temp_files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.') || n.contains("tmp"))
        .collect()
}

fn resume(dir: &Path, ckpt: &str, extra: &[&str]) -> std::process::Output {
    let mut a = vec!["render", "--resume", ckpt, "-q"];
    a.extend(extra);
    mcrender(&a, dir)
}

#[test]
fn sigkill_after_the_first_checkpoint_resumes_to_the_same_bytes() {
    let reference = reference();
    let dir = tempfile::tempdir().unwrap();
    let ckpt = dir.path().join("c.ckpt");
    let mut child = spawn(
        dir.path(),
        &[
            "--checkpoint",
            "c.ckpt",
            "--checkpoint-every",
            "100ms",
            "--threads",
            "2",
        ],
    );
    wait_for(&ckpt, &mut child);
    child.kill().unwrap(); // SIGKILL
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(9), "{status:?}");
    assert!(!dir.path().join("out.exr").exists());
    // A different thread count on resume does not change the image.
    let o = resume(dir.path(), "c.ckpt", &["--threads", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(dir.path().join("out.exr")).unwrap(), reference);
    assert!(!ckpt.exists(), "a finished render removes its checkpoint");
    assert_eq!(temp_files(dir.path()), Vec::<String>::new());
}

fn interrupted_render(sig: &str, code: i32) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let mut child = spawn(dir.path(), &["--checkpoint", "c.ckpt", "--checkpoint-every", "50ms"]);
    // The first checkpoint shows the render is under way with its handlers installed.
    wait_for(&dir.path().join("c.ckpt"), &mut child);
    signal(&child, sig);
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(code), "{err}");
    assert!(err.contains("samples per pixel") && err.contains("--resume"), "{err}");
    assert_eq!(temp_files(dir.path()), Vec::<String>::new());
    dir
}

#[test]
fn sigint_writes_a_partial_exr_and_a_checkpoint_that_resume_identically() {
    let reference = reference();
    let dir = interrupted_render("-INT", 130);
    let out = dir.path().join("out.exr");
    let meta = mcrender_formats::image_io::read_exr_metadata(&out).unwrap();
    let spp: u32 = meta
        .iter()
        .find(|(k, _)| k == "mcrender.samplesPerPixel")
        .map(|(_, v)| v.parse().unwrap())
        .expect("sample count in the EXR header");
    assert!(spp < 300, "{meta:?}");
    assert!(meta.contains(&("mcrender.samplesRequested".into(), SPP.into())));
    let partial = mcrender_formats::image_io::read_exr(&out).unwrap();
    assert_eq!((partial.width, partial.height), (24, 24));
    if spp > 0 {
        assert!(
            partial.pixels.iter().any(|p| p.r > 0.0),
            "the partial image has content"
        );
    }
    let o = resume(dir.path(), "c.ckpt", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(&out).unwrap(), reference);
}

#[test]
fn sigterm_exits_143_and_running_the_same_command_again_continues() {
    let reference = reference();
    let dir = interrupted_render("-TERM", 143);
    let o = spawn(dir.path(), &["--checkpoint", "c.ckpt"])
        .wait_with_output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("continuing the render"));
    assert_eq!(std::fs::read(dir.path().join("out.exr")).unwrap(), reference);
}

/// A directory with a copy of the scene, an interrupted render's checkpoint `c.ckpt`, and
/// a sentinel `out.exr`.
fn checkpointed_copy() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("scene.pbrt");
    std::fs::copy(scene("cornell-box/scene-v4.pbrt"), &scene_path).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_mcrender"))
        .args([
            "render",
            "scene.pbrt",
            "--spp",
            SPP,
            "--resolution",
            RES,
            "-o",
            "out.exr",
            "-q",
        ])
        .args(["--checkpoint", "c.ckpt", "--checkpoint-every", "50ms"])
        .current_dir(dir.path())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for(&dir.path().join("c.ckpt"), &mut child);
    child.kill().unwrap();
    child.wait().unwrap();
    std::fs::write(dir.path().join("out.exr"), b"sentinel").unwrap();
    (dir, scene_path)
}

fn assert_refused(o: &std::process::Output, dir: &Path, ckpt: &[u8], what: &str) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{what}: {err}");
    assert_eq!(err.trim().lines().count(), 1, "{what}: one line: {err}");
    assert!(err.contains("checkpoint"), "{what}: {err}");
    assert_eq!(
        std::fs::read(dir.join("out.exr")).unwrap(),
        b"sentinel",
        "{what}: output overwritten"
    );
    assert_eq!(
        std::fs::read(dir.join("c.ckpt")).unwrap(),
        ckpt,
        "{what}: checkpoint overwritten"
    );
    assert_eq!(temp_files(dir), Vec::<String>::new(), "{what}");
}

#[test]
fn mismatched_truncated_and_foreign_checkpoints_are_refused() {
    let (dir, scene_path) = checkpointed_copy();
    let d = dir.path();
    let good = std::fs::read(d.join("c.ckpt")).unwrap();

    // Truncated.
    std::fs::write(d.join("c.ckpt"), &good[..good.len() / 2]).unwrap();
    let cut = good[..good.len() / 2].to_vec();
    assert_refused(&resume(d, "c.ckpt", &[]), d, &cut, "truncated");
    std::fs::write(d.join("c.ckpt"), &good).unwrap();

    // Another scene's checkpoint under this render's --checkpoint name.
    let other = [
        "render",
        "scene.pbrt",
        "--spp",
        SPP,
        "--resolution",
        RES,
        "-o",
        "out.exr",
        "-q",
        "--seed",
        "99",
        "--checkpoint",
        "c.ckpt",
    ];
    assert_refused(&mcrender(&other, d), d, &good, "other settings");
    let text = std::fs::read_to_string(&scene_path).unwrap();
    let text = text.replacen("WorldBegin", "WorldBegin\nAttributeBegin AttributeEnd", 1);
    std::fs::write(d.join("foreign.pbrt"), text).unwrap();
    let foreign = [
        "render",
        "foreign.pbrt",
        "--spp",
        SPP,
        "--resolution",
        RES,
        "-o",
        "out.exr",
        "-q",
        "--checkpoint",
        "c.ckpt",
    ];
    assert_refused(&mcrender(&foreign, d), d, &good, "another scene");

    // Wrong fingerprint: the scene changed since the checkpoint.
    let mut text = std::fs::read_to_string(&scene_path).unwrap();
    text.push_str("\n# edited\n");
    std::fs::write(&scene_path, text).unwrap();
    assert_refused(&resume(d, "c.ckpt", &[]), d, &good, "edited scene");

    // Not a checkpoint at all.
    let o = resume(d, "out.exr", &[]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read(d.join("out.exr")).unwrap(), b"sentinel");
}

/// The light tracer splats into other pixels: its splat sums are checkpointed and continued
/// too, so a killed and resumed render still matches an uninterrupted one byte for byte.
#[test]
fn a_splatting_integrator_resumes_to_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = |out: &'static str| {
        vec![
            "render".to_string(),
            scene("cornell-box/scene-v4.pbrt"),
            "--integrator".into(),
            "lightpath".into(),
            "--spp".into(),
            "200".into(),
            "--resolution".into(),
            RES.into(),
            "-o".into(),
            out.into(),
            "-q".into(),
        ]
    };
    let r = args("ref.exr");
    let o = mcrender(&r.iter().map(String::as_str).collect::<Vec<_>>(), d);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut child = Command::new(env!("CARGO_BIN_EXE_mcrender"))
        .args(args("out.exr"))
        .args(["--checkpoint", "c.ckpt", "--checkpoint-every", "50ms"])
        .current_dir(d)
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for(&d.join("c.ckpt"), &mut child);
    child.kill().unwrap();
    child.wait().unwrap();
    let o = resume(d, "c.ckpt", &["--threads", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(d.join("out.exr")).unwrap(),
        std::fs::read(d.join("ref.exr")).unwrap()
    );
}

/// The Cornell box rendered by SPPM, long enough (100 iterations) to be caught mid-render.
fn sppm_scene(dir: &Path) {
    let text = std::fs::read_to_string(scene("cornell-box/scene-v4.pbrt")).unwrap();
    let sppm = "Integrator \"sppm\" \"integer numiterations\" [ 100 ] \
                \"integer photonsperiteration\" [ 20000 ] \"float radius\" [ 0.05 ]";
    let text = text.replacen("Integrator \"path\"", sppm, 1);
    assert!(text.contains("\"sppm\""), "the scene names its integrator");
    std::fs::write(dir.join("sppm.pbrt"), text).unwrap();
}

/// Arguments rendering the scene file `file` (in the test's directory) to `out`.
fn file_args(file: &str, out: &str) -> Vec<String> {
    ["render", file, "--resolution", RES, "-o", out, "-q"]
        .iter()
        .map(|s| s.to_string())
        .collect()
}

fn spawn_file(dir: &Path, file: &str, extra: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_mcrender"))
        .args(file_args(file, "out.exr"))
        .args(extra)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("mcrender starts")
}

fn file_reference(dir: &Path, file: &str) -> Vec<u8> {
    let a = file_args(file, "ref.exr");
    let o = mcrender(&a.iter().map(String::as_str).collect::<Vec<_>>(), dir);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::read(dir.join("ref.exr")).unwrap()
}

fn spawn_sppm(dir: &Path, extra: &[&str]) -> Child {
    spawn_file(dir, "sppm.pbrt", extra)
}

fn sppm_reference(dir: &Path) -> Vec<u8> {
    file_reference(dir, "sppm.pbrt")
}

/// SPPM's per-pixel state (radii, photon counts, flux, direct light) and its iteration
/// count are checkpointed between iterations: killed with SIGKILL and resumed on another
/// thread count, the image is byte for byte the uninterrupted one.
#[test]
fn sppm_killed_after_a_checkpoint_resumes_to_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    sppm_scene(d);
    let reference = sppm_reference(d);
    let mut child = spawn_sppm(
        d,
        &[
            "--checkpoint",
            "c.ckpt",
            "--checkpoint-every",
            "100ms",
            "--threads",
            "2",
        ],
    );
    wait_for(&d.join("c.ckpt"), &mut child);
    child.kill().unwrap();
    assert_eq!(child.wait().unwrap().signal(), Some(9));
    assert!(!d.join("out.exr").exists());
    let o = resume(d, "c.ckpt", &["--threads", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_continued(&stderr(&o), "iteration", 100);
    assert_eq!(std::fs::read(d.join("out.exr")).unwrap(), reference);
    assert!(!d.join("c.ckpt").exists(), "a finished render removes its checkpoint");
    assert_eq!(temp_files(d), Vec::<String>::new());
}

/// SIGINT stops SPPM between iterations: a readable partial EXR recording the iterations
/// done, a checkpoint, exit 130; resuming finishes to the uninterrupted bytes.
#[test]
fn sppm_sigint_writes_a_partial_exr_and_a_checkpoint_that_resume_identically() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    sppm_scene(d);
    let reference = sppm_reference(d);
    let mut child = spawn_sppm(d, &["--checkpoint", "c.ckpt", "--checkpoint-every", "50ms"]);
    wait_for(&d.join("c.ckpt"), &mut child);
    signal(&child, "-INT");
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(err.contains("SPPM iterations") && err.contains("--resume"), "{err}");
    assert_eq!(temp_files(d), Vec::<String>::new());
    let out = d.join("out.exr");
    let meta = mcrender_formats::image_io::read_exr_metadata(&out).unwrap();
    let done: u32 = meta
        .iter()
        .find(|(k, _)| k == "mcrender.iterations")
        .map(|(_, v)| v.parse().unwrap())
        .expect("iteration count in the EXR header");
    assert!((1..100).contains(&done), "{meta:?}");
    assert!(meta.contains(&("mcrender.iterationsRequested".into(), "100".into())));
    let partial = mcrender_formats::image_io::read_exr(&out).unwrap();
    assert!(
        partial.pixels.iter().any(|p| p.r > 0.0),
        "the partial image has content"
    );
    assert_ne!(std::fs::read(&out).unwrap(), reference, "a partial render differs");
    let o = resume(d, "c.ckpt", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(assert_continued(&stderr(&o), "iteration", 100), u64::from(done));
    assert_eq!(std::fs::read(&out).unwrap(), reference);
}

/// The resume continued the saved state (it did not start again): the `unit` (iteration,
/// mutation) it continued from, between 1 and `total` - 1.
fn assert_continued(err: &str, unit: &str, total: u64) -> u64 {
    let k: u64 = err
        .split(&format!("continued from {unit} "))
        .nth(1)
        .and_then(|rest| rest.split(')').next())
        .and_then(|k| k.parse().ok())
        .unwrap_or_else(|| panic!("the resume says where it continued from: {err}"));
    assert!((1..total).contains(&k), "{err}");
    k
}

/// The Cornell box rendered by MLT at depth 5: 24x24 pixels x 2000 mutations per pixel
/// over 64 chains (1.15 M mutations, 1 to 4 s on 2 cores), long enough to be caught
/// mid-render.
fn mlt_scene(dir: &Path) {
    let text = std::fs::read_to_string(scene("cornell-box/scene-v4.pbrt")).unwrap();
    let mlt = "Integrator \"mlt\" \"integer bootstrapsamples\" [ 2000 ] \"integer chains\" [ 64 ] \
               \"integer mutationsperpixel\" [ 2000 ]";
    let text = text.replacen("Integrator \"path\"", mlt, 1).replacen(
        "\"integer maxdepth\" [ 65 ]",
        "\"integer maxdepth\" [ 5 ]",
        1,
    );
    assert!(
        text.contains("\"mlt\"") && text.contains("[ 5 ]"),
        "the scene names its integrator"
    );
    std::fs::write(dir.join("mlt.pbrt"), text).unwrap();
}

/// Mutations of [`mlt_scene`] at [`RES`].
const MLT_MUTATIONS: u64 = 24 * 24 * 2000;

/// The uninterrupted MLT render's bytes (rendered once for all tests).
fn mlt_reference() -> &'static [u8] {
    static REF: OnceLock<Vec<u8>> = OnceLock::new();
    REF.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        mlt_scene(dir.path());
        file_reference(dir.path(), "mlt.pbrt")
    })
}

/// MLT's state (b, every chain's primary sample space state, generators and current path,
/// the splat sums) is checkpointed between steps of mutations: killed with SIGKILL and
/// resumed on another thread count, the image is byte for byte the uninterrupted one.
#[test]
fn mlt_killed_after_a_checkpoint_resumes_to_the_same_bytes() {
    let reference = mlt_reference();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    mlt_scene(d);
    let mut child = spawn_file(
        d,
        "mlt.pbrt",
        &[
            "--checkpoint",
            "c.ckpt",
            "--checkpoint-every",
            "100ms",
            "--threads",
            "2",
        ],
    );
    wait_for_progress(&d.join("c.ckpt"), &mut child);
    child.kill().unwrap();
    assert_eq!(child.wait().unwrap().signal(), Some(9));
    assert!(!d.join("out.exr").exists());
    let o = resume(d, "c.ckpt", &["--threads", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_continued(&stderr(&o), "mutation", MLT_MUTATIONS);
    assert_eq!(std::fs::read(d.join("out.exr")).unwrap(), reference);
    assert!(!d.join("c.ckpt").exists(), "a finished render removes its checkpoint");
    assert_eq!(temp_files(d), Vec::<String>::new());
}

/// The count under `key` in an EXR's header.
fn exr_count(path: &Path, key: &str) -> u64 {
    let meta = mcrender_formats::image_io::read_exr_metadata(path).unwrap();
    meta.iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.parse().unwrap())
        .unwrap_or_else(|| panic!("{key} in the EXR header: {meta:?}"))
}

/// SIGINT stops MLT after a whole mutation of each chain: a readable partial EXR recording
/// the mutations made, a checkpoint, exit 130; resuming finishes to the uninterrupted bytes.
#[test]
fn mlt_sigint_writes_a_partial_exr_and_a_checkpoint_that_resume_identically() {
    let reference = mlt_reference();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    mlt_scene(d);
    let mut child = spawn_file(d, "mlt.pbrt", &["--checkpoint", "c.ckpt", "--checkpoint-every", "50ms"]);
    wait_for_progress(&d.join("c.ckpt"), &mut child);
    signal(&child, "-INT");
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(err.contains("MLT mutations") && err.contains("--resume"), "{err}");
    assert_eq!(temp_files(d), Vec::<String>::new());
    let out = d.join("out.exr");
    let done = exr_count(&out, "mcrender.mutations");
    assert!((1..MLT_MUTATIONS).contains(&done), "{done} mutations");
    assert_eq!(exr_count(&out, "mcrender.mutationsRequested"), MLT_MUTATIONS);
    let partial = mcrender_formats::image_io::read_exr(&out).unwrap();
    assert_eq!((partial.width, partial.height), (24, 24));
    assert!(
        partial.pixels.iter().any(|p| p.r > 0.0),
        "the partial image has content"
    );
    assert_ne!(std::fs::read(&out).unwrap(), reference, "a partial render differs");
    let o = resume(d, "c.ckpt", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(assert_continued(&stderr(&o), "mutation", MLT_MUTATIONS), done);
    assert_eq!(std::fs::read(&out).unwrap(), reference);
}

/// Whether the process has handlers for SIGINT and SIGTERM (Linux: `SigCgt` in
/// /proc/PID/status), i.e. whether a signal now reaches the render rather than ending it.
fn handles_signals(child: &Child) -> bool {
    let status = std::fs::read_to_string(format!("/proc/{}/status", child.id())).unwrap_or_default();
    let caught = status
        .lines()
        .find_map(|l| l.strip_prefix("SigCgt:"))
        .and_then(|m| u64::from_str_radix(m.trim(), 16).ok())
        .unwrap_or(0);
    let bit = |signal: u32| 1u64 << (signal - 1);
    caught & bit(2) != 0 && caught & bit(15) != 0
}

/// Without --checkpoint, SIGTERM still stops MLT with the image so far and a checkpoint
/// beside it (OUTPUT.ckpt), exit 143; that checkpoint resumes to the uninterrupted bytes.
#[test]
fn mlt_sigterm_without_checkpoint_writes_the_partial_image() {
    let reference = mlt_reference();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    mlt_scene(d);
    let mut child = spawn_file(d, "mlt.pbrt", &[]);
    let start = Instant::now();
    while !handles_signals(&child) {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the render ended before it handled signals"
        );
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no signal handlers after 60 s"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    signal(&child, "-TERM");
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(143), "{err}");
    assert!(err.contains("SIGTERM") && err.contains("out.exr.ckpt"), "{err}");
    let out = d.join("out.exr");
    assert!(exr_count(&out, "mcrender.mutations") < MLT_MUTATIONS);
    assert_eq!(mcrender_formats::image_io::read_exr(&out).unwrap().width, 24);
    assert_eq!(temp_files(d), Vec::<String>::new());
    let o = resume(d, "out.exr.ckpt", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(&out).unwrap(), reference);
}

/// An MLT render refuses a path render's checkpoint; a path render refuses an MLT
/// checkpoint; an MLT checkpoint is refused by another MLT render (other seed) and after
/// its scene changed: exit 2, one line, nothing overwritten.
#[test]
fn mlt_checkpoints_of_another_integrator_or_scene_are_refused() {
    // A path render's checkpoint, offered to an MLT render.
    let (path_dir, _) = checkpointed_copy();
    let p = path_dir.path();
    let path_ckpt = std::fs::read(p.join("c.ckpt")).unwrap();
    mlt_scene(p);
    let mut a = file_args("mlt.pbrt", "out.exr");
    a.extend(["--checkpoint".into(), "c.ckpt".into()]);
    let a: Vec<&str> = a.iter().map(String::as_str).collect();
    assert_refused(&mcrender(&a, p), p, &path_ckpt, "a path checkpoint for mlt");

    // An MLT checkpoint, offered to a path render, another MLT render, and after an edit.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    mlt_scene(d);
    std::fs::copy(scene("cornell-box/scene-v4.pbrt"), d.join("path.pbrt")).unwrap();
    let mut child = spawn_file(d, "mlt.pbrt", &["--checkpoint", "c.ckpt", "--checkpoint-every", "50ms"]);
    wait_for(&d.join("c.ckpt"), &mut child);
    child.kill().unwrap();
    child.wait().unwrap();
    std::fs::write(d.join("out.exr"), b"sentinel").unwrap();
    let good = std::fs::read(d.join("c.ckpt")).unwrap();
    let run = |file: &str, extra: &[&str]| {
        let mut a = file_args(file, "out.exr");
        a.extend(["--checkpoint", "c.ckpt"].iter().chain(extra).map(|s| s.to_string()));
        mcrender(&a.iter().map(String::as_str).collect::<Vec<_>>(), d)
    };
    assert_refused(&run("path.pbrt", &[]), d, &good, "an mlt checkpoint for path");
    assert_refused(&run("mlt.pbrt", &["--seed", "99"]), d, &good, "another seed");
    let mut text = std::fs::read_to_string(d.join("mlt.pbrt")).unwrap();
    text.push_str("\n# edited\n");
    std::fs::write(d.join("mlt.pbrt"), text).unwrap();
    assert_refused(&resume(d, "c.ckpt", &[]), d, &good, "edited scene");
}
