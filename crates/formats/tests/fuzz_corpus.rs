//! Replays the fuzzers' kept inputs on stable, through the same entry points as the
//! cargo-fuzz targets (`mcrender_formats::fuzzing`): every file of `fuzz/seeds/TARGET` and
//! `fuzz/regressions/TARGET` (the inputs that once crashed, hung or ran out of memory, each
//! fixed) must return without a panic and quickly.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use mcrender_formats::fuzzing::{run, TARGETS};

/// An input that takes longer than this is a hang (libFuzzer's limit in bench/fuzz.sh is 10 s).
const SLOW: Duration = Duration::from_secs(10);

fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz")
}

fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.is_file())
                .collect()
        })
        .unwrap_or_default();
    out.sort();
    out
}

#[test]
fn every_kept_fuzz_input_replays_without_panic_or_hang() {
    let mut failures = Vec::new();
    let mut replayed = 0;
    for target in TARGETS {
        let mut target_files = 0;
        for kind in ["seeds", "regressions"] {
            for path in files(&fuzz_dir().join(kind).join(target)) {
                let data = std::fs::read(&path).unwrap();
                let start = Instant::now();
                let result = std::panic::catch_unwind(|| run(target, &data));
                let took = start.elapsed();
                if result.is_err() {
                    failures.push(format!("{target}: {} panicked", path.display()));
                } else if took > SLOW {
                    failures.push(format!("{target}: {} took {took:?}", path.display()));
                }
                target_files += 1;
            }
        }
        assert!(target_files > 0, "no seeds or regressions for fuzz target {target}");
        replayed += target_files;
    }
    println!("replayed {replayed} fuzz inputs");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn loader_inputs_split_into_named_files() {
    use mcrender_formats::source::FileSource;
    let files = mcrender_formats::fuzzing::split_files(b"scene\n--8<-- a.ply\nply\n--8<-- t.png\n\x89PNG");
    assert_eq!(files.read(Path::new("fuzz.pbrt")).unwrap(), b"scene");
    assert_eq!(files.read(Path::new("a.ply")).unwrap(), b"ply");
    assert_eq!(files.read(Path::new("t.png")).unwrap(), b"\x89PNG");
}

#[test]
fn loader_seeds_load_so_the_fuzzer_starts_from_working_scenes() {
    use std::sync::Arc;

    use mcrender_formats::pbrt::{load_file_with, LoadOptions};
    for path in files(&fuzz_dir().join("seeds/loader")) {
        let data = std::fs::read(&path).unwrap();
        let options = LoadOptions {
            files: Arc::new(mcrender_formats::fuzzing::split_files(&data)),
            ..LoadOptions::default()
        };
        let scene =
            load_file_with(Path::new("fuzz.pbrt"), &options).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(scene.image_bytes > 0, "{}: no image was read", path.display());
        assert!(!scene.description.shapes.is_empty());
    }
}

/// The Mitsuba seeds (scenes of Mitsuba's test suite, their meshes and images bundled, big
/// ones swapped for small files of the same format; and one of includes, refs, OBJ with
/// MTL, PLY and a bitmap) are read from memory; those mcrender supports load, so the
/// fuzzer starts from working scenes. Prints which do not, and why.
#[test]
fn mitsuba_seeds_load_from_memory() {
    use std::sync::Arc;

    use mcrender_formats::fuzzing::{split_files_with_top, MITSUBA_SCENE};
    use mcrender_formats::limits::LoadLimits;
    let mut loaded = 0;
    let seeds = files(&fuzz_dir().join("seeds/mitsuba"));
    for path in &seeds {
        let files = Arc::new(split_files_with_top(&std::fs::read(path).unwrap(), MITSUBA_SCENE));
        match mcrender_formats::mitsuba::load_file_from(Path::new(MITSUBA_SCENE), &[], LoadLimits::default(), files) {
            Ok(scene) => {
                let d = &scene.description;
                assert!(!(d.shapes.is_empty() && d.instances.is_empty()), "{}", path.display());
                loaded += 1;
            }
            Err(e) => println!("{}: not loaded: {e}", path.display()),
        }
    }
    println!("{loaded} of {} Mitsuba seeds load", seeds.len());
    assert!(
        loaded * 2 > seeds.len(),
        "{loaded} of {} Mitsuba seeds load",
        seeds.len()
    );
    let own = fuzz_dir().join("seeds/mitsuba/include-ref-obj-ply-bitmap");
    let files = Arc::new(split_files_with_top(&std::fs::read(own).unwrap(), MITSUBA_SCENE));
    let scene = mcrender_formats::mitsuba::load_file_from(Path::new(MITSUBA_SCENE), &[], LoadLimits::default(), files)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.description.shapes.len(), 4);
    assert!(scene.image_bytes > 0, "the bitmap was read from memory");
}
