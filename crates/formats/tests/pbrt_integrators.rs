//! `Integrator "lightpath"`, `"sppm"` and `"mlt"`: kinds, SPPM and MLT parameters with pbrt-v4's
//! defaults, and bad parameters reported with their position.

use std::path::Path;

use mcrender_core::scene::{IntegratorKind, MltDesc, SppmDesc};
use mcrender_formats::pbrt::{load_str, LoadedScene};

/// Loads `src` followed by a world with a light (so that only integrator warnings remain).
fn load(src: &str) -> LoadedScene {
    let src = format!("{src}LightSource \"point\"\n");
    match load_str(&src, "scene.pbrt", Path::new("")) {
        Ok(s) => s,
        Err(e) => panic!("{e}"),
    }
}

fn load_err(src: &str) -> String {
    match load_str(src, "scene.pbrt", Path::new("")) {
        Ok(_) => panic!("loaded: {src}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn lightpath_is_its_own_integrator() {
    let s = load("Integrator \"lightpath\" \"integer maxdepth\" 3\nWorldBegin\n");
    assert_eq!(s.description.integrator.kind, IntegratorKind::LightPath);
    assert_eq!(s.description.integrator.max_depth, 3);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn sppm_parameters_and_defaults() {
    let s = load("Integrator \"sppm\"\nWorldBegin\n");
    assert_eq!(s.description.integrator.kind, IntegratorKind::Sppm);
    assert_eq!(s.description.integrator.sppm, SppmDesc::default());
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let s = load(
        "Integrator \"sppm\" \"integer numiterations\" 10 \"integer photonsperiteration\" 5000 \
         \"float radius\" 0.25 \"integer seed\" 9 \"integer maxdepth\" 7\nWorldBegin\n",
    );
    let i = &s.description.integrator;
    assert_eq!(
        i.sppm,
        SppmDesc {
            iterations: 10,
            photons_per_iteration: Some(5000),
            radius: 0.25,
            seed: Some(9),
        }
    );
    assert_eq!(i.max_depth, 7);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn bad_sppm_parameters_are_errors_with_their_position() {
    for (params, what) in [
        ("\"integer numiterations\" 0", "numiterations"),
        ("\"integer photonsperiteration\" 0", "photonsperiteration"),
        ("\"float radius\" -1", "radius"),
    ] {
        let e = load_err(&format!("Integrator \"sppm\" {params}\nWorldBegin\n"));
        assert!(e.starts_with("scene.pbrt:1:"), "{e}");
        assert!(e.contains(what), "{e}");
    }
}

#[test]
fn mlt_is_its_own_integrator_without_a_warning() {
    let s = load("Integrator \"mlt\"\nWorldBegin\n");
    assert_eq!(s.description.integrator.kind, IntegratorKind::Mlt);
    assert_eq!(s.description.integrator.mlt, MltDesc::default());
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let s = load(
        "Integrator \"mlt\" \"integer maxdepth\" 3 \"integer bootstrapsamples\" 500 \"integer chains\" 8 \
         \"integer mutationsperpixel\" 16 \"float largestepprobability\" 0.5 \"float sigma\" 0.05 \
         \"bool regularize\" true\nWorldBegin\n",
    );
    let i = &s.description.integrator;
    assert_eq!(
        i.mlt,
        MltDesc {
            bootstrap_samples: 500,
            chains: 8,
            mutations_per_pixel: 16,
            large_step_probability: 0.5,
            sigma: 0.05,
            regularize: true,
        }
    );
    assert_eq!(i.max_depth, 3);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn bad_mlt_parameters_are_errors_with_their_position() {
    for (params, what) in [
        ("\"integer bootstrapsamples\" 0", "bootstrapsamples"),
        ("\"integer chains\" -2", "chains"),
        ("\"integer mutationsperpixel\" 0", "mutationsperpixel"),
        ("\"float largestepprobability\" 1.5", "largestepprobability"),
        ("\"float sigma\" 0", "sigma"),
    ] {
        let e = load_err(&format!("Integrator \"mlt\" {params}\nWorldBegin\n"));
        assert!(e.starts_with("scene.pbrt:1:"), "{e}");
        assert!(e.contains(what), "{e}");
    }
}
