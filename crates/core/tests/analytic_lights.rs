//! Analytic scenes for the lights that are not shapes: a diffuse receiver of albedo rho
//! under a uniform sky, an environment map, a distant light and a spot light, each with a
//! closed-form (or exactly summed) irradiance E, so the receiver's radiance is rho E / pi.
//! Every render's mean must agree within 4 standard errors of the render's own samples.

mod common;

use common::*;
use mcrender_core::color::Rgb;
use mcrender_core::light::Light;
use mcrender_core::math::{Mat4, Transform, Vec2, Vec3, PI};
use mcrender_core::sampling::equal_area_square_to_sphere;
use mcrender_core::scene::{
    AreaLightDesc, EnvMapping, ImageInfiniteLightDesc, LightDesc, RgbImageDesc, Scene, SpotFalloff, SpotLightDesc,
};

/// The receiver (normal +y) seen by a narrow camera, direct lighting only.
fn receiver_scene(rho: f32, spp: u32) -> mcrender_core::scene::SceneDescription {
    let mut d = empty_scene();
    add_receiver(&mut d, rho);
    aim_at_receiver(&mut d);
    d.integrator.max_depth = 1;
    d.sampler.samples_per_pixel = spp;
    d
}

/// Light space +z to world +y.
fn z_up_to_y_up() -> Transform {
    Transform::new(Mat4::from_rotation_x(-PI / 2.0)).unwrap()
}

/// Under a uniform sky L the irradiance is pi L: radiance rho L, with MIS between the
/// uniform-sphere light samples and the BSDF samples that escape.
#[test]
fn uniform_sky_gives_radiance_rho_l() {
    let (rho, l) = (0.8, Rgb::new(1.5, 0.5, 1.0));
    let mut d = receiver_scene(rho, 1024);
    d.lights.push(LightDesc::UniformInfinite { radiance: l });
    assert_mean_radiance(&d, l * rho);
    // Deeper paths change nothing: there is nothing else to bounce off.
    d.integrator.max_depth = 5;
    assert_mean_radiance(&d, l * rho);
}

/// Camera rays that miss everything see the sky itself (depth 0, unweighted).
#[test]
fn escaped_camera_rays_see_the_sky() {
    let l = Rgb::new(0.25, 0.5, 2.0);
    let mut d = empty_scene();
    d.sampler.samples_per_pixel = 4;
    d.lights.push(LightDesc::UniformInfinite { radiance: l });
    assert_mean_radiance(&d, l);
}

/// A constant environment map renders as the uniform sky of its colour, in either layout.
#[test]
fn constant_env_map_renders_as_a_uniform_sky() {
    let (rho, c) = (0.7, Rgb::new(0.4, 1.2, 0.9));
    for (mapping, w, h) in [(EnvMapping::EqualArea, 4, 4), (EnvMapping::Equirect, 8, 4)] {
        let mut d = receiver_scene(rho, 1024);
        d.lights.push(LightDesc::ImageInfinite(ImageInfiniteLightDesc {
            image: RgbImageDesc {
                width: w,
                height: h,
                pixels: vec![c; (w * h) as usize],
            },
            mapping,
            scale: 2.0,
            world_from_light: z_up_to_y_up(),
        }));
        assert_mean_radiance(&d, c * (2.0 * rho));
    }
}

/// An equirect map with sky colour A in its upper half (+z, rotated to world +y) and
/// ground colour B below: the receiver facing up sees only the sky, E = pi A.
#[test]
fn rotated_equirect_sky_and_ground() {
    let (rho, a, b) = (0.9, Rgb::new(1.0, 2.0, 3.0), Rgb::new(5.0, 0.0, 5.0));
    let (w, h) = (8u32, 6u32);
    let pixels = (0..w * h).map(|i| if i / w < h / 2 { a } else { b }).collect();
    let mut d = receiver_scene(rho, 1024);
    d.lights.push(LightDesc::ImageInfinite(ImageInfiniteLightDesc {
        image: RgbImageDesc {
            width: w,
            height: h,
            pixels,
        },
        mapping: EnvMapping::Equirect,
        scale: 1.0,
        world_from_light: z_up_to_y_up(),
    }));
    assert_mean_radiance(&d, a * rho);
}

/// An equal-area map with a bright spot, rotated: the irradiance on the receiver is the sum
/// over a fine grid of the square of `L(uv) max(0, n . w(uv)) 4 pi / N`.
#[test]
fn equal_area_env_map_with_a_bright_spot() {
    let n = 8u32;
    let mut pixels = vec![Rgb::splat(0.3); (n * n) as usize];
    pixels[(2 * n + 5) as usize] = Rgb::new(60.0, 40.0, 20.0);
    pixels[(3 * n + 3) as usize] = Rgb::new(0.0, 8.0, 0.0);
    let world_from_light = Transform::new(Mat4::from_rotation_x(-PI / 2.0) * Mat4::from_rotation_z(0.4)).unwrap();
    let rho = 0.6;
    let mut d = receiver_scene(rho, 2048);
    let desc = ImageInfiniteLightDesc {
        image: RgbImageDesc {
            width: n,
            height: n,
            pixels: pixels.clone(),
        },
        mapping: EnvMapping::EqualArea,
        scale: 1.0,
        world_from_light,
    };
    d.lights.push(LightDesc::ImageInfinite(desc));
    // Irradiance by a midpoint rule with 1024^2 points (128^2 per pixel).
    let m = 1024u32;
    let mut e = [0.0f64; 3];
    for j in 0..m {
        for i in 0..m {
            let uv = Vec2::new((i as f32 + 0.5) / m as f32, (j as f32 + 0.5) / m as f32);
            let w = world_from_light.vector(equal_area_square_to_sphere(uv));
            let cos = f64::from(w.y.max(0.0));
            let p = pixels[((j * n / m) * n + i * n / m) as usize];
            for c in 0..3 {
                e[c] += f64::from(p[c]) * cos;
            }
        }
    }
    let k = 4.0 * std::f64::consts::PI / f64::from(m * m) * f64::from(rho) / std::f64::consts::PI;
    assert_mean_radiance(&d, Rgb::new((e[0] * k) as f32, (e[1] * k) as f32, (e[2] * k) as f32));
}

/// A distant light of radiance E at angle theta from the normal: irradiance E cos theta.
#[test]
fn distant_light_irradiance_is_e_cos_theta() {
    let (rho, e) = (0.5, Rgb::new(3.0, 2.0, 1.0));
    let direction = Vec3::new(0.3, 1.0, 0.2).normalize();
    let mut d = receiver_scene(rho, 16);
    d.lights.push(LightDesc::Distant { direction, radiance: e });
    assert_mean_radiance(&d, e * (rho * direction.y / PI));
    // From below the receiver, nothing arrives on the visible side.
    d.lights[0] = LightDesc::Distant {
        direction: -direction,
        radiance: e,
    };
    assert_mean_radiance(&d, Rgb::BLACK);
}

/// The receiver of [`receiver_scene`] under a spot of intensity `i` 100 above it, its axis
/// tilted by `alpha` from straight down, falling off between the angles `start` and `end`.
fn spot_receiver(
    rho: f32,
    i: Rgb,
    alpha: f32,
    (start, end): (f32, f32),
    falloff: SpotFalloff,
) -> mcrender_core::scene::SceneDescription {
    // Light-space +z points down (-y), tilted by alpha about x.
    let m = Mat4::from_translation(Vec3::new(0.0, 100.0, 0.0))
        * Mat4::from_rotation_x(alpha)
        * Mat4::from_rotation_x(PI / 2.0);
    let mut d = receiver_scene(rho, 16);
    d.lights.push(LightDesc::Spot(SpotLightDesc {
        world_from_light: Transform::new(m).unwrap(),
        intensity: i,
        cos_falloff_start: start.cos(),
        cos_falloff_end: end.cos(),
        falloff,
        projection: None,
    }));
    d
}

/// A spot light 100 above the receiver, tilted so the receiver's centre is at angle alpha
/// off its axis: E = I falloff(alpha) / 100^2 (the receiver faces the light, cos = 1). The
/// distance keeps the variation of r^2 and of the angle across the pixels' footprint on the
/// receiver (+-0.01) below 1e-8: every sample has the same value, so the standard error
/// is about zero and only rounding is tolerated.
#[test]
fn spot_light_irradiance_follows_the_falloff() {
    let (rho, i) = (0.8, Rgb::new(1e4, 2e4, 5e3));
    let (start, end) = (15.0f32.to_radians(), 30.0f32.to_radians());
    for alpha_deg in [10.0f32, 22.5, 35.0] {
        let alpha = alpha_deg.to_radians();
        let d = spot_receiver(rho, i, alpha, (start, end), SpotFalloff::SmoothCosine);
        let t = ((alpha.cos() - end.cos()) / (start.cos() - end.cos())).clamp(0.0, 1.0);
        let falloff = t * t * (3.0 - 2.0 * t);
        eprintln!("alpha {alpha_deg}: falloff {falloff}");
        assert_mean_radiance(&d, i * (rho / PI * falloff / 1e4));
    }
}

/// Mitsuba 3's spot (linear in angle), set up as the test above: E = I falloff(alpha) /
/// 100^2 with falloff 1 inside the beam width, `(end - alpha) / (end - start)` in the
/// ramp and 0 beyond the cutoff.
#[test]
fn mitsuba_spot_irradiance_ramps_linearly_in_angle() {
    let (rho, i) = (0.8, Rgb::new(1e4, 2e4, 5e3));
    let (start, end) = (15.0f32.to_radians(), 30.0f32.to_radians());
    for alpha_deg in [10.0f32, 18.0, 26.0, 35.0] {
        let alpha = alpha_deg.to_radians();
        let d = spot_receiver(rho, i, alpha, (start, end), SpotFalloff::LinearAngle);
        let falloff = ((end - alpha) / (end - start)).clamp(0.0, 1.0);
        eprintln!("alpha {alpha_deg}: falloff {falloff}");
        assert_mean_radiance(&d, i * (rho / PI * falloff / 1e4));
    }
}

/// pbrt-v4's area-light `power`: every primitive's radiance becomes
/// `power / (pi A sides)`, per primitive (triangle), as pbrt makes one light per triangle.
#[test]
fn area_light_power_normalises_each_primitive() {
    let mut d = empty_scene();
    add_square_light(&mut d, 0.5, 1.0, Rgb::new(1.0, 0.5, 2.0));
    d.shapes[0].area_light = Some(AreaLightDesc {
        radiance: Rgb::new(1.0, 0.5, 2.0),
        two_sided: true,
        power: Some(10.0),
    });
    let scene = Scene::build(&d).unwrap();
    assert_eq!(scene.lights.len(), 2);
    for l in &scene.lights {
        let Light::DiffuseArea(a) = l else { panic!("{l:?}") };
        let k = 10.0 / (PI * 2.0 * 0.5);
        assert!((a.radiance.g - 0.5 * k).abs() < 1e-5 * k, "{:?}", a.radiance);
        assert!((l.power().r - 10.0).abs() < 1e-4, "{:?}", l.power());
    }
}

/// Every direct-lighting strategy finds the infinite lights: by sampling them
/// (`light-area`, `mis`) or by rays that leave the scene (`bsdf`, the hemisphere
/// techniques), with 1 and 3 samples per vertex.
#[test]
fn every_direct_strategy_sees_infinite_lights() {
    use mcrender_core::scene::DirectStrategy;
    let (rho, l) = (0.8, Rgb::new(1.5, 0.5, 1.0));
    for strategy in DirectStrategy::ALL {
        for samples in [1, 3] {
            let mut d = receiver_scene(rho, 256);
            d.integrator.direct = strategy;
            d.integrator.light_samples = samples;
            d.lights.push(LightDesc::UniformInfinite { radiance: l });
            eprintln!("{} x{samples}", strategy.name());
            assert_mean_radiance(&d, l * rho);
        }
    }
}
