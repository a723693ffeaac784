//! Checkpoint, resume and interruption of `mcrender render` (issue 10 items 2 and 3): a
//! render killed with SIGKILL after a checkpoint, or stopped with SIGINT / SIGTERM, resumes
//! to the same bytes as a render never stopped; checkpoints that do not match are refused
//! with exit 2 and nothing overwritten; no temporary file is ever left.

mod common;

use std::path::{Path, PathBuf};
use std::process::Child;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use common::checkpoint::{
    assert_continued, assert_partial, assert_resumes_to, exr_count, interrupt, kill, kill_at_checkpoint, rendered,
    resume, run, spawn, temp_files, wait_for, wait_for_progress,
};
use common::{scene, stderr};

const SPP: &str = "300";
const RES: &str = "24x24";
/// The film size of [`RES`].
const FILM: (u32, u32) = (24, 24);
/// Checkpoints to `c.ckpt` every 50 ms.
const EVERY_50MS: [&str; 4] = ["--checkpoint", "c.ckpt", "--checkpoint-every", "50ms"];

/// `mcrender render` of the scene `file` at [`SPP`] and [`RES`] to `out`.
fn spp_args(file: &str, out: &str) -> Vec<String> {
    ["render", file, "--spp", SPP, "--resolution", RES, "-o", out, "-q"]
        .iter()
        .map(|s| s.to_string())
        .collect()
}

/// `mcrender render` of the repository's Cornell box at [`SPP`] and [`RES`] to `out`.
fn base_args(out: &str) -> Vec<String> {
    spp_args(&scene("cornell-box/scene-v4.pbrt"), out)
}

/// The uninterrupted render's bytes (rendered once for all tests).
fn reference() -> &'static [u8] {
    static REF: OnceLock<Vec<u8>> = OnceLock::new();
    REF.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        rendered(dir.path(), &base_args("ref.exr"), "ref.exr")
    })
}

#[test]
fn sigkill_after_the_first_checkpoint_resumes_to_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    killed_and_resumed(dir.path(), &base_args("out.exr"), wait_for, reference());
}

/// Render `args` in `dir` checkpointing every 100 ms on 2 threads, SIGKILL it once `wait`
/// saw its checkpoint, and check that it left no image, that the resume on 1 thread (a
/// different thread count does not change the image) is `reference` byte for byte,
/// removes its checkpoint and leaves no temporary file. Returns the resume's stderr.
fn killed_and_resumed(dir: &Path, args: &[String], wait: fn(&Path, &mut Child), reference: &[u8]) -> String {
    let ckpt = dir.join("c.ckpt");
    let every = [
        "--checkpoint",
        "c.ckpt",
        "--checkpoint-every",
        "100ms",
        "--threads",
        "2",
    ];
    let mut child = spawn(dir, args, &every);
    wait(&ckpt, &mut child);
    kill(child);
    assert!(!dir.join("out.exr").exists());
    let err = assert_resumes_to(dir, "c.ckpt", &["--threads", "1"], reference);
    assert!(!ckpt.exists(), "a finished render removes its checkpoint");
    assert_eq!(temp_files(dir), Vec::<String>::new());
    err
}

fn interrupted_render(sig: &str, code: i32) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let mut child = spawn(dir.path(), &base_args("out.exr"), &EVERY_50MS);
    // The first checkpoint shows the render is under way with its handlers installed.
    wait_for(&dir.path().join("c.ckpt"), &mut child);
    let err = interrupt(child, sig, code, dir.path());
    assert!(err.contains("samples per pixel") && err.contains("--resume"), "{err}");
    dir
}

#[test]
fn sigint_writes_a_partial_exr_and_a_checkpoint_that_resume_identically() {
    let reference = reference();
    let dir = interrupted_render("-INT", 130);
    let out = dir.path().join("out.exr");
    let spp = exr_count(&out, "mcrender.samplesPerPixel");
    let requested: u64 = SPP.parse().unwrap();
    assert!(spp < requested, "{spp} samples per pixel");
    assert_eq!(exr_count(&out, "mcrender.samplesRequested"), requested);
    assert_partial(&out, FILM, spp > 0);
    assert_resumes_to(dir.path(), "c.ckpt", &[], reference);
}

#[test]
fn sigterm_exits_143_and_running_the_same_command_again_continues() {
    let reference = reference();
    let dir = interrupted_render("-TERM", 143);
    let o = run(dir.path(), &base_args("out.exr"), &["--checkpoint", "c.ckpt"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("continuing the render"));
    assert_eq!(std::fs::read(dir.path().join("out.exr")).unwrap(), reference);
}

/// A directory with a copy of the scene, an interrupted render's checkpoint `c.ckpt`, and
/// a sentinel `out.exr`.
fn checkpointed_copy() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("scene.pbrt");
    std::fs::copy(scene("cornell-box/scene-v4.pbrt"), &scene_path).unwrap();
    let child = spawn(dir.path(), &spp_args("scene.pbrt", "out.exr"), &EVERY_50MS);
    kill_at_checkpoint(child, &dir.path().join("c.ckpt"));
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
    let other = run(
        d,
        &spp_args("scene.pbrt", "out.exr"),
        &["--seed", "99", "--checkpoint", "c.ckpt"],
    );
    assert_refused(&other, d, &good, "other settings");
    let text = std::fs::read_to_string(&scene_path).unwrap();
    let text = text.replacen("WorldBegin", "WorldBegin\nAttributeBegin AttributeEnd", 1);
    std::fs::write(d.join("foreign.pbrt"), text).unwrap();
    let foreign = run(d, &spp_args("foreign.pbrt", "out.exr"), &["--checkpoint", "c.ckpt"]);
    assert_refused(&foreign, d, &good, "another scene");

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
    let cornell = scene("cornell-box/scene-v4.pbrt");
    let args = |out: &str| -> Vec<String> {
        let a = ["render", &cornell, "--integrator", "lightpath", "--spp", "200"];
        a.iter()
            .chain(&["--resolution", RES, "-o", out, "-q"])
            .map(|s| s.to_string())
            .collect()
    };
    let reference = rendered(d, &args("ref.exr"), "ref.exr");
    kill_at_checkpoint(spawn(d, &args("out.exr"), &EVERY_50MS), &d.join("c.ckpt"));
    assert_resumes_to(d, "c.ckpt", &["--threads", "1"], &reference);
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

/// The uninterrupted render of the scene file `file` in `dir` (written to `ref.exr`).
fn file_reference(dir: &Path, file: &str) -> Vec<u8> {
    rendered(dir, &file_args(file, "ref.exr"), "ref.exr")
}

/// SPPM's per-pixel state (radii, photon counts, flux, direct light) and its iteration
/// count are checkpointed between iterations: killed with SIGKILL and resumed on another
/// thread count, the image is byte for byte the uninterrupted one.
#[test]
fn sppm_killed_after_a_checkpoint_resumes_to_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    sppm_scene(d);
    let reference = file_reference(d, "sppm.pbrt");
    let err = killed_and_resumed(d, &file_args("sppm.pbrt", "out.exr"), wait_for, &reference);
    assert_continued(&err, "iteration", 100);
}

/// SIGINT stops SPPM between iterations: a readable partial EXR recording the iterations
/// done, a checkpoint, exit 130; resuming finishes to the uninterrupted bytes.
#[test]
fn sppm_sigint_writes_a_partial_exr_and_a_checkpoint_that_resume_identically() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    sppm_scene(d);
    let reference = file_reference(d, "sppm.pbrt");
    let mut child = spawn(d, &file_args("sppm.pbrt", "out.exr"), &EVERY_50MS);
    wait_for(&d.join("c.ckpt"), &mut child);
    let err = interrupt(child, "-INT", 130, d);
    assert!(err.contains("SPPM iterations") && err.contains("--resume"), "{err}");
    let out = d.join("out.exr");
    let done = exr_count(&out, "mcrender.iterations");
    assert!((1..100).contains(&done), "{done} iterations");
    assert_eq!(exr_count(&out, "mcrender.iterationsRequested"), 100);
    assert_partial(&out, FILM, true);
    assert_ne!(std::fs::read(&out).unwrap(), reference, "a partial render differs");
    let err = assert_resumes_to(d, "c.ckpt", &[], &reference);
    assert_eq!(assert_continued(&err, "iteration", 100), done);
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
    let err = killed_and_resumed(d, &file_args("mlt.pbrt", "out.exr"), wait_for_progress, reference);
    assert_continued(&err, "mutation", MLT_MUTATIONS);
}

/// SIGINT stops MLT after a whole mutation of each chain: a readable partial EXR recording
/// the mutations made, a checkpoint, exit 130; resuming finishes to the uninterrupted bytes.
#[test]
fn mlt_sigint_writes_a_partial_exr_and_a_checkpoint_that_resume_identically() {
    let reference = mlt_reference();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    mlt_scene(d);
    let mut child = spawn(d, &file_args("mlt.pbrt", "out.exr"), &EVERY_50MS);
    wait_for_progress(&d.join("c.ckpt"), &mut child);
    let err = interrupt(child, "-INT", 130, d);
    assert!(err.contains("MLT mutations") && err.contains("--resume"), "{err}");
    let out = d.join("out.exr");
    let done = exr_count(&out, "mcrender.mutations");
    assert!((1..MLT_MUTATIONS).contains(&done), "{done} mutations");
    assert_eq!(exr_count(&out, "mcrender.mutationsRequested"), MLT_MUTATIONS);
    assert_partial(&out, FILM, true);
    assert_ne!(std::fs::read(&out).unwrap(), reference, "a partial render differs");
    let err = assert_resumes_to(d, "c.ckpt", &[], reference);
    assert_eq!(assert_continued(&err, "mutation", MLT_MUTATIONS), done);
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
    let mut child = spawn(d, &file_args("mlt.pbrt", "out.exr"), &[]);
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
    let err = interrupt(child, "-TERM", 143, d);
    assert!(err.contains("SIGTERM") && err.contains("out.exr.ckpt"), "{err}");
    let out = d.join("out.exr");
    assert!(exr_count(&out, "mcrender.mutations") < MLT_MUTATIONS);
    assert_partial(&out, FILM, false);
    assert_resumes_to(d, "out.exr.ckpt", &[], reference);
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
    let o = run(p, &file_args("mlt.pbrt", "out.exr"), &["--checkpoint", "c.ckpt"]);
    assert_refused(&o, p, &path_ckpt, "a path checkpoint for mlt");

    // An MLT checkpoint, offered to a path render, another MLT render, and after an edit.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    mlt_scene(d);
    std::fs::copy(scene("cornell-box/scene-v4.pbrt"), d.join("path.pbrt")).unwrap();
    kill_at_checkpoint(
        spawn(d, &file_args("mlt.pbrt", "out.exr"), &EVERY_50MS),
        &d.join("c.ckpt"),
    );
    std::fs::write(d.join("out.exr"), b"sentinel").unwrap();
    let good = std::fs::read(d.join("c.ckpt")).unwrap();
    let run = |file: &str, extra: &[&str]| {
        run(
            d,
            &file_args(file, "out.exr"),
            &[&["--checkpoint", "c.ckpt"], extra].concat(),
        )
    };
    assert_refused(&run("path.pbrt", &[]), d, &good, "an mlt checkpoint for path");
    assert_refused(&run("mlt.pbrt", &["--seed", "99"]), d, &good, "another seed");
    let mut text = std::fs::read_to_string(d.join("mlt.pbrt")).unwrap();
    text.push_str("\n# edited\n");
    std::fs::write(d.join("mlt.pbrt"), text).unwrap();
    assert_refused(&resume(d, "c.ckpt", &[]), d, &good, "edited scene");
}
