//! The layered, mix and interface materials in whole renders: a thin clear-coated
//! Lambertian under a uniform sky has a closed-form radiance, which every direct-lighting
//! technique must reach (MIS needs the BSDF's pdf, not the proportional sampled one); a mix
//! reflects the mixture of its materials; an `interface` surface changes nothing.

mod common;

use common::*;
use mcrender_core::bsdf::fresnel::fr_dielectric;
use mcrender_core::color::Rgb;
use mcrender_core::material::{CoatedConductorMaterial, CoatedDiffuseMaterial, DiffuseMaterial, MixMaterial};
use mcrender_core::math::{Mat4, Transform, Vec3};
use mcrender_core::scene::{DirectStrategy, GeometryDesc, MaterialDesc, Scene, SceneDescription, ShapeDesc};

/// The receiver of [`add_receiver`] under a uniform sky of radiance `sky`, seen at a
/// grazing angle by a narrow camera, with direct lighting only.
fn under_sky(sky: f32) -> SceneDescription {
    let (mut d, _) = receiver_under_sky(sky, 0.8);
    d.sampler.samples_per_pixel = 512;
    d
}

/// Replace the receiver's material (the last one) by `m`.
fn set_receiver_material(d: &mut SceneDescription, m: MaterialDesc) {
    *d.materials.last_mut().unwrap() = m;
}

fn assert_close(d: &SceneDescription, expected: f64, label: &str) {
    let out = render_desc(d);
    assert_eq!(out.stats.nonfinite_samples, 0, "{label}");
    let (mean, se) = mean_and_standard_error(&out);
    for c in 0..3 {
        assert!(
            (mean[c] - expected).abs() <= 4.0 * se[c] + 1e-4,
            "{label}, channel {c}: {:.5} vs expected {expected:.5} (standard error {:.1e})",
            mean[c],
            se[c]
        );
    }
}

/// Cosine-weighted average of the internal Fresnel reflectance of a coat of index `eta`.
fn internal_fresnel_average(eta: f32) -> f64 {
    let steps = 100_000;
    (0..steps)
        .map(|i| {
            let mu = (f64::from(i) + 0.5) / f64::from(steps);
            2.0 * mu * f64::from(fr_dielectric(mu as f32, 1.0 / eta))
        })
        .sum::<f64>()
        / f64::from(steps)
}

#[test]
fn thin_coated_lambertian_under_a_sky_matches_its_closed_form_with_every_technique() {
    let (sky, r) = (1.5f32, 0.5f32);
    let mut d = under_sky(sky);
    set_receiver_material(
        &mut d,
        MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
            reflectance: Rgb::splat(r).into(),
            u_roughness: 0.0.into(),
            v_roughness: 0.0.into(),
            remap_roughness: false,
            thickness: 1e-5.into(),
            eta: 1.5,
            albedo: Rgb::BLACK.into(),
            g: 0.0.into(),
            max_depth: 200,
            n_samples: 1,
        }),
    );
    // The camera sees the receiver's centre from (1, 0.2, 0.3): cos theta_o = 0.2 / |eye|.
    let cos_o = 0.2 / Vec3::new(1.0, 0.2, 0.3).length();
    let f = f64::from(fr_dielectric(cos_o, 1.5));
    let fi = internal_fresnel_average(1.5);
    let (r, sky) = (f64::from(r), f64::from(sky));
    // The coat's mirror reflection plus what leaves after bounces on the base (see the
    // layered BSDF's unit tests for the derivation).
    let expected = sky * (f + (1.0 - f) * r * (1.0 - fi) / (1.0 - r * fi));
    for strategy in DirectStrategy::ALL {
        let mut d = d.clone();
        d.integrator.direct = strategy;
        assert_close(&d, expected, strategy.name());
    }
}

#[test]
fn mixes_reflect_the_mixture_of_their_materials() {
    let sky = 1.5f64;
    let mut d = under_sky(sky as f32);
    let n = d.materials.len() as u32;
    // n-1: the receiver's diffuse 0.8; n: diffuse 0.2; n+1: their mix; n+2: a mix of the
    // mix and a black diffuse.
    d.materials.push(MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: Rgb::splat(0.2).into(),
    }));
    d.materials.push(MaterialDesc::Mix(MixMaterial {
        materials: [n - 1, n],
        amount: 0.25.into(),
    }));
    d.materials.push(MaterialDesc::Mix(MixMaterial {
        materials: [n + 1, 0],
        amount: 0.5.into(),
    }));
    let receiver = d.shapes.len() - 1;
    for (material, albedo) in [
        (n + 1, 0.75 * 0.8 + 0.25 * 0.2),
        (n + 2, 0.5 * (0.75 * 0.8 + 0.25 * 0.2)),
    ] {
        d.shapes[receiver].material = material;
        assert_close(&d, sky * albedo, &format!("material {material}"));
    }
    // amount 0 and 1 choose one material outright: noise-free.
    for (amount, albedo) in [(0.0, 0.8), (1.0, 0.2), (-3.0, 0.8), (7.0, 0.2)] {
        d.materials[n as usize + 1] = MaterialDesc::Mix(MixMaterial {
            materials: [n - 1, n],
            amount: amount.into(),
        });
        d.shapes[receiver].material = n + 1;
        assert_close(&d, sky * albedo, &format!("amount {amount}"));
    }
    // A mix that contains itself is refused.
    d.materials[n as usize + 1] = MaterialDesc::Mix(MixMaterial {
        materials: [n - 1, n + 2],
        amount: 0.5.into(),
    });
    let e = Scene::build(&d).unwrap_err().to_string();
    assert!(e.contains("contains itself"), "{e}");
}

/// An `interface` sphere of radius `r` at `centre`, using material `m`.
fn interface_sphere(m: u32, r: f32, centre: Vec3) -> ShapeDesc {
    ShapeDesc {
        geometry: GeometryDesc::full_sphere(r, Transform::new(Mat4::from_translation(centre)).unwrap()),
        material: m,
        area_light: None,
        flip_normals: false,
        alpha: None,
    }
}

#[test]
fn interface_surfaces_change_nothing() {
    // The receiver lit by a square light above it: radiance albedo / pi * E.
    let (mut d, expected) = receiver_under_square_light(0.5, 1.0, 2.0, 0.8);
    d.sampler.samples_per_pixel = 256;
    let expected = f64::from(expected.g);
    // Interface spheres across the camera rays and across the shadow rays.
    d.materials.push(MaterialDesc::Interface);
    let m = (d.materials.len() - 1) as u32;
    d.shapes.push(interface_sphere(m, 0.1, Vec3::new(0.5, 0.1, 0.15)));
    d.shapes.push(interface_sphere(m, 0.3, Vec3::new(0.0, 0.5, 0.0)));
    for strategy in DirectStrategy::ALL {
        let mut d = d.clone();
        d.integrator.direct = strategy;
        assert_close(&d, expected, &format!("interface, {}", strategy.name()));
    }
}

#[test]
fn invalid_layered_and_mix_parameters_are_refused() {
    let coated = MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
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
    });
    let conductor = MaterialDesc::CoatedConductor(CoatedConductorMaterial {
        interface_u_roughness: 0.0.into(),
        interface_v_roughness: 0.0.into(),
        interface_eta: 1.5,
        conductor_eta: Rgb::splat(0.2).into(),
        conductor_k: Rgb::splat(3.0).into(),
        reflectance: None,
        conductor_u_roughness: 0.1.into(),
        conductor_v_roughness: 0.1.into(),
        remap_roughness: true,
        thickness: 0.01.into(),
        albedo: Rgb::BLACK.into(),
        g: 0.0.into(),
        max_depth: 10,
        n_samples: 1,
    });
    let build = |m: MaterialDesc| {
        let mut d = under_sky(1.0);
        set_receiver_material(&mut d, m);
        Scene::build(&d).map(|_| ()).map_err(|e| e.to_string())
    };
    assert_eq!(build(coated.clone()), Ok(()));
    assert_eq!(build(conductor.clone()), Ok(()));
    let mut bad = Vec::new();
    for (field, v) in [
        ("thickness", f32::NAN),
        ("thickness", -1.0),
        ("g", f32::NAN),
        ("eta", 0.0),
        ("roughness", -0.1),
    ] {
        let mut m = coated.clone();
        if let MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
            thickness,
            g,
            eta,
            u_roughness,
            ..
        }) = &mut m
        {
            match field {
                "thickness" => *thickness = v.into(),
                "g" => *g = v.into(),
                "eta" => *eta = v,
                _ => *u_roughness = v.into(),
            }
        }
        bad.push((format!("coated diffuse {field} {v}"), m));
    }
    for (field, v) in [
        ("albedo", -0.5),
        ("conductor k", f32::NAN),
        ("interface eta", f32::INFINITY),
    ] {
        let mut m = conductor.clone();
        if let MaterialDesc::CoatedConductor(CoatedConductorMaterial {
            albedo,
            conductor_k,
            interface_eta,
            ..
        }) = &mut m
        {
            match field {
                "albedo" => *albedo = Rgb::splat(v).into(),
                "conductor k" => *conductor_k = Rgb::splat(v).into(),
                _ => *interface_eta = v,
            }
        }
        bad.push((format!("coated conductor {field} {v}"), m));
    }
    bad.push((
        "mix amount NaN".into(),
        MaterialDesc::Mix(MixMaterial {
            materials: [0, 0],
            amount: f32::NAN.into(),
        }),
    ));
    bad.push((
        "mix of a missing material".into(),
        MaterialDesc::Mix(MixMaterial {
            materials: [0, 99],
            amount: 0.5.into(),
        }),
    ));
    for (label, m) in bad {
        let e = build(m).expect_err(&label);
        assert!(e.contains("material"), "{label}: {e}");
    }
}
