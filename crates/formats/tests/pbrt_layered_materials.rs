//! The `coateddiffuse`, `coatedconductor`, `mix` and `interface` materials: parameters,
//! defaults, named references and the messages for what is wrong.

use mcrender_core::material::{CoatedConductorMaterial, CoatedDiffuseMaterial, MixMaterial};
use std::path::Path;

use mcrender_core::color::Rgb;
use mcrender_core::scene::{MaterialDesc, SceneDescription};
use mcrender_formats::pbrt::load_str;
use mcrender_formats::SceneErrorKind;

fn load(src: &str) -> (SceneDescription, Vec<String>) {
    let s = load_str(src, "scene.pbrt", Path::new("")).unwrap_or_else(|e| panic!("{e}"));
    let warnings = s.warnings.into_iter().filter(|w| !w.contains("no lights")).collect();
    (s.description, warnings)
}

/// The material of a sphere given `Material <decl>`, and the warnings.
fn material(decl: &str) -> (MaterialDesc, Vec<String>) {
    let (d, w) = load(&format!("WorldBegin\nMaterial {decl}\nShape \"sphere\""));
    (d.materials[d.shapes[0].material as usize].clone(), w)
}

fn error(src: &str) -> (SceneErrorKind, String) {
    let e = load_str(src, "scene.pbrt", Path::new("")).unwrap_err();
    (e.kind, e.to_string())
}

fn material_error(decl: &str) -> (SceneErrorKind, String) {
    error(&format!("WorldBegin\nMaterial {decl}\nShape \"sphere\""))
}

#[test]
fn coateddiffuse_defaults_are_pbrts() {
    let (m, w) = material("\"coateddiffuse\"");
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(
        m,
        MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
            reflectance: Rgb::splat(0.5).into(),
            u_roughness: 0.0.into(),
            v_roughness: 0.0.into(),
            remap_roughness: true,
            thickness: 0.01.into(),
            eta: 1.5,
            albedo: Rgb::BLACK.into(),
            g: 0.0.into(),
            max_depth: 10,
            n_samples: 1,
        })
    );
}

#[test]
fn coateddiffuse_reads_every_parameter() {
    let (m, w) = material(
        "\"coateddiffuse\" \"rgb reflectance\" [0.1 0.2 0.3] \"float roughness\" 0.3 \"float vroughness\" 0.1 \
         \"bool remaproughness\" false \"float thickness\" 0.5 \"float eta\" 1.33 \"rgb albedo\" [0.4 0.5 0.6] \
         \"float g\" -0.2 \"integer maxdepth\" 20 \"integer nsamples\" 4",
    );
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(
        m,
        MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
            reflectance: Rgb::new(0.1, 0.2, 0.3).into(),
            u_roughness: 0.3.into(),
            v_roughness: 0.1.into(),
            remap_roughness: false,
            thickness: 0.5.into(),
            eta: 1.33,
            albedo: Rgb::new(0.4, 0.5, 0.6).into(),
            g: (-0.2).into(),
            max_depth: 20,
            n_samples: 4,
        })
    );
    // A named glass for eta, as for dielectrics; unknown parameters are warned by name.
    let (m, w) = material("\"coateddiffuse\" \"spectrum eta\" \"glass-BK7\" \"float sigma\" 2");
    let MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial { eta, .. }) = m else {
        panic!("{m:?}")
    };
    assert!((eta - 1.5185).abs() < 1e-3, "{eta}");
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("sigma"), "{w:?}");
}

#[test]
fn coatedconductor_defaults_and_parameters() {
    let (m, w) = material("\"coatedconductor\"");
    assert!(w.is_empty(), "{w:?}");
    let MaterialDesc::CoatedConductor(CoatedConductorMaterial {
        interface_eta,
        conductor_eta,
        conductor_k,
        reflectance,
        thickness,
        max_depth,
        n_samples,
        ..
    }) = m
    else {
        panic!("{m:?}")
    };
    // Copper by default.
    assert_eq!(
        (interface_eta, reflectance, thickness.constant()),
        (1.5, None, Some(0.01))
    );
    let (conductor_eta, conductor_k) = (conductor_eta.constant().unwrap(), conductor_k.constant().unwrap());
    assert!(
        conductor_eta.r < 0.5 && conductor_k.r > 3.0,
        "{conductor_eta:?} {conductor_k:?}"
    );
    assert_eq!((max_depth, n_samples), (10, 1));

    let (m, w) = material(
        "\"coatedconductor\" \"float interface.roughness\" 0.2 \"float interface.vroughness\" 0.05 \
         \"float interface.eta\" 1.4 \"spectrum conductor.eta\" \"metal-Au-eta\" \"spectrum conductor.k\" \"metal-Au-k\" \
         \"float conductor.uroughness\" 0.3 \"float conductor.vroughness\" 0.4 \"bool remaproughness\" false \
         \"float thickness\" 0.2 \"rgb albedo\" [0.5 0.5 0.5] \"float g\" 0.7 \"integer maxdepth\" 5 \"integer nsamples\" 2",
    );
    assert!(w.is_empty(), "{w:?}");
    let MaterialDesc::CoatedConductor(CoatedConductorMaterial {
        interface_u_roughness,
        interface_v_roughness,
        interface_eta,
        conductor_eta,
        conductor_k,
        conductor_u_roughness,
        conductor_v_roughness,
        remap_roughness,
        thickness,
        albedo,
        g,
        max_depth,
        n_samples,
        ..
    }) = m
    else {
        panic!("{m:?}")
    };
    assert_eq!(
        (
            interface_u_roughness.constant(),
            interface_v_roughness.constant(),
            interface_eta
        ),
        (Some(0.2), Some(0.05), 1.4)
    );
    let (conductor_eta, conductor_k) = (conductor_eta.constant().unwrap(), conductor_k.constant().unwrap());
    // Gold: a small real part in blue... and red; more absorption in red.
    assert!(
        conductor_eta.r < 0.3 && conductor_k.r > conductor_k.b,
        "{conductor_eta:?} {conductor_k:?}"
    );
    assert_eq!(
        (
            conductor_u_roughness.constant(),
            conductor_v_roughness.constant(),
            remap_roughness
        ),
        (Some(0.3), Some(0.4), false)
    );
    assert_eq!(
        (
            thickness.constant(),
            albedo.constant(),
            g.constant(),
            max_depth,
            n_samples
        ),
        (Some(0.2), Some(Rgb::splat(0.5)), Some(0.7), 5, 2)
    );

    let (m, _) = material("\"coatedconductor\" \"rgb reflectance\" [0.9 0.5 0.1]");
    let MaterialDesc::CoatedConductor(CoatedConductorMaterial { reflectance, .. }) = m else {
        panic!("{m:?}")
    };
    assert_eq!(reflectance, Some(Rgb::new(0.9, 0.5, 0.1).into()));
}

#[test]
fn malformed_layered_parameters_are_errors_with_locations() {
    let cases = [
        (
            "\"coateddiffuse\" \"float thickness\" -1",
            "scene.pbrt:2:26: \"thickness\" of Material \"coateddiffuse\" must be a finite number >= 0",
        ),
        (
            "\"coateddiffuse\" \"float g\" 1.5",
            "scene.pbrt:2:26: \"g\" of Material \"coateddiffuse\" must be between -1 and 1",
        ),
        (
            "\"coateddiffuse\" \"integer nsamples\" 0",
            "scene.pbrt:2:26: \"nsamples\" of Material \"coateddiffuse\" must be at least 1",
        ),
        (
            "\"coateddiffuse\" \"integer maxdepth\" -3",
            "scene.pbrt:2:26: \"maxdepth\" of Material \"coateddiffuse\" must be at least 0",
        ),
        (
            "\"coateddiffuse\" \"rgb albedo\" [2 0 0]",
            "scene.pbrt:2:26: albedo (2 0 0) of Material \"coateddiffuse\" must be between 0 and 1",
        ),
        (
            "\"coateddiffuse\" \"rgb reflectance\" [0.5 -0.5 0]",
            "scene.pbrt:2:26: \"rgb reflectance\" of Material \"coateddiffuse\" must not be negative",
        ),
        (
            "\"coatedconductor\" \"float conductor.roughness\" -0.1",
            "scene.pbrt:2:28: \"conductor.roughness\" of Material \"coatedconductor\" must not be negative",
        ),
        (
            "\"coatedconductor\" \"rgb reflectance\" [0.5 0.5 0.5] \"spectrum conductor.k\" \"metal-Ag-k\"",
            "scene.pbrt:2:28: Material \"coatedconductor\" has both \"reflectance\" and \"conductor.eta\"/\"conductor.k\"",
        ),
        (
            "\"coatedconductor\" \"spectrum conductor.eta\" \"metal-Xx-eta\"",
            "scene.pbrt:2:28: unknown named spectrum \"metal-Xx-eta\"",
        ),
        (
            "\"coatedconductor\" \"float interface.eta\" -2",
            "scene.pbrt:2:28: \"interface.eta\" of Material \"coatedconductor\" must be a finite number > 0",
        ),
        (
            "\"coateddiffuse\" \"float g\" \"x\"",
            "scene.pbrt:2:",
        ),
    ];
    for (decl, expected) in cases {
        let (_, e) = material_error(decl);
        assert!(e.starts_with(expected), "{decl}: {e}");
    }
}

/// Two named materials and a mix of them.
const MIX: &str = "WorldBegin
MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.8 0 0]
MakeNamedMaterial \"gloss\" \"string type\" \"coateddiffuse\"
";

#[test]
fn mix_refers_to_named_materials_defined_before_or_after() {
    let (d, w) = load(&format!(
        "{MIX}MakeNamedMaterial \"both\" \"string type\" \"mix\" \"string materials\" [\"red\" \"later\"] \"float amount\" 0.25
NamedMaterial \"both\"
Shape \"sphere\"
MakeNamedMaterial \"later\" \"string type\" \"interface\"
"
    ));
    assert!(w.is_empty(), "{w:?}");
    let MaterialDesc::Mix(MixMaterial { materials, amount }) = d.materials[d.shapes[0].material as usize].clone()
    else {
        panic!("{:?}", d.materials)
    };
    assert_eq!(amount.constant(), Some(0.25));
    assert!(matches!(d.materials[materials[0] as usize], MaterialDesc::Diffuse(_)));
    assert_eq!(d.materials[materials[1] as usize], MaterialDesc::Interface);

    // Inline mixes, nested mixes, default amount.
    let (d, _) = load(&format!(
        "{MIX}MakeNamedMaterial \"inner\" \"string type\" \"mix\" \"string materials\" [\"red\" \"gloss\"]
Material \"mix\" \"string materials\" [\"inner\" \"red\"] \"float amount\" 1
Shape \"sphere\"
"
    ));
    let MaterialDesc::Mix(MixMaterial { materials, amount }) = d.materials[d.shapes[0].material as usize].clone()
    else {
        panic!("{:?}", d.materials)
    };
    assert_eq!(amount.constant(), Some(1.0));
    assert_eq!(
        d.materials[materials[0] as usize],
        MaterialDesc::Mix(MixMaterial {
            materials: [materials[1], materials[0] - 1],
            amount: 0.5.into()
        })
    );
}

#[test]
fn malformed_mixes_are_errors_with_locations() {
    let cases = [
        (
            format!("{MIX}Material \"mix\" \"string materials\" [\"red\" \"blue\"]\nShape \"sphere\""),
            "scene.pbrt:4:16: named material \"blue\" is not defined",
        ),
        (
            format!("{MIX}Material \"mix\" \"string materials\" [\"red\"]\nShape \"sphere\""),
            "scene.pbrt:4:16: \"string materials\" of Material \"mix\" needs exactly two material names, found 1",
        ),
        (format!("{MIX}Material \"mix\"\nShape \"sphere\""), "scene.pbrt:4:"),
        (
            format!(
                "{MIX}MakeNamedMaterial \"a\" \"string type\" \"mix\" \"string materials\" [\"red\" \"b\"]
MakeNamedMaterial \"b\" \"string type\" \"mix\" \"string materials\" [\"a\" \"gloss\"]
NamedMaterial \"a\"
Shape \"sphere\""
            ),
            "scene.pbrt:5:43: mix material \"a\" contains itself (through a -> b)",
        ),
    ];
    for (src, expected) in &cases {
        let (_, e) = error(src);
        assert!(e.starts_with(expected), "{src}:\n{e}");
    }
    // A mix that nothing uses is not resolved, as in pbrt (no error).
    let (_, w) = load(&format!(
        "{MIX}MakeNamedMaterial \"unused\" \"string type\" \"mix\" \"string materials\" [\"red\" \"nothing\"]\n"
    ));
    assert!(w.is_empty(), "{w:?}");
}

#[test]
fn interface_and_its_pbrt_spellings_have_no_surface() {
    for kind in ["interface", "none", ""] {
        let (m, w) = material(&format!("\"{kind}\""));
        assert_eq!(m, MaterialDesc::Interface, "{kind}");
        assert!(w.is_empty(), "{w:?}");
    }
}

/// A float and a spectrum checkerboard texture, `f` and `s`.
const TEXTURES: &str = "WorldBegin
Texture \"f\" \"float\" \"checkerboard\" \"float tex1\" 0.1 \"float tex2\" 0.3
Texture \"s\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [0.1 0.2 0.3] \"rgb tex2\" [0.4 0.5 0.6]
";

/// The material of a sphere given `Material <decl>` after [`TEXTURES`].
fn textured_material(decl: &str) -> MaterialDesc {
    let (d, w) = load(&format!("{TEXTURES}Material {decl}\nShape \"sphere\""));
    assert!(w.is_empty(), "{w:?}");
    d.materials[d.shapes[0].material as usize].clone()
}

#[test]
fn coated_and_mix_parameters_take_textures() {
    let m = textured_material(
        "\"coateddiffuse\" \"texture reflectance\" \"s\" \"texture uroughness\" \"f\" \"texture vroughness\" \"f\" \
         \"texture thickness\" \"f\" \"texture albedo\" \"s\" \"texture g\" \"f\"",
    );
    let MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
        reflectance,
        u_roughness,
        v_roughness,
        thickness,
        albedo,
        g,
        ..
    }) = m
    else {
        panic!("{m:?}")
    };
    assert!(reflectance.constant().is_none() && albedo.constant().is_none());
    for t in [u_roughness, v_roughness, thickness, g] {
        assert!(t.constant().is_none(), "{t:?}");
    }
    // A single roughness texture serves both directions.
    let m = textured_material("\"coateddiffuse\" \"texture roughness\" \"f\"");
    let MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
        u_roughness,
        v_roughness,
        ..
    }) = m
    else {
        panic!("{m:?}")
    };
    assert!(u_roughness.constant().is_none() && v_roughness.constant().is_none());

    let m = textured_material(
        "\"coatedconductor\" \"texture interface.roughness\" \"f\" \"texture conductor.eta\" \"s\" \
         \"texture conductor.k\" \"s\" \"texture conductor.uroughness\" \"f\" \"texture conductor.vroughness\" \"f\" \
         \"texture thickness\" \"f\" \"texture albedo\" \"s\" \"texture g\" \"f\"",
    );
    let MaterialDesc::CoatedConductor(CoatedConductorMaterial {
        interface_u_roughness,
        interface_v_roughness,
        conductor_eta,
        conductor_k,
        conductor_u_roughness,
        conductor_v_roughness,
        thickness,
        albedo,
        g,
        ..
    }) = m
    else {
        panic!("{m:?}")
    };
    for t in [conductor_eta, conductor_k, albedo] {
        assert!(t.constant().is_none(), "{t:?}");
    }
    for t in [
        interface_u_roughness,
        interface_v_roughness,
        conductor_u_roughness,
        conductor_v_roughness,
        thickness,
        g,
    ] {
        assert!(t.constant().is_none(), "{t:?}");
    }
    let m = textured_material("\"coatedconductor\" \"texture reflectance\" \"s\"");
    let MaterialDesc::CoatedConductor(CoatedConductorMaterial { reflectance, .. }) = m else {
        panic!("{m:?}")
    };
    assert!(reflectance.is_some_and(|r| r.constant().is_none()));

    let (d, w) = load(&format!(
        "{TEXTURES}{}Material \"mix\" \"string materials\" [\"red\" \"gloss\"] \"texture amount\" \"f\"\nShape \"sphere\"",
        &MIX["WorldBegin\n".len()..]
    ));
    assert!(w.is_empty(), "{w:?}");
    let MaterialDesc::Mix(MixMaterial { amount, .. }) = &d.materials[d.shapes[0].material as usize] else {
        panic!("{:?}", d.materials)
    };
    assert!(amount.constant().is_none(), "{amount:?}");
}

#[test]
fn wrong_textures_on_coated_parameters_are_errors() {
    let cases = [
        ("\"coateddiffuse\" \"texture albedo\" \"f\"", "scene.pbrt:4:"),
        ("\"coateddiffuse\" \"texture g\" \"s\"", "scene.pbrt:4:"),
        ("\"coatedconductor\" \"texture thickness\" \"nothing\"", "scene.pbrt:4:"),
        // pbrt-v4: the coat's index is a Float or Spectrum, not a texture.
        ("\"coateddiffuse\" \"texture eta\" \"f\"", "scene.pbrt:4:"),
        ("\"coatedconductor\" \"texture interface.eta\" \"f\"", "scene.pbrt:4:"),
    ];
    for (decl, expected) in cases {
        let (_, e) = error(&format!("{TEXTURES}Material {decl}\nShape \"sphere\""));
        assert!(e.starts_with(expected), "{decl}: {e}");
    }
}
