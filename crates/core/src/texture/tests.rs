//! Tests of the MIP map, the texture classes and the screen-space footprints.

use std::sync::Arc;

use super::*;
use crate::camera::CameraDesc;
use crate::camera::PerspectiveCamera;
use crate::film::FilmDesc;
use crate::math::{Transform, Vec2, Vec3};
use crate::shape::{Interaction, SurfaceInteraction};

fn close(a: Rgb, b: Rgb, tol: f32) -> bool {
    (0..3).all(|c| (a[c] - b[c]).abs() <= tol)
}

/// A deterministic non-constant image.
fn pattern(w: u32, h: u32) -> Vec<Rgb> {
    (0..w * h)
        .map(|i| {
            let x = (i * 2_654_435_761u32) >> 16;
            Rgb::new((x % 97) as f32 / 97.0, (x % 13) as f32 / 13.0, (i % 7) as f32)
        })
        .collect()
}

fn ctx_at(uv: Vec2) -> TextureContext {
    TextureContext {
        uv,
        ..TextureContext::default()
    }
}

#[test]
fn every_level_keeps_the_image_mean() {
    for (w, h) in [(8, 8), (5, 3), (1, 7), (16, 2)] {
        let pixels = pattern(w, h);
        let m = MipMap::new(w, h, &pixels, WrapMode::Repeat);
        let base = MipLevel {
            width: w as usize,
            height: h as usize,
            texels: pixels,
        }
        .mean();
        let levels = m.levels();
        assert_eq!(levels.last().map(|l| (l.width, l.height)), Some((1, 1)));
        assert!(levels[0].width.is_power_of_two() && levels[0].height.is_power_of_two());
        for (i, l) in levels.iter().enumerate() {
            assert!(
                close(l.mean(), base, 1e-5),
                "{w}x{h} level {i}: {:?} vs {base:?}",
                l.mean()
            );
        }
    }
}

#[test]
fn a_constant_image_gives_the_constant_for_every_filter() {
    let c = Rgb::new(0.25, 0.5, 0.75);
    for wrap in [WrapMode::Repeat, WrapMode::Clamp, WrapMode::OctahedralSphere] {
        let m = MipMap::new(7, 5, &vec![c; 35], wrap);
        for filter in [
            MipFilter::Point,
            MipFilter::Bilinear,
            MipFilter::Trilinear,
            MipFilter::Ewa,
        ] {
            let options = MipFilterOptions {
                filter,
                max_anisotropy: 8.0,
            };
            for (st, d0, d1) in [
                (Vec2::new(0.3, 0.7), Vec2::ZERO, Vec2::ZERO),
                (Vec2::new(0.01, 0.99), Vec2::new(0.01, 0.0), Vec2::new(0.0, 0.02)),
                (Vec2::new(0.5, 0.5), Vec2::new(0.1, 0.05), Vec2::new(-0.02, 0.03)),
                (Vec2::new(0.9, 0.1), Vec2::new(0.6, 0.0), Vec2::new(0.0, 0.001)),
                (Vec2::new(0.2, 0.2), Vec2::new(3.0, 0.0), Vec2::new(0.0, 3.0)),
            ] {
                let v = m.filter(&options, st, d0, d1);
                assert!(close(v, c, 1e-5), "{filter:?} {wrap:?} at {st}: {v:?}");
            }
        }
    }
}

#[test]
fn point_and_bilinear_lookups_on_a_2x2_image() {
    let (a, b, c, d) = (Rgb::splat(1.0), Rgb::splat(2.0), Rgb::splat(4.0), Rgb::splat(8.0));
    // Row 0 (top): a b; row 1: c d.
    let pixels = [a, b, c, d];
    let m = MipMap::new(2, 2, &pixels, WrapMode::Repeat);
    let point = MipFilterOptions {
        filter: MipFilter::Point,
        max_anisotropy: 8.0,
    };
    let bilinear = MipFilterOptions::default();
    let zero = Vec2::ZERO;
    let look = |o: &MipFilterOptions, s: f32, t: f32| m.filter(o, Vec2::new(s, t), zero, zero);
    assert_eq!(look(&point, 0.25, 0.25), a);
    assert_eq!(look(&point, 0.7, 0.2), b);
    assert_eq!(look(&point, 0.2, 0.8), c);
    assert_eq!(look(&point, 0.9, 0.9), d);
    assert_eq!(look(&bilinear, 0.25, 0.25), a);
    assert_eq!(look(&bilinear, 0.5, 0.5), (a + b + c + d) * 0.25);
    assert_eq!(look(&bilinear, 0.25, 0.5), (a + c) * 0.5);
    assert_eq!(look(&bilinear, 0.5, 0.75), (c + d) * 0.5);
    assert_eq!(look(&bilinear, 0.375, 0.25), a * 0.75 + b * 0.25);
    // Across the left edge the wrap mode decides the neighbour.
    for (wrap, expected) in [
        (WrapMode::Repeat, (a + b) * 0.5),
        (WrapMode::Clamp, a),
        (WrapMode::Black, a * 0.5),
    ] {
        let m = MipMap::new(2, 2, &pixels, wrap);
        assert_eq!(m.bilerp(0, Vec2::new(0.0, 0.25)), expected, "{wrap:?}");
    }
}

#[test]
fn wrap_modes_remap_texel_coordinates() {
    let l = MipLevel {
        width: 3,
        height: 2,
        texels: (0..6).map(|i| Rgb::splat(i as f32)).collect(),
    };
    let at = |x, y, w| l.texel(x, y, w).r;
    assert_eq!(at(-1, 0, WrapMode::Repeat), 2.0);
    assert_eq!(at(3, 3, WrapMode::Repeat), 3.0);
    assert_eq!(at(-1, 0, WrapMode::Clamp), 0.0);
    assert_eq!(at(5, 7, WrapMode::Clamp), 5.0);
    assert_eq!(at(-1, 0, WrapMode::Black), 0.0);
    assert_eq!(at(1, 2, WrapMode::Black), 0.0);
    assert_eq!(at(2, 1, WrapMode::Black), 5.0);
    // Octahedral: mirrored across the edge and across the other axis' midline.
    assert_eq!(at(-1, 0, WrapMode::OctahedralSphere), 4.0); // (1, 1)
    assert_eq!(at(3, 0, WrapMode::OctahedralSphere), 5.0); // (2, 1)
    assert_eq!(at(0, -1, WrapMode::OctahedralSphere), 5.0); // (2, 1)
}

#[test]
fn trilinear_interpolates_between_the_two_levels_around_the_footprint() {
    let pixels = pattern(8, 8);
    let m = MipMap::new(8, 8, &pixels, WrapMode::Repeat);
    let options = MipFilterOptions {
        filter: MipFilter::Trilinear,
        max_anisotropy: 8.0,
    };
    // 4 levels (8, 4, 2, 1); level = 3 + log2(2 d) = 1.25 for d = 2^-2.75 / 2.
    let d = 2f32.powf(-1.75) / 2.0;
    let st = Vec2::new(0.3, 0.6);
    let v = m.filter(&options, st, Vec2::new(d, 0.0), Vec2::new(0.0, d * 0.5));
    let expected = m.bilerp(1, st) * 0.75 + m.bilerp(2, st) * 0.25;
    assert!(close(v, expected, 1e-5), "{v:?} vs {expected:?}");
    // The level-1 texel at (0, 0) is the average of the top-left 2x2 block.
    let block = (pixels[0] + pixels[1] + pixels[8] + pixels[9]) * 0.25;
    assert!(close(m.bilerp(1, Vec2::splat(0.125)), block, 1e-6));
}

#[test]
fn ewa_of_a_checker_image_tends_to_its_mean_for_wide_footprints() {
    let n = 64u32;
    let pixels: Vec<Rgb> = (0..n * n).map(|i| Rgb::splat(((i % n + i / n) % 2) as f32)).collect();
    let m = MipMap::new(n, n, &pixels, WrapMode::Repeat);
    let ewa = MipFilterOptions {
        filter: MipFilter::Ewa,
        max_anisotropy: 8.0,
    };
    // A footprint of about one texel sees the checker.
    let narrow = m.filter(
        &ewa,
        Vec2::splat(0.5 / n as f32),
        Vec2::new(0.2 / n as f32, 0.0),
        Vec2::ZERO,
    );
    assert!(narrow.r > 0.9 || narrow.r < 0.1, "{narrow:?}");
    for (d0, d1) in [
        (Vec2::new(0.1, 0.0), Vec2::new(0.0, 0.1)),
        (Vec2::new(0.2, 0.1), Vec2::new(-0.05, 0.1)),
        (Vec2::new(0.5, 0.0), Vec2::new(0.0, 0.001)),
    ] {
        for st in [Vec2::new(0.3, 0.4), Vec2::new(0.01, 0.77)] {
            let v = m.filter(&ewa, st, d0, d1);
            assert!((v.r - 0.5).abs() < 0.02, "{d0} {d1} at {st}: {v:?}");
        }
    }
}

#[test]
fn checkerboard_values_at_known_uvs_and_filtered_to_the_mean() {
    let board = CheckerboardTexture::<f32> {
        mapping: TextureMapping::Uv {
            su: 4.0,
            sv: 4.0,
            du: 0.0,
            dv: 0.0,
        },
        tex1: 1.0.into(),
        tex2: 3.0.into(),
    };
    let at = |u: f32, v: f32| board.evaluate(&ctx_at(Vec2::new(u, v)));
    assert_eq!(at(0.1, 0.1), 1.0); // (0.4, 0.4): square (0, 0), even
    assert_eq!(at(0.3, 0.1), 3.0); // (1.2, 0.4): odd
    assert_eq!(at(0.3, 0.3), 1.0); // (1.2, 1.2): even
    assert_eq!(at(0.1, 0.6), 1.0); // (0.4, 2.4): even
    assert_eq!(at(0.1, 0.8), 3.0); // (0.4, 3.2): odd
    assert_eq!(at(-0.1, 0.1), 3.0); // (-0.4, 0.4): odd
                                    // A footprint many squares wide averages the two.
    let wide = TextureContext {
        uv: Vec2::new(0.31, 0.17),
        dudx: 3.0,
        dvdy: 3.0,
        ..TextureContext::default()
    };
    assert!((board.evaluate(&wide) - 2.0).abs() < 0.02, "{}", board.evaluate(&wide));
    // A small footprint inside a square changes nothing.
    let small = TextureContext {
        uv: Vec2::new(0.1, 0.1),
        dudx: 0.001,
        dvdy: 0.001,
        ..TextureContext::default()
    };
    assert_eq!(board.evaluate(&small), 1.0);
}

#[test]
fn scale_and_mix_combine_their_inputs() {
    let ctx = ctx_at(Vec2::splat(0.5));
    let scale = RgbTexture::Scale(Arc::new(ScaleTexture {
        tex: Rgb::new(0.5, 1.0, 2.0).into(),
        scale: 0.5.into(),
    }));
    assert_eq!(scale.evaluate(&ctx), Rgb::new(0.25, 0.5, 1.0));
    let mix = RgbTexture::Mix(Arc::new(MixTexture {
        tex1: Rgb::splat(1.0).into(),
        tex2: Rgb::new(3.0, 5.0, 9.0).into(),
        amount: 0.25.into(),
    }));
    assert_eq!(mix.evaluate(&ctx), Rgb::new(1.5, 2.0, 3.0));
    // Nested: the amount itself a scaled texture.
    let mix = FloatTexture::Mix(Arc::new(MixTexture {
        tex1: 2.0.into(),
        tex2: 4.0.into(),
        amount: FloatTexture::Scale(Arc::new(ScaleTexture {
            tex: 0.5.into(),
            scale: 2.0.into(),
        })),
    }));
    assert_eq!(mix.evaluate(&ctx), 4.0);
}

#[test]
fn image_textures_flip_t_scale_invert_and_read_red_for_floats() {
    // Top row red-ish, bottom row dark.
    let top = Rgb::new(0.8, 0.2, 0.4);
    let bottom = Rgb::new(0.1, 0.0, 0.3);
    let image = |scale: f32, invert: bool| ImageTexture {
        mapping: TextureMapping::default(),
        mipmap: Arc::new(MipMap::new(1, 2, &[top, bottom], WrapMode::Clamp)),
        filter: MipFilterOptions {
            filter: MipFilter::Point,
            max_anisotropy: 8.0,
        },
        scale,
        invert,
    };
    let high_v = ctx_at(Vec2::new(0.5, 0.9));
    let low_v = ctx_at(Vec2::new(0.5, 0.1));
    assert_eq!(image(1.0, false).evaluate_rgb(&high_v), top);
    assert_eq!(image(1.0, false).evaluate_rgb(&low_v), bottom);
    assert_eq!(image(2.0, false).evaluate_rgb(&high_v), top * 2.0);
    let inverted = image(1.0, true).evaluate_rgb(&high_v);
    assert!(close(inverted, Rgb::new(0.2, 0.8, 0.6), 1e-6), "{inverted:?}");
    let inverted = image(2.0, true).evaluate_rgb(&high_v);
    assert!(close(inverted, Rgb::new(0.0, 0.6, 0.2), 1e-6), "{inverted:?}");
    let float = FloatTexture::Image(Arc::new(image(1.0, false)));
    assert_eq!(float.evaluate(&high_v), top.r);
}

/// A hit on the plane `z = d` in front of a camera at the origin looking down +z, with
/// `u = x / scale`, `v = y`.
fn plane_hit(d: f32, scale: f32) -> SurfaceInteraction {
    SurfaceInteraction {
        intr: Interaction {
            p: Vec3::new(0.0, 0.0, d),
            p_error: Vec3::ZERO,
            n: -Vec3::Z,
        },
        ns: -Vec3::Z,
        dpdu: Vec3::X,
        dp_du: Vec3::X * scale,
        dp_dv: Vec3::Y,
        uv: Vec2::ZERO,
        wo: -Vec3::Z,
        t: d,
        mesh: crate::shape::MeshPoint::default(),
        unmapped_ns: None,
        bitangent_sign: 1.0,
    }
}

#[test]
fn footprint_of_a_plane_facing_the_camera_is_the_pixel_size() {
    let fov = 2.0f32;
    let res = 100u32;
    let camera = PerspectiveCamera::new(
        &CameraDesc {
            fov_degrees: fov,
            world_from_camera: Transform::IDENTITY,
            ..CameraDesc::default()
        },
        &FilmDesc {
            width: res,
            height: res,
        },
        Vec2::splat(0.5),
    );
    for (d, scale, spp) in [(3.0f32, 1.0f32, 1u32), (10.0, 2.0, 1), (5.0, 1.0, 16), (5.0, 1.0, 1024)] {
        let si = plane_hit(d, scale);
        let (dpdx, dpdy) = camera.approximate_dp_dxy(si.p(), si.n(), spp);
        let ctx = TextureContext::with_footprint(&si, dpdx, dpdy);
        // One pixel spans 2 d tan(fov / 2) / res on the plane; pbrt shrinks the
        // footprint by max(1/8, 1/sqrt(spp)).
        let pixel = 2.0 * d * (fov.to_radians() / 2.0).tan() / res as f32;
        let footprint = pixel * (1.0 / (spp as f32).sqrt()).max(0.125);
        let rel = |a: f32, b: f32| ((a - b) / b).abs();
        assert!(
            rel(ctx.dudx, footprint / scale) < 2e-3,
            "{} vs {}",
            ctx.dudx,
            footprint / scale
        );
        // Raster y grows downwards, v = y upwards.
        assert!(rel(-ctx.dvdy, footprint) < 2e-3, "{} vs {footprint}", ctx.dvdy);
        assert!(ctx.dudy.abs() < 1e-3 * footprint && ctx.dvdx.abs() < 1e-3 * footprint);
        assert!(rel(dpdx.length(), footprint) < 2e-3);
    }
}

#[test]
fn ewa_widens_ellipses_longer_than_max_anisotropy() {
    let m = MipMap::new(16, 16, &pattern(16, 16), WrapMode::Repeat);
    let st = Vec2::new(0.4, 0.6);
    for (aniso, widened) in [(1.0, 0.1), (2.0, 0.05)] {
        let ewa = MipFilterOptions {
            filter: MipFilter::Ewa,
            max_anisotropy: aniso,
        };
        let thin = m.filter(&ewa, st, Vec2::new(0.1, 0.0), Vec2::new(0.0, 0.01));
        let wide = m.filter(&ewa, st, Vec2::new(0.1, 0.0), Vec2::new(0.0, widened));
        assert!(close(thin, wide, 1e-6), "max anisotropy {aniso}: {thin:?} vs {wide:?}");
    }
}

/// At a hit seen from `eye`, moving the point by `eps dp_du` (or `eps dp_dv`) and
/// re-intersecting changes uv by `(eps, 0)` (or `(0, eps)`), up to O(eps^2).
fn check_uv_derivatives(shape: &crate::shape::Shape, eye: Vec3, target: Vec3) {
    use crate::math::Ray;
    let hit_uv = |p: Vec3| {
        let ray = Ray::new(eye, (p - eye).normalize());
        let hit = shape.intersect(&ray, f32::INFINITY).expect("hit");
        shape.interaction(&ray, &hit)
    };
    let si = hit_uv(target);
    let eps = 1e-3;
    for (dp, duv) in [(si.dp_du, Vec2::new(eps, 0.0)), (si.dp_dv, Vec2::new(0.0, eps))] {
        let moved = hit_uv(si.p() + eps * dp);
        let got = moved.uv - si.uv;
        assert!((got - duv).abs().max_element() < 5e-5, "{shape:?}: {got} vs {duv}");
    }
}

#[test]
fn dp_du_and_dp_dv_match_the_uv_parameterisation() {
    use crate::shape::{Disk, Shape, Sphere, Triangle, TriangleMesh};
    let t = Transform::new(glam::Mat4::from_scale_rotation_translation(
        Vec3::new(1.0, 2.0, 0.5),
        glam::Quat::from_rotation_x(0.3),
        Vec3::new(0.1, 0.2, 0.3),
    ))
    .unwrap();
    let sphere = Shape::Sphere(Sphere::new(1.5, t, false));
    check_uv_derivatives(&sphere, Vec3::new(5.0, -6.0, 4.0), t.point(Vec3::new(1.0, -0.8, 0.6)));
    let disk = Shape::Disk(Disk::new(0.2, 2.0, 0.5, 5.0, t, false));
    check_uv_derivatives(&disk, Vec3::new(0.5, 0.3, 6.0), t.point(Vec3::new(1.0, 0.5, 0.2)));
    let mesh = std::sync::Arc::new(TriangleMesh {
        positions: vec![Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.5, 3.0, 1.0)],
        indices: vec![0, 1, 2],
        normals: None,
        uvs: Some(vec![Vec2::new(0.1, 0.2), Vec2::new(0.9, 0.3), Vec2::new(0.2, 0.8)]),
        flip_normals: false,
        tangents: None,
    });
    let tri = Shape::Triangle(Triangle::new(mesh, 0));
    check_uv_derivatives(&tri, Vec3::new(0.5, 0.5, 5.0), Vec3::new(0.8, 1.0, 0.33));
}

#[test]
fn spherical_cylindrical_and_planar_mappings_at_known_points() {
    let shift = Transform::new(glam::Mat4::from_translation(Vec3::new(0.0, 0.0, 2.0))).unwrap();
    let texture_from_world = shift.inverse();
    let ctx = |p: Vec3| TextureContext {
        p,
        dpdx: Vec3::new(0.01, 0.0, 0.0),
        dpdy: Vec3::new(0.0, 0.0, 0.01),
        ..TextureContext::default()
    };
    let near = |a: f32, b: f32| (a - b).abs() < 1e-5;
    // Spherical: s = theta / pi, t = phi / 2 pi around the texture-space origin (0, 0, 2).
    let sph = TextureMapping::Spherical { texture_from_world };
    let c = sph.map(&ctx(Vec3::new(0.0, 1.0, 2.0)));
    assert!(near(c.st.x, 0.5) && near(c.st.y, 0.25), "{:?}", c.st);
    let c = sph.map(&ctx(Vec3::new(1.0, 0.0, 3.0)));
    assert!(near(c.st.x, 0.25) && near(c.st.y, 0.0), "{:?}", c.st);
    // At (1, 0, 3) (theta = pi/4), a step +z lowers theta: ds/dy = -(0.01 sin(pi/4)/sqrt 2)/pi.
    assert!(near(c.dsdy, -0.01 * 0.5 / std::f32::consts::PI), "{}", c.dsdy);
    // Cylindrical: s = (pi + atan2(y, x)) / 2 pi, t = z.
    let cyl = TextureMapping::Cylindrical { texture_from_world };
    let c = cyl.map(&ctx(Vec3::new(0.0, 2.0, 2.5)));
    assert!(near(c.st.x, 0.75) && near(c.st.y, 0.5), "{:?}", c.st);
    assert!(near(c.dtdy, 0.01) && near(c.dtdx, 0.0));
    // Planar: s = ds + p . v1, t = dt + p . v2.
    let planar = TextureMapping::Planar {
        texture_from_world,
        vs: Vec3::new(1.0, 0.0, 0.0),
        vt: Vec3::new(0.0, 0.0, 2.0),
        ds: 0.25,
        dt: 0.5,
    };
    let c = planar.map(&ctx(Vec3::new(3.0, 7.0, 2.5)));
    assert!(near(c.st.x, 3.25) && near(c.st.y, 1.5), "{:?}", c.st);
    assert!(near(c.dsdx, 0.01) && near(c.dtdy, 0.02) && near(c.dsdy, 0.0));
}
