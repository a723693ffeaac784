//! The estimator lab's commands as a user runs them: `compare` (table, JSON, images),
//! `bounces`, `rr-study`, and the estimator flags of `render`.

mod common;

use common::{mcrender, scene, stderr};

/// The JSON report is consistent with itself (efficiency = 1 / (variance x time), relative
/// efficiency = efficiency / best), and on the occluder scene the variances are ordered as
/// theory says: light sampling < cosine-weighted < uniform hemisphere sampling.
#[test]
fn compare_reports_consistent_numbers_and_the_expected_order() {
    let dir = tempfile::tempdir().unwrap();
    let o = mcrender(
        &[
            "compare",
            &scene("occluder/occluder.pbrt"),
            "--spp",
            "8",
            "--resolution",
            "64x48",
            "--json",
            "-o",
            "out",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON on stdout");
    let rows = report["techniques"].as_array().unwrap();
    assert_eq!(rows.len(), 5);
    let get = |name: &str, key: &str| {
        rows.iter()
            .find(|r| r["technique"] == name)
            .unwrap_or_else(|| panic!("no row {name}"))[key]
            .as_f64()
            .unwrap()
    };
    let best = rows
        .iter()
        .map(|r| r["efficiency"].as_f64().unwrap())
        .fold(0.0, f64::max);
    for r in rows {
        let (v, t, e) = (
            r["variance"].as_f64().unwrap(),
            r["time_s"].as_f64().unwrap(),
            r["efficiency"].as_f64().unwrap(),
        );
        assert!(
            (e * v * t - 1.0).abs() < 1e-9,
            "{}: efficiency {e} != 1 / ({v} x {t})",
            r["technique"]
        );
        assert!((r["relative_efficiency"].as_f64().unwrap() - e / best).abs() < 1e-12);
    }
    let (uniform, cosine, light) = (
        get("uniform-hemisphere", "variance"),
        get("cosine-hemisphere", "variance"),
        get("light-area", "variance"),
    );
    assert!(
        light < cosine && cosine < uniform,
        "variances: light {light}, cosine {cosine}, uniform {uniform}"
    );
    for f in ["contact-sheet.png", "convergence.png", "occluder-mis.exr"] {
        assert!(dir.path().join("out").join(f).exists(), "{f} missing");
    }
}

#[test]
fn compare_with_a_reference_reports_relative_mse() {
    let dir = tempfile::tempdir().unwrap();
    let occ = scene("occluder/occluder.pbrt");
    let r = mcrender(
        &[
            "render",
            &occ,
            "--resolution",
            "32x24",
            "--spp",
            "64",
            "-o",
            "ref.exr",
            "-q",
        ],
        dir.path(),
    );
    assert!(r.status.success(), "{}", stderr(&r));
    let o = mcrender(
        &[
            "compare",
            &occ,
            "--spp",
            "4",
            "--resolution",
            "32x24",
            "--techniques",
            "light-area,mis",
            "--reference",
            "ref.exr",
            "--json",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for row in report["techniques"].as_array().unwrap() {
        assert!(row["rel_mse"].as_f64().unwrap() > 0.0, "{row}");
    }
    // A reference of the wrong size is refused with a message saying so.
    let o = mcrender(
        &[
            "compare",
            &occ,
            "--spp",
            "1",
            "--resolution",
            "16x12",
            "--reference",
            "ref.exr",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("32x24"), "{}", stderr(&o));
}

#[test]
fn bounces_writes_one_image_per_depth_and_a_sheet() {
    let dir = tempfile::tempdir().unwrap();
    let o = mcrender(
        &[
            "bounces",
            "--depths",
            "0,1,3",
            "--spp",
            "2",
            "--resolution",
            "24x24",
            "-o",
            "b",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [
        "cornell-box-depth-0.png",
        "cornell-box-depth-1.png",
        "cornell-box-depth-3.png",
        "cornell-box-bounces.png",
    ] {
        assert!(dir.path().join("b").join(f).exists(), "{f} missing");
    }
    let table = String::from_utf8_lossy(&o.stdout);
    assert_eq!(table.lines().filter(|l| l.starts_with("depth")).count(), 3, "{table}");
}

#[test]
fn rr_study_prints_the_lecture_table() {
    let dir = tempfile::tempdir().unwrap();
    let o = mcrender(
        &["rr-study", "--spp", "4", "--resolution", "16x16", "--max-depth", "16"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    for row in [
        "no RR",
        "50% below 0.25",
        "50% below 0.5",
        "90% below 0.125",
        "90% below 1",
    ] {
        assert!(out.contains(row), "row {row} missing:\n{out}");
    }
    let bad = mcrender(&["rr-study", "--settings", "0.5:1.5"], dir.path());
    assert_eq!(bad.status.code(), Some(2));
}

#[test]
fn render_accepts_the_estimator_flags_and_refuses_what_cannot_work() {
    let dir = tempfile::tempdir().unwrap();
    let o = mcrender(
        &[
            "render",
            "--direct",
            "uniform-hemisphere",
            "--light-samples",
            "2",
            "--rr-threshold",
            "0.5",
            "--rr-prob",
            "0.5",
            "--resolution",
            "16x16",
            "--spp",
            "2",
            "-o",
            "u.png",
            "-q",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("u.png").exists());
    // A point light cannot be found by hemisphere sampling: refused, not rendered black.
    let pbrt = dir.path().join("point.pbrt");
    std::fs::write(
        &pbrt,
        "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\nWorldBegin\n\
         LightSource \"point\" \"rgb I\" [ 1 1 1 ]\nShape \"sphere\" \"float radius\" [ 3 ]\n",
    )
    .unwrap();
    let o = mcrender(
        &[
            "render",
            pbrt.to_str().unwrap(),
            "--direct",
            "bsdf",
            "-o",
            "p.png",
            "-q",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("point"), "{}", stderr(&o));
    assert!(!dir.path().join("p.png").exists());
    let o = mcrender(&["render", "--direct", "nonsense", "-q"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("light-area"), "{}", stderr(&o));
}
