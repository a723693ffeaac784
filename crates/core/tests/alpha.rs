//! Alpha cut-outs: shapes with alpha 0 are invisible and cast no shadow, a constant alpha
//! `a` lets `1 - a` of the light through in expectation (to camera and shadow rays alike),
//! textured alpha shadows by its coverage, emitters emit only where present, and the
//! stochastic test is deterministic per ray.

mod common;

use std::sync::Arc;

use common::*;
use mcrender_core::color::Rgb;
use mcrender_core::math::{Mat4, Transform, Vec2, Vec3};
use mcrender_core::render::{render, RenderOptions};
use mcrender_core::scene::*;
use mcrender_core::texture::{CheckerboardTexture, Texture, TextureMapping};

/// The receiver lit by a square light above it, seen by a camera with a tiny field of view,
/// direct lighting only; and the mean radiance expected without occluders,
/// `albedo / pi * E`.
fn lit_receiver() -> (SceneDescription, f64) {
    let (mut d, expected) = receiver_under_square_light(0.5, 1.0, 2.0, 0.8);
    d.sampler.samples_per_pixel = 256;
    (d, f64::from(expected.g))
}

/// A black square of half-side `s` centred at `c` with normal `n`, uv from 0 to 1 across.
fn sheet(c: Vec3, n: Vec3, s: f32, alpha: Option<FloatTexture>) -> ShapeDesc {
    let a = n.any_orthonormal_vector();
    let b = n.cross(a);
    ShapeDesc {
        geometry: GeometryDesc::TriangleMesh(TriangleMeshDesc {
            positions: vec![
                c - s * a - s * b,
                c + s * a - s * b,
                c + s * a + s * b,
                c - s * a + s * b,
            ],
            indices: vec![0, 1, 2, 0, 2, 3],
            normals: None,
            uvs: Some(vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(0.0, 1.0),
            ]),
            tangents: None,
        }),
        material: 0,
        area_light: None,
        flip_normals: false,
        alpha,
    }
}

/// A sheet halfway up between receiver and light, covering all of the light seen from
/// the receiver.
fn shadow_sheet(alpha: Option<FloatTexture>) -> ShapeDesc {
    sheet(Vec3::new(0.0, 0.5, 0.0), Vec3::Y, 0.4, alpha)
}

/// Halfway between the camera and the receiver, across every camera ray and no shadow ray.
const CAMERA_MIDPOINT: Vec3 = Vec3::new(0.5, 0.1, 0.15);

/// A sheet across the camera rays.
fn camera_sheet(alpha: Option<FloatTexture>) -> ShapeDesc {
    sheet(CAMERA_MIDPOINT, CAMERA_MIDPOINT.normalize(), 0.05, alpha)
}

/// Image mean within 4 standard errors plus `rel` relative of `expected`, every channel.
fn assert_close(d: &SceneDescription, expected: f64, rel: f64, label: &str) {
    let out = render_desc(d);
    assert_eq!(out.stats.nonfinite_samples, 0, "{label}");
    let (mean, se) = mean_and_standard_error(&out);
    for c in 0..3 {
        eprintln!(
            "{label}: {:.5} vs {expected:.5} (standard error {:.1e})",
            mean[c], se[c]
        );
        assert!(
            (mean[c] - expected).abs() <= 4.0 * se[c] + rel * expected + 1e-5,
            "{label}, channel {c}: {:.5} vs expected {expected:.5} (standard error {:.1e})",
            mean[c],
            se[c]
        );
    }
}

#[test]
fn alpha_zero_is_invisible_and_casts_no_shadow() {
    let (mut d, expected) = lit_receiver();
    d.shapes.push(shadow_sheet(Some(0.0.into())));
    d.shapes.push(camera_sheet(Some(0.0.into())));
    for strategy in DirectStrategy::ALL {
        let mut d = d.clone();
        d.integrator.direct = strategy;
        assert_close(&d, expected, 0.0, &format!("alpha 0, {}", strategy.name()));
    }
    // The same sheets opaque: black (the test can fail).
    let (mut opaque, _) = lit_receiver();
    opaque.shapes.push(shadow_sheet(Some(1.0.into())));
    assert_close(&opaque, 0.0, 0.0, "opaque shadow sheet");
}

#[test]
fn half_alpha_casts_half_a_shadow() {
    let (mut d, expected) = lit_receiver();
    d.shapes.push(shadow_sheet(Some(0.5.into())));
    for strategy in [DirectStrategy::Mis, DirectStrategy::LightArea, DirectStrategy::Bsdf] {
        let mut d = d.clone();
        d.integrator.direct = strategy;
        assert_close(
            &d,
            0.5 * expected,
            0.0,
            &format!("shadow alpha 0.5, {}", strategy.name()),
        );
    }
}

#[test]
fn half_alpha_is_half_transparent_to_camera_rays() {
    let (mut d, expected) = lit_receiver();
    d.shapes.push(camera_sheet(Some(0.5.into())));
    assert_close(&d, 0.5 * expected, 0.0, "camera alpha 0.5");
}

#[test]
fn ignored_hits_continue_to_the_back_of_a_sphere() {
    // Camera rays cross both surfaces of a half-transparent sphere: 1/4 gets through.
    let (mut d, expected) = lit_receiver();
    d.shapes.push(ShapeDesc {
        geometry: GeometryDesc::full_sphere(0.05, Transform::new(Mat4::from_translation(CAMERA_MIDPOINT)).unwrap()),
        material: 0,
        area_light: None,
        flip_normals: false,
        alpha: Some(0.5.into()),
    });
    assert_close(&d, 0.25 * expected, 0.0, "sphere alpha 0.5");
}

#[test]
fn checkerboard_alpha_shadows_by_its_coverage() {
    // Fine checks, half of them cut out: half the light gets through, up to the
    // checks' discreteness (allowed 3%).
    let checks = Texture::Checkerboard(Arc::new(CheckerboardTexture {
        mapping: TextureMapping::Uv {
            su: 40.0,
            sv: 40.0,
            du: 0.0,
            dv: 0.0,
        },
        tex1: 1.0.into(),
        tex2: 0.0.into(),
    }));
    let (mut d, expected) = lit_receiver();
    d.shapes.push(shadow_sheet(Some(checks)));
    for strategy in [DirectStrategy::Mis, DirectStrategy::Bsdf] {
        let mut d = d.clone();
        d.integrator.direct = strategy;
        assert_close(
            &d,
            0.5 * expected,
            0.03,
            &format!("checkerboard alpha, {}", strategy.name()),
        );
    }
}

#[test]
fn instanced_shapes_honour_alpha() {
    let (mut d, expected) = lit_receiver();
    d.objects.push(ObjectDesc {
        shapes: vec![shadow_sheet(Some(0.5.into()))],
    });
    d.instances.push(InstanceDesc {
        object: 0,
        world_from_instance: Transform::new(Mat4::from_translation(Vec3::new(0.0, 0.1, 0.0))).unwrap(),
    });
    assert_close(&d, 0.5 * expected, 0.0, "instanced alpha 0.5");
}

#[test]
fn emitters_emit_only_where_present() {
    // Every strategy, whether it finds the light by rays or samples points on it, sees
    // half the emission of a half-present light and none of a cut-out one.
    for (alpha, fraction) in [(0.5, 0.5), (0.0, 0.0)] {
        let (mut d, expected) = lit_receiver();
        let light = d.shapes.iter_mut().find(|s| s.area_light.is_some()).unwrap();
        light.alpha = Some(FloatTexture::Constant(alpha));
        for strategy in DirectStrategy::ALL {
            let mut d = d.clone();
            d.integrator.direct = strategy;
            assert_close(
                &d,
                fraction * expected,
                0.0,
                &format!("light alpha {alpha}, {}", strategy.name()),
            );
        }
    }
}

#[test]
fn stochastic_alpha_is_deterministic() {
    let (mut d, _) = lit_receiver();
    d.shapes.push(shadow_sheet(Some(0.5.into())));
    d.shapes.push(camera_sheet(Some(0.3.into())));
    d.sampler.samples_per_pixel = 16;
    let scene = Scene::build(&d).unwrap();
    let image = |threads| {
        let options = RenderOptions {
            threads: Some(threads),
            ..RenderOptions::default()
        };
        let out = render(&scene, &options, &|_, _| {}).unwrap();
        out.film.pixels().iter().map(|p| p.mean()).collect::<Vec<Rgb>>()
    };
    let once = image(1);
    assert_eq!(once, image(1));
    assert_eq!(once, image(2));
}
