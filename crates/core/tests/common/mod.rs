//! Helpers shared by the integration tests: small scenes built directly as descriptions,
//! and statistical assertions.
#![allow(dead_code, missing_docs)]

pub mod direct_loops;

use mcrender_core::color::Rgb;
use mcrender_core::material::DiffuseMaterial;
use mcrender_core::math::{Mat4, Transform, Vec2, Vec3, PI};
use mcrender_core::render::{render, RenderOptions, RenderOutput};
use mcrender_core::scene::*;

/// A scene with no shapes, a black diffuse material 0, and a 4x4 film.
pub fn empty_scene() -> SceneDescription {
    SceneDescription {
        camera: CameraDesc::default(),
        film: FilmDesc { width: 4, height: 4 },
        filter: FilterDesc::Box {
            radius: Vec2::splat(0.5),
        },
        reconstruction: Reconstruction::default(),
        sampler: SamplerDesc {
            samples_per_pixel: 64,
            ..Default::default()
        },
        integrator: IntegratorDesc::default(),
        materials: vec![MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::BLACK.into(),
        })],
        shapes: vec![],
        lights: vec![],
        objects: vec![],
        instances: vec![],
    }
}

/// A camera at the centre of a sphere of `radius` with albedo `albedo`, optionally
/// emitting. `inward` flips the sphere's normals (pbrt ReverseOrientation).
pub fn inside_sphere_scene(
    radius: f32,
    albedo: Rgb,
    emission: Option<AreaLightDesc>,
    inward: bool,
) -> SceneDescription {
    let mut d = empty_scene();
    d.materials.push(MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: albedo.into(),
    }));
    d.camera.fov_degrees = 60.0;
    d.shapes.push(ShapeDesc {
        geometry: GeometryDesc::full_sphere(radius, Transform::IDENTITY),
        material: 1,
        area_light: emission,
        flip_normals: inward,
        alpha: None,
    });
    d
}

/// A 0.2 x 0.2 diffuse square at the origin facing +y.
pub fn add_receiver(d: &mut SceneDescription, albedo: f32) {
    d.materials.push(MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: Rgb::splat(albedo).into(),
    }));
    let s = 0.1;
    d.shapes.push(ShapeDesc {
        geometry: GeometryDesc::TriangleMesh(TriangleMeshDesc {
            positions: vec![
                Vec3::new(-s, 0.0, -s),
                Vec3::new(s, 0.0, -s),
                Vec3::new(s, 0.0, s),
                Vec3::new(-s, 0.0, s),
            ],
            indices: vec![0, 2, 1, 0, 3, 2],
            normals: None,
            uvs: None,
            tangents: None,
        }),
        material: (d.materials.len() - 1) as u32,
        area_light: None,
        flip_normals: false,
        alpha: None,
    });
}

/// A square of half-side `s` at height `h` above the origin, emitting `l` downwards.
pub fn add_square_light(d: &mut SceneDescription, s: f32, h: f32, l: Rgb) {
    let square = GeometryDesc::TriangleMesh(TriangleMeshDesc {
        positions: vec![
            Vec3::new(-s, h, -s),
            Vec3::new(s, h, -s),
            Vec3::new(s, h, s),
            Vec3::new(-s, h, s),
        ],
        indices: vec![0, 1, 2, 0, 2, 3],
        normals: None,
        uvs: None,
        tangents: None,
    });
    add_emitter(d, square, l);
}

/// A shape of `geometry` (material 0, one-sided) emitting `l`.
pub fn add_emitter(d: &mut SceneDescription, geometry: GeometryDesc, l: Rgb) {
    d.shapes.push(ShapeDesc {
        geometry,
        material: 0,
        area_light: Some(AreaLightDesc {
            radiance: l,
            two_sided: false,
            power: None,
        }),
        flip_normals: false,
        alpha: None,
    });
}

/// A sphere light of radius `r` at `centre`.
pub fn add_sphere_light(d: &mut SceneDescription, r: f32, centre: Vec3, l: Rgb) {
    let world_from_object = Transform::new(Mat4::from_translation(centre) * Mat4::from_scale(Vec3::splat(r))).unwrap();
    add_emitter(d, GeometryDesc::full_sphere(1.0, world_from_object), l);
}

/// A disk of radius `r` at height `h` above the origin, emitting `l` downwards: object
/// space `z` is mapped to world `-y` by a rotation, as a pbrt scene would place it.
pub fn add_disk_light(d: &mut SceneDescription, r: f32, h: f32, l: Rgb) {
    let disk = GeometryDesc::Disk {
        height: 0.0,
        radius: r,
        inner_radius: 0.0,
        phi_max: 2.0 * std::f32::consts::PI,
        world_from_object: Transform::new(
            Mat4::from_translation(Vec3::new(0.0, h, 0.0)) * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2),
        )
        .unwrap(),
    };
    add_emitter(d, disk, l);
}

/// A camera low beside the receiver, looking at its centre with a tiny field of view, so
/// every pixel sees (nearly) the receiver's centre.
pub fn aim_at_receiver(d: &mut SceneDescription) {
    let eye = Vec3::new(1.0, 0.2, 0.3);
    // pbrt's camera looks down +z: world_from_camera maps +z to the viewing direction.
    let camera_from_world = Mat4::look_at_lh(eye, Vec3::ZERO, Vec3::Y);
    d.camera.world_from_camera = Transform::new(camera_from_world).unwrap().inverse();
    d.camera.fov_degrees = 0.5;
}

/// Render with the default options.
pub fn render_desc(d: &SceneDescription) -> RenderOutput {
    let scene = Scene::build(d).expect("valid scene");
    render(&scene, &RenderOptions::default(), &|_, _| {}).expect("render")
}

/// Assert that the image mean equals `expected` within 4 standard errors per channel,
/// the standard error estimated from the per-pixel variances of the render itself.
pub fn assert_mean_radiance(d: &SceneDescription, expected: Rgb) {
    let out = render_desc(d);
    let (mean, se) = mean_and_standard_error(&out);
    for c in 0..3 {
        let e = f64::from(expected[c]);
        let tol = 4.0 * se[c] + 1e-6 * e.abs().max(1e-3);
        assert!(
            (mean[c] - e).abs() <= tol,
            "channel {c}: mean {:.6} vs expected {e:.6}; |diff| {:.2e} > 4 standard errors {:.2e}",
            mean[c],
            (mean[c] - e).abs(),
            4.0 * se[c]
        );
        eprintln!(
            "channel {c}: mean {:.6}, expected {e:.6}, standard error {:.2e}",
            mean[c], se[c]
        );
    }
    assert_eq!(out.stats.nonfinite_samples, 0, "non-finite samples");
}

/// Image mean per channel and its standard error (from the per-pixel variances).
pub fn mean_and_standard_error(out: &RenderOutput) -> ([f64; 3], [f64; 3]) {
    let n = out.film.pixels().len() as f64;
    let mut mean = [0.0; 3];
    let mut se = [0.0; 3];
    for c in 0..3 {
        mean[c] = out.film.pixels().iter().map(|p| f64::from(p.mean()[c])).sum::<f64>() / n;
        let var: f64 = out
            .film
            .pixels()
            .iter()
            .map(|p| f64::from(p.variance_of_mean()[c]))
            .sum::<f64>()
            / (n * n);
        se[c] = var.sqrt();
    }
    (mean, se)
}

/// Average over pixels of the variance of the pixel estimate (luminance).
pub fn mean_pixel_variance(out: &RenderOutput) -> f64 {
    let n = out.film.pixels().len() as f64;
    out.film
        .pixels()
        .iter()
        .map(|p| f64::from(p.variance_of_mean().luminance()))
        .sum::<f64>()
        / n
}

/// Irradiance at a point below the centre of a square emitter of half-side `s` at height
/// `h` with radiance `l`, facing it: `E = pi L F`, where the view factor is four corners of
/// F = 1/(2 pi) [X/sqrt(1+X^2) atan(Y/sqrt(1+X^2)) + Y/sqrt(1+Y^2) atan(X/sqrt(1+Y^2))],
/// X = a/c, Y = b/c, for a point below the corner of an a x b rectangle at distance c.
pub fn square_light_irradiance(s: f32, h: f32, l: f32) -> f32 {
    let corner = |a: f32, b: f32, c: f32| {
        let (x, y) = (a / c, b / c);
        let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
        (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * std::f32::consts::PI)
    };
    std::f32::consts::PI * l * 4.0 * corner(s, s, h)
}

/// A closed sphere of `radius` and albedo `albedo` emitting `le` inwards, the camera at its
/// centre: every point sees L from everywhere, so L = le + albedo L, L = le / (1 - albedo)
/// (le (1 - albedo^(D+1)) / (1 - albedo) up to depth D).
pub fn emissive_sphere(radius: f32, albedo: Rgb, le: Rgb) -> SceneDescription {
    let emission = AreaLightDesc {
        radiance: le,
        two_sided: false,
        power: None,
    };
    inside_sphere_scene(radius, albedo, Some(emission), true)
}

/// A diffuse sphere of radius 1 and albedo 1/2 with a point light of intensity
/// `intensity` at its centre (where the camera is). With intensity pi the direct radiance
/// is (a/pi)(I/r^2) = 1/2, and depth k carries 2^-k: L = 1 - 2^-D up to depth D, 1 in all.
pub fn point_lit_sphere(intensity: f32) -> SceneDescription {
    let mut d = inside_sphere_scene(1.0, Rgb::splat(0.5), None, false);
    d.lights.push(LightDesc::Point {
        position: Vec3::ZERO,
        intensity: Rgb::splat(intensity),
    });
    d
}

/// The receiver of [`add_receiver`] (albedo `rho`) seen by [`aim_at_receiver`], direct
/// light only (max depth 1), inside a sphere of radius 50 emitting `l` inwards (a uniform
/// sky: the irradiance is pi l); and its radiance, rho l.
pub fn receiver_under_sky(l: f32, rho: f32) -> (SceneDescription, Rgb) {
    let mut d = emissive_sphere(50.0, Rgb::BLACK, Rgb::splat(l));
    add_receiver(&mut d, rho);
    aim_at_receiver(&mut d);
    d.integrator.max_depth = 1;
    (d, Rgb::splat(rho * l))
}

/// The receiver of [`add_receiver`] (albedo `rho`) seen by [`aim_at_receiver`], direct
/// light only, under a square light of half-side `s` at height `h` emitting `l`; and its
/// radiance, rho / pi E with E from [`square_light_irradiance`].
pub fn receiver_under_square_light(s: f32, h: f32, l: f32, rho: f32) -> (SceneDescription, Rgb) {
    let mut d = empty_scene();
    add_receiver(&mut d, rho);
    add_square_light(&mut d, s, h, Rgb::splat(l));
    aim_at_receiver(&mut d);
    d.integrator.max_depth = 1;
    (d, Rgb::splat(rho / PI * square_light_irradiance(s, h, l)))
}

/// The receiver of [`add_receiver`] (albedo `rho`) seen by [`aim_at_receiver`], direct
/// light only, under a sphere light of radius `r` emitting `l` at distance `dist` above it:
/// E = pi l (r/dist)^2, so the radiance is rho l (r/dist)^2.
pub fn receiver_under_sphere_light(r: f32, dist: f32, l: f32, rho: f32) -> (SceneDescription, Rgb) {
    let mut d = empty_scene();
    add_receiver(&mut d, rho);
    add_sphere_light(&mut d, r, Vec3::new(0.0, dist, 0.0), Rgb::splat(l));
    aim_at_receiver(&mut d);
    d.integrator.max_depth = 1;
    (d, Rgb::splat(rho * l * (r / dist) * (r / dist)))
}

/// The receiver of [`add_receiver`] (albedo `rho`) seen by [`aim_at_receiver`], direct
/// light only, under a disk light of radius `r` at height `h` on its axis emitting `l`
/// downwards: E = pi l r^2 / (r^2 + h^2), so the radiance is rho l r^2 / (r^2 + h^2).
pub fn receiver_under_disk_light(r: f32, h: f32, l: f32, rho: f32) -> (SceneDescription, Rgb) {
    let mut d = empty_scene();
    add_receiver(&mut d, rho);
    add_disk_light(&mut d, r, h, Rgb::splat(l));
    aim_at_receiver(&mut d);
    d.integrator.max_depth = 1;
    (d, Rgb::splat(rho / PI * (PI * l * r * r / (r * r + h * h))))
}

/// The receiver of [`add_receiver`] (albedo `rho`) seen by [`aim_at_receiver`], direct
/// light only, on the axis of an open cylinder of radius `r` spanning heights `a..b` above
/// it (world `y`), emitting `l` inwards. A wall point at height `y` is seen at polar angle
/// `theta` with `tan theta = r / y`, so `E = L int cos dw = pi L (sin^2 theta_a -
/// sin^2 theta_b) = pi L (r^2 / (r^2 + a^2) - r^2 / (r^2 + b^2))`; the radiance is
/// `rho / pi E`.
pub fn receiver_inside_cylinder_light(r: f32, a: f32, b: f32, l: f32, rho: f32) -> (SceneDescription, Rgb) {
    let mut d = empty_scene();
    add_receiver(&mut d, rho);
    // Object z along world y.
    let world_from_object = Transform::new(Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2)).unwrap();
    let cylinder = GeometryDesc::Cylinder {
        radius: r,
        z_min: a,
        z_max: b,
        phi_max: 2.0 * PI,
        world_from_object,
    };
    add_emitter(&mut d, cylinder, Rgb::splat(l));
    d.shapes.last_mut().expect("the cylinder").flip_normals = true;
    aim_at_receiver(&mut d);
    d.integrator.max_depth = 1;
    let e = PI * l * (r * r / (r * r + a * a) - r * r / (r * r + b * b));
    (d, Rgb::splat(rho / PI * e))
}

/// A closed can (an open cylinder of radius `r` from `z = -h` to `h` with two disks for
/// lids) of albedo `albedo`, every part emitting `le` inwards, the camera at its centre:
/// as inside an emissive sphere, L = le / (1 - albedo) at unbounded depth.
pub fn emissive_can(r: f32, h: f32, albedo: Rgb, le: Rgb) -> SceneDescription {
    let mut d = inside_sphere_scene(1.0, albedo, None, false);
    d.shapes.clear();
    let emission = Some(AreaLightDesc {
        radiance: le,
        two_sided: false,
        power: None,
    });
    let lid = |height: f32| GeometryDesc::Disk {
        height,
        radius: r,
        inner_radius: 0.0,
        phi_max: 2.0 * PI,
        world_from_object: Transform::IDENTITY,
    };
    let cylinder = GeometryDesc::Cylinder {
        radius: r,
        z_min: -h,
        z_max: h,
        phi_max: 2.0 * PI,
        world_from_object: Transform::IDENTITY,
    };
    // Inwards: the wall and the top lid flipped; the bottom lid's +z already faces in.
    for (geometry, flip_normals) in [(cylinder, true), (lid(h), true), (lid(-h), false)] {
        d.shapes.push(ShapeDesc {
            geometry,
            material: 1,
            area_light: emission,
            flip_normals,
            alpha: None,
        });
    }
    d
}

/// Assert that an estimate `(mean, standard error)` per channel is `expected` within 4
/// standard errors (and a relative 1e-5 for rounding).
pub fn assert_close(label: &str, (mean, se): ([f64; 3], [f64; 3]), expected: Rgb) {
    for c in 0..3 {
        let e = f64::from(expected[c]);
        let tol = 4.0 * se[c] + 1e-5 * e.abs().max(1e-3);
        eprintln!("{label} channel {c}: {:.5} vs {e:.5} (se {:.2e})", mean[c], se[c]);
        assert!(
            (mean[c] - e).abs() <= tol,
            "{label}, channel {c}: {:.5} vs closed form {e:.5} (standard error {:.2e})",
            mean[c],
            se[c]
        );
    }
}
