//! The `conductor`, `dielectric`, `thindielectric` and `diffusetransmission` materials:
//! parameters, defaults, named spectra and the messages for what is wrong or unsupported.

use mcrender_core::material::{
    ConductorMaterial, DielectricMaterial, DiffuseMaterial, DiffuseTransmissionMaterial, ThinDielectricMaterial,
};
use std::path::Path;

use mcrender_core::color::Rgb;
use mcrender_core::scene::MaterialDesc;
use mcrender_formats::pbrt::load_str;
use mcrender_formats::SceneErrorKind;

/// The material of a sphere given `Material <decl>`, and the warnings.
fn material(decl: &str) -> (MaterialDesc, Vec<String>) {
    let src = format!("WorldBegin\nMaterial {decl}\nShape \"sphere\"");
    let s = load_str(&src, "scene.pbrt", Path::new("")).unwrap_or_else(|e| panic!("{e}"));
    let d = s.description;
    let warnings = s.warnings.into_iter().filter(|w| !w.contains("no lights")).collect();
    (d.materials[d.shapes[0].material as usize].clone(), warnings)
}

fn error(decl: &str) -> (SceneErrorKind, String) {
    let src = format!("WorldBegin\nMaterial {decl}\nShape \"sphere\"");
    let e = load_str(&src, "scene.pbrt", Path::new("")).unwrap_err();
    (e.kind, e.to_string())
}

fn conductor_parts(m: &MaterialDesc) -> (Rgb, Rgb, Option<Rgb>, f32, f32, bool) {
    match m {
        MaterialDesc::Conductor(ConductorMaterial {
            eta,
            k,
            reflectance,
            u_roughness,
            v_roughness,
            remap_roughness,
            ..
        }) => (
            eta.constant().unwrap(),
            k.constant().unwrap(),
            reflectance.as_ref().map(|r| r.constant().unwrap()),
            u_roughness.constant().unwrap(),
            v_roughness.constant().unwrap(),
            *remap_roughness,
        ),
        _ => panic!("not a conductor: {m:?}"),
    }
}

#[test]
fn conductor_defaults_to_smooth_copper() {
    let (m, warnings) = material("\"conductor\"");
    let (eta, k, reflectance, u, v, remap) = conductor_parts(&m);
    let (cu_eta, cu_k) =
        conductor_parts(&material("\"conductor\" \"spectrum eta\" \"metal-Cu-eta\" \"spectrum k\" \"metal-Cu-k\"").0)
            .to_owned_pair();
    assert_eq!((eta, k), (cu_eta, cu_k));
    assert!(eta.r < eta.b && k.r > k.b, "copper: {eta:?} {k:?}");
    assert_eq!((reflectance, u, v, remap), (None, 0.0, 0.0, true));
    assert!(warnings.is_empty(), "{warnings:?}");
}

trait Pair {
    fn to_owned_pair(self) -> (Rgb, Rgb);
}
impl Pair for (Rgb, Rgb, Option<Rgb>, f32, f32, bool) {
    fn to_owned_pair(self) -> (Rgb, Rgb) {
        (self.0, self.1)
    }
}

#[test]
fn conductor_reads_rgb_indices_and_roughness() {
    let (m, _) = material(
        "\"conductor\" \"rgb eta\" [0.2 0.9 1.1] \"rgb k\" [3.9 2.4 2.1] \"float roughness\" 0.3 \
         \"float vroughness\" 0.1 \"bool remaproughness\" false",
    );
    assert_eq!(
        conductor_parts(&m),
        (Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.9, 2.4, 2.1), None, 0.3, 0.1, false)
    );
}

#[test]
fn conductor_named_metals_differ() {
    let gold =
        conductor_parts(&material("\"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"").0);
    let silver =
        conductor_parts(&material("\"conductor\" \"spectrum eta\" \"metal-Ag-eta\" \"spectrum k\" \"metal-Ag-k\"").0);
    let alu =
        conductor_parts(&material("\"conductor\" \"spectrum eta\" \"metal-Al-eta\" \"spectrum k\" \"metal-Al-k\"").0);
    assert!(gold.0.b > gold.0.r && silver.0.r < 0.2 && alu.1.r > 7.0);
}

#[test]
fn conductor_reflectance_replaces_the_index() {
    let (m, _) = material("\"conductor\" \"rgb reflectance\" [0.9 0.8 0.7] \"float uroughness\" 0.2");
    assert_eq!(
        conductor_parts(&m).2,
        Some(Rgb::new(0.9, 0.8, 0.7)),
        "pbrt turns it into eta = 1, k = 2 sqrt(r) / sqrt(1 - r) when building the BSDF"
    );
    assert_eq!(conductor_parts(&m).3, 0.2);
    assert_eq!(
        error("\"conductor\" \"rgb reflectance\" [0.9 0.8 0.7] \"rgb eta\" [1 1 1]"),
        (
            SceneErrorKind::Invalid,
            "scene.pbrt:2:22: Material \"conductor\" has both \"reflectance\" and \"eta\"/\"k\"; give one or the other"
                .to_owned()
        )
    );
}

#[test]
fn conductor_errors_name_the_parameter() {
    let (kind, msg) = error("\"conductor\" \"spectrum eta\" \"metal-Zn-eta\"");
    assert_eq!(kind, SceneErrorKind::Invalid);
    assert!(
        msg.starts_with("scene.pbrt:2:22: unknown named spectrum \"metal-Zn-eta\" for \"spectrum eta\" of Material \"conductor\"; known: metal-Ag-eta"),
        "{msg}"
    );
    assert_eq!(
        error("\"conductor\" \"spectrum k\" \"metal-CuZn-k\""),
        (
            SceneErrorKind::Unsupported,
            "scene.pbrt:2:22: \"spectrum k\" of Material \"conductor\" (named spectrum \"metal-CuZn-k\") is not supported yet"
                .to_owned()
        )
    );
    assert_eq!(
        error("\"conductor\" \"texture k\" \"tex\""),
        (
            SceneErrorKind::Invalid,
            "scene.pbrt:2:22: \"texture k\" of Material \"conductor\" refers to texture \"tex\", which is not defined (define it with Texture \"tex\" \"spectrum\" ... first)".to_owned()
        )
    );
    assert_eq!(
        error("\"conductor\" \"float roughness\" -0.1").1,
        "scene.pbrt:2:22: \"roughness\" of Material \"conductor\" must not be negative"
    );
    assert_eq!(
        error("\"conductor\" \"rgb k\" [1 -1 1]").1,
        "scene.pbrt:2:22: \"rgb k\" of Material \"conductor\" must not be negative"
    );
}

#[test]
fn sampled_spectra_become_rgb() {
    // A constant index maps to itself; a falling one is higher in blue than in red.
    let (eta, k, ..) =
        conductor_parts(&material("\"conductor\" \"spectrum eta\" [400 1.2 700 1.2] \"spectrum k\" [400 3 700 1]").0);
    assert!((0..3).all(|c| (eta[c] - 1.2).abs() < 1e-5), "{eta:?}");
    assert!(k.b > k.g && k.g > k.r, "{k:?}");
    let MaterialDesc::Diffuse(DiffuseMaterial { reflectance }) =
        material("\"diffuse\" \"spectrum reflectance\" [300 0.5 800 0.5]").0
    else {
        panic!()
    };
    let reflectance = reflectance.constant().unwrap();
    assert!((0..3).all(|c| (reflectance[c] - 0.5).abs() < 1e-5), "{reflectance:?}");
    // A dielectric takes the index at 550 nm, as for the named glasses.
    let MaterialDesc::Dielectric(DielectricMaterial { eta, .. }) =
        material("\"dielectric\" \"spectrum eta\" [500 1.6 600 1.4]").0
    else {
        panic!()
    };
    assert!((eta - 1.5).abs() < 1e-5, "{eta}");
    let (_, msg) = error("\"dielectric\" \"spectrum eta\" [600 1.6 500 1.4]");
    assert!(
        msg.starts_with("scene.pbrt:2:23:") && msg.contains("must increase"),
        "{msg}"
    );
}

#[test]
fn dielectric_eta_as_float_named_glass_or_default() {
    let eta = |decl: &str| match material(decl).0 {
        MaterialDesc::Dielectric(DielectricMaterial { eta, .. })
        | MaterialDesc::ThinDielectric(ThinDielectricMaterial { eta }) => eta,
        m => panic!("{m:?}"),
    };
    assert_eq!(eta("\"dielectric\""), 1.5);
    assert_eq!(eta("\"dielectric\" \"float eta\" 1.33"), 1.33);
    assert!((eta("\"dielectric\" \"spectrum eta\" \"glass-BK7\"") - 1.5185).abs() < 1e-3);
    assert!((eta("\"thindielectric\" \"spectrum eta\" \"glass-F11\"") - 1.791).abs() < 1e-3);
    assert_eq!(eta("\"thindielectric\""), 1.5);
    assert_eq!(
        eta("\"dielectric\" \"float eta\" 0"),
        1.0,
        "pbrt: an index of 0 means 1"
    );
    let (kind, msg) = error("\"dielectric\" \"spectrum eta\" \"glass-XYZ\"");
    assert_eq!(kind, SceneErrorKind::Invalid);
    assert!(msg.contains("unknown named spectrum \"glass-XYZ\""), "{msg}");
    assert_eq!(
        error("\"dielectric\" \"float eta\" -1.5").1,
        "scene.pbrt:2:23: \"eta\" of Material \"dielectric\" must be a finite number > 0, found -1.5"
    );
}

#[test]
fn dielectric_roughness() {
    let (m, warnings) = material("\"dielectric\" \"float eta\" 1.5 \"float uroughness\" 0.1 \"float vroughness\" 0.4");
    assert_eq!(
        m,
        MaterialDesc::Dielectric(DielectricMaterial {
            eta: 1.5,
            u_roughness: 0.1.into(),
            v_roughness: 0.4.into(),
            remap_roughness: true,
            microfacet: Default::default(),
        })
    );
    assert!(warnings.is_empty());
    // pbrt's other parameters are read or warned about, never dropped silently.
    let (_, warnings) = material("\"thindielectric\" \"float roughness\" 0.2");
    assert_eq!(
        warnings,
        ["scene.pbrt:2:27: warning: parameter \"float roughness\" of Material \"thindielectric\" is not supported and was ignored"]
    );
}

#[test]
fn diffuse_transmission_parameters() {
    assert_eq!(
        material("\"diffusetransmission\"").0,
        MaterialDesc::DiffuseTransmission(DiffuseTransmissionMaterial {
            reflectance: Rgb::splat(0.25).into(),
            transmittance: Rgb::splat(0.25).into(),
            scale: 1.0
        })
    );
    assert_eq!(
        material("\"diffusetransmission\" \"rgb reflectance\" [0.1 0.2 0.3] \"rgb transmittance\" [0.4 0.5 0.6] \"float scale\" 1.5").0,
        MaterialDesc::DiffuseTransmission(DiffuseTransmissionMaterial {
            reflectance: Rgb::new(0.1, 0.2, 0.3).into(),
            transmittance: Rgb::new(0.4, 0.5, 0.6).into(),
            scale: 1.5
        })
    );
    assert_eq!(
        error("\"diffusetransmission\" \"rgb transmittance\" [0.4 1.5 0.6]").1,
        "scene.pbrt:2:32: transmittance (0.4 1.5 0.6) of Material \"diffusetransmission\" must be between 0 and 1"
    );
}

#[test]
fn equal_materials_share_an_index() {
    let src = "WorldBegin\nMaterial \"conductor\" \"float roughness\" 0.1\nShape \"sphere\"\nShape \"sphere\"\n\
               Material \"conductor\" \"float roughness\" 0.2\nShape \"sphere\"";
    let d = load_str(src, "scene.pbrt", Path::new("")).unwrap().description;
    assert_eq!(d.materials.len(), 2);
    assert_eq!(d.shapes[0].material, d.shapes[1].material);
    assert_ne!(d.shapes[0].material, d.shapes[2].material);
}
