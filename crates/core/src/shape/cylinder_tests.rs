//! Tests of the cylinder: analytic hits, random rays against a brute-force search of the
//! implicit surface, error bounds, parameterisation, area and area sampling (chi-square).

use super::*;
use crate::math::Mat4;
use crate::math::UVec2;
use crate::sampling::chi2::{suite_seed, Chi2Test, RectGrid, SIGNIFICANCE};
use crate::sampling::Pcg32;
use glam::DMat4;

fn unit() -> Cylinder {
    Cylinder::new(1.0, -1.0, 1.0, 2.0 * PI, Transform::IDENTITY, false)
}

/// A rotated, translated, non-uniformly scaled placement (an elliptic cylinder in world).
fn placed() -> Transform {
    let m = Mat4::from_translation(Vec3::new(0.3, -0.2, 1.5))
        * Mat4::from_rotation_x(0.7)
        * Mat4::from_rotation_z(0.3)
        * Mat4::from_scale(Vec3::new(1.5, 0.6, 1.2));
    Transform::new(m).unwrap()
}

fn hit_t(c: &Cylinder, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
    c.intersect(&Ray::new(o, d), t_max).map(|h| h.t)
}

#[test]
fn analytic_hits_and_misses() {
    let c = unit();
    let close = |t: Option<f32>, e: f32| t.is_some_and(|t| (t - e).abs() < 1e-5);
    // From outside: the near wall at x = 1, normal +x.
    let ray = Ray::new(Vec3::new(5.0, 0.0, 0.0), -Vec3::X);
    let hit = c.intersect(&ray, f32::INFINITY).unwrap();
    assert!((hit.t - 4.0).abs() < 1e-5);
    let si = c.interaction(&ray, &hit);
    assert!((si.n() - Vec3::X).length() < 1e-6 && (si.p() - Vec3::X).length() < 1e-6);
    // From the axis outwards: the wall at t = 1 (the cylinder is open), normal still outwards.
    let ray = Ray::new(Vec3::new(0.0, 0.0, 0.3), Vec3::new(0.0, 2.0, 0.0));
    let hit = c.intersect(&ray, f32::INFINITY).unwrap();
    assert!((hit.t - 0.5).abs() < 1e-6, "t is in units of |d|: {}", hit.t);
    assert!((c.interaction(&ray, &hit).n() - Vec3::Y).length() < 1e-6);
    // The segment stops short of the wall.
    assert!(hit_t(&c, Vec3::new(5.0, 0.0, 0.0), -Vec3::X, 3.99).is_none());
    // A slanted ray through the open top: enters through the cap plane, meets the far wall.
    // From (0, 0, 3) towards (-1, 0, 0): x = -t/sqrt(10)... parameterised by the direction
    // (-1, 0, -3), the wall x = -1 is met at t = 1 at z = 0.
    assert!(close(
        hit_t(&c, Vec3::new(0.0, 0.0, 3.0), Vec3::new(-1.0, 0.0, -3.0), 10.0),
        1.0
    ));
    // ... and misses when the wall it would meet lies above z_max.
    assert!(hit_t(&c, Vec3::new(0.0, 0.0, 3.0), Vec3::new(-1.0, 0.0, -0.5), 10.0).is_none());
    // Rays along the axis, inside or outside, never hit; nor do NaN or zero directions.
    for o in [Vec3::ZERO, Vec3::new(0.5, 0.2, -3.0), Vec3::new(3.0, 0.0, 0.0)] {
        for d in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::ZERO,
            Vec3::new(f32::NAN, 0.0, 1.0),
            Vec3::splat(f32::NAN),
        ] {
            assert!(hit_t(&c, o, d, f32::INFINITY).is_none(), "{o} {d}");
        }
    }
    // Rays in the end planes: z = z_max is on the surface (inclusive), just above is not.
    assert!(close(hit_t(&c, Vec3::new(5.0, 0.0, 1.0), -Vec3::X, 100.0), 4.0));
    assert!(close(hit_t(&c, Vec3::new(5.0, 0.0, -1.0), -Vec3::X, 100.0), 4.0));
    assert!(hit_t(&c, Vec3::new(5.0, 0.0, 1.0001), -Vec3::X, 100.0).is_none());
    // Grazing: just inside the tangent line hits twice (the nearer first), just outside misses.
    let near = 5.0 - (1.0f32 - 0.999 * 0.999).sqrt();
    assert!(hit_t(&c, Vec3::new(5.0, 0.999, 0.0), -Vec3::X, 100.0).is_some_and(|t| (t - near).abs() < 1e-3));
    assert!(hit_t(&c, Vec3::new(5.0, 1.001, 0.0), -Vec3::X, 100.0).is_none());
    // The exactly tangent ray may or may not hit, but never with a non-finite answer.
    if let Some(t) = hit_t(&c, Vec3::new(5.0, 1.0, 0.0), -Vec3::X, 100.0) {
        assert!((t - 5.0).abs() < 1e-2, "{t}");
    }
}

#[test]
fn azimuth_cut_lets_rays_through() {
    let c = Cylinder::new(1.0, -1.0, 1.0, 90f32.to_radians(), Transform::IDENTITY, false);
    // y = 0.5: the near wall at phi = 30 degrees is kept.
    let t = hit_t(&c, Vec3::new(5.0, 0.5, 0.0), -Vec3::X, 100.0).unwrap();
    assert!((t - (5.0 - 0.75f32.sqrt())).abs() < 1e-5);
    // y = -0.5: phi = 330 then 210 degrees, both cut.
    assert!(hit_t(&c, Vec3::new(5.0, -0.5, 0.0), -Vec3::X, 100.0).is_none());
    // From x = -5 at y = 0.5: the near wall (phi = 150) is cut, the far one (30) is kept.
    let t = hit_t(&c, Vec3::new(-5.0, 0.5, 0.0), Vec3::X, 100.0).unwrap();
    assert!((t - (5.0 + 0.75f32.sqrt())).abs() < 1e-5);
    // uv: u = phi / phi_max, v from z_min to z_max.
    let ray = Ray::new(Vec3::new(5.0, 0.5, 0.5), -Vec3::X);
    let si = c.interaction(&ray, &c.intersect(&ray, 100.0).unwrap());
    assert!(
        (si.uv.x - 30.0 / 90.0).abs() < 1e-4 && (si.uv.y - 0.75).abs() < 1e-4,
        "{:?}",
        si.uv
    );
}

/// The first root of `x^2 + y^2 = r^2` along the object-space ray that the cylinder keeps,
/// by marching the implicit function in small steps and bisecting each sign change (f64),
/// with a flag saying whether the answer is ill-conditioned (a root near an edge or a
/// grazing ray), in which case the test skips the ray.
fn brute_force(c: &Cylinder, o: glam::DVec3, d: glam::DVec3, t_max: f64) -> (Option<f64>, bool) {
    let r = f64::from(c.radius);
    let f = |t: f64| {
        let p = o + t * d;
        p.x * p.x + p.y * p.y - r * r
    };
    // Distance of the line from the axis, for grazing rays.
    let dxy = glam::DVec2::new(d.x, d.y);
    let oxy = glam::DVec2::new(o.x, o.y);
    let grazing = dxy.length() > 0.0 && {
        let closest = oxy - dxy * (oxy.dot(dxy) / dxy.length_squared());
        (closest.length() - r).abs() < 2e-3 * r
    };
    let steps = 10_000;
    let h = t_max / f64::from(steps);
    let mut ill = grazing;
    for i in 0..steps {
        let (mut a, mut b) = (f64::from(i) * h, f64::from(i + 1) * h);
        if f(a).signum() == f(b).signum() {
            continue;
        }
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            if f(m).signum() == f(a).signum() {
                a = m;
            } else {
                b = m;
            }
        }
        let t = 0.5 * (a + b);
        let p = o + t * d;
        let phi = p.y.atan2(p.x).rem_euclid(std::f64::consts::TAU);
        let (z0, z1, pm) = (f64::from(c.z_min), f64::from(c.z_max), f64::from(c.phi_max));
        let margin = 1e-3 * (z1 - z0);
        if (p.z - z0).abs() < margin || (p.z - z1).abs() < margin || (phi - pm).abs() < 1e-3 || phi < 1e-3 {
            ill = true;
        }
        if t < 1e-3 {
            ill = true;
        }
        if p.z >= z0 && p.z <= z1 && phi <= pm {
            return (Some(t), ill);
        }
    }
    (None, ill)
}

/// Random rays from inside and outside a placed, elliptic, azimuth-cut cylinder: hit or miss
/// and distance as the brute-force search, spawned rays on the right side of the surface
/// (checked in f64), the point within the bounds, uv and normal consistent with the point.
#[test]
fn random_rays_agree_with_the_implicit_surface() {
    let t = placed();
    let c = Cylinder::new(0.8, -0.5, 1.2, 1.6 * PI, t, false);
    let inv = t.m.as_dmat4().inverse();
    let mut rng = Pcg32::new(11, 3);
    let (mut hits, mut misses, mut inside_hits, mut skipped) = (0, 0, 0, 0);
    for k in 0..4000 {
        let u = |rng: &mut Pcg32, s: f32| s * (2.0 * rng.next_f32() - 1.0);
        // Half the origins inside the cylinder (object space), half anywhere in a box.
        let o_obj = if k % 2 == 0 {
            let (rr, phi) = (0.8 * rng.next_f32().sqrt(), 2.0 * PI * rng.next_f32());
            Vec3::new(rr * phi.cos(), rr * phi.sin(), -0.5 + 1.7 * rng.next_f32())
        } else {
            Vec3::new(u(&mut rng, 3.0), u(&mut rng, 3.0), u(&mut rng, 3.0))
        };
        let o = t.point(o_obj);
        let d = Vec3::new(u(&mut rng, 1.0), u(&mut rng, 1.0), u(&mut rng, 1.0));
        let t_max = 20.0;
        let (od, dd) = (inv.transform_point3(o.as_dvec3()), inv.transform_vector3(d.as_dvec3()));
        let (expected, ill) = brute_force(&c, od, dd, f64::from(t_max));
        if ill {
            skipped += 1;
            continue;
        }
        let ray = Ray::new(o, d);
        match (c.intersect(&ray, t_max), expected) {
            (None, None) => misses += 1,
            (Some(hit), Some(te)) => {
                assert!(
                    (f64::from(hit.t) - te).abs() < 1e-4 * te.max(1.0),
                    "t {} vs {te}",
                    hit.t
                );
                let si = c.interaction(&ray, &hit);
                assert!(c.bounds().contains(si.p()));
                let p_obj = inv.transform_point3(si.p().as_dvec3());
                let radial = glam::DVec3::new(p_obj.x, p_obj.y, 0.0).normalize();
                // The normal is the transformed radial direction.
                let n_expected = t.normal(radial.as_vec3()).normalize();
                assert!((si.n() - n_expected).length() < 1e-4, "{} vs {n_expected}", si.n());
                // Spawned origins on either side stay on that side of the surface.
                for side in [1.0f32, -1.0] {
                    let q = inv.transform_point3(si.intr.offset_origin(side * si.n()).as_dvec3());
                    let rho = (q.x * q.x + q.y * q.y).sqrt() - 0.8;
                    assert!(rho * f64::from(side) > 0.0, "offset origin on the wrong side: {rho}");
                }
                // uv from the object-space point.
                let phi = p_obj.y.atan2(p_obj.x).rem_euclid(std::f64::consts::TAU);
                assert!((f64::from(si.uv.x) - phi / f64::from(1.6 * PI)).abs() < 1e-4);
                assert!((f64::from(si.uv.y) - (p_obj.z + 0.5) / 1.7).abs() < 1e-4);
                if k % 2 == 0 {
                    inside_hits += 1;
                }
                hits += 1;
            }
            (got, want) => panic!("ray {ray:?}: got {got:?}, brute force {want:?}"),
        }
    }
    assert!(
        hits > 800 && misses > 800 && inside_hits > 800 && skipped < 400,
        "{hits} hits ({inside_hits} from inside), {misses} misses, {skipped} skipped"
    );
}

/// A ray along the (placed) axis from inside misses; a ray in the (placed) end plane hits.
#[test]
fn placed_axis_and_end_plane_rays() {
    let t = placed();
    let c = Cylinder::new(0.8, -0.5, 1.2, 2.0 * PI, t, false);
    let axis = t.vector(Vec3::Z);
    for o_obj in [Vec3::new(0.1, 0.2, 0.0), Vec3::new(0.1, 0.2, -3.0)] {
        assert!(c.intersect(&Ray::new(t.point(o_obj), axis), f32::INFINITY).is_none());
        assert!(c.intersect(&Ray::new(t.point(o_obj), -axis), f32::INFINITY).is_none());
    }
    // In the plane z = 0.6 (safely inside the height range) along object x.
    let ray = Ray::new(t.point(Vec3::new(-4.0, 0.0, 0.6)), t.vector(Vec3::X));
    let hit = c.intersect(&ray, f32::INFINITY).unwrap();
    assert!((hit.t - 3.2).abs() < 1e-4, "{}", hit.t);
}

#[test]
fn normal_points_outwards_unless_flipped() {
    let t = placed();
    for (flip, sign) in [(false, 1.0), (true, -1.0)] {
        let c = Cylinder::new(0.8, -0.5, 1.2, 2.0 * PI, t, flip);
        let ray = Ray::new(t.point(Vec3::new(3.0, 0.0, 0.2)), t.vector(-Vec3::X));
        let si = c.interaction(&ray, &c.intersect(&ray, f32::INFINITY).unwrap());
        let n = t.normal(Vec3::X).normalize();
        assert!((si.n() - sign * n).length() < 1e-5);
        assert!((si.ns - si.n()).length() < 1e-6);
        let s = c.sample_area(Vec2::new(0.5, 0.0));
        assert!((s.intr.n - sign * n).length() < 1e-5);
    }
}

/// dp/du and dp/dv are the derivatives of the point in uv: finite differences of sampled
/// points (sample_area's u maps linearly to (v, u) of the surface).
#[test]
fn partial_derivatives_match_finite_differences() {
    let t = placed();
    let c = Cylinder::new(0.8, -0.5, 1.2, 1.6 * PI, t, false);
    let at = |u: f32, v: f32| c.sample_area(Vec2::new(v, u)).intr.p;
    for (u, v) in [(0.2, 0.3), (0.7, 0.9), (0.5, 0.5)] {
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        let si = c.interaction_at(t.m_inv.transform_point3(at(u, v)), -ray.d, 1.0);
        assert!((si.uv - Vec2::new(u, v)).length() < 1e-4, "{:?}", si.uv);
        let h = 1e-3;
        let du = (at(u + h, v) - at(u - h, v)) / (2.0 * h);
        let dv = (at(u, v + h) - at(u, v - h)) / (2.0 * h);
        assert!((du - si.dp_du).length() < 2e-3 * si.dp_du.length(), "{du} {}", si.dp_du);
        assert!((dv - si.dp_dv).length() < 2e-3 * si.dp_dv.length(), "{dv} {}", si.dp_dv);
        assert!(si.dpdu.dot(si.n()).abs() < 1e-5 && (si.dpdu.length() - 1.0).abs() < 1e-5);
    }
}

/// `|dp/dphi x dp/dz|` of the placed surface at azimuth `phi`, computed directly in f64.
fn area_element(m: DMat4, r: f64, phi: f64) -> f64 {
    let dphi = m.transform_vector3(glam::DVec3::new(-r * phi.sin(), r * phi.cos(), 0.0));
    let dz = m.transform_vector3(glam::DVec3::Z);
    dphi.cross(dz).length()
}

#[test]
fn area_follows_the_transform() {
    // Uniform scale 2: area 2 pi r h s^2, exactly.
    let s = Transform::new(Mat4::from_scale(Vec3::splat(2.0))).unwrap();
    let c = Cylinder::new(0.5, 0.0, 3.0, 2.0 * PI, s, false);
    assert!((c.area() - 2.0 * PI * 0.5 * 3.0 * 4.0).abs() < 1e-4, "{}", c.area());
    // Elliptic and cut: against an independent quadrature of the area element.
    let t = placed();
    let c = Cylinder::new(0.8, -0.5, 1.2, 1.6 * PI, t, false);
    let n = 100_000;
    let h = 1.6 * std::f64::consts::PI / f64::from(n);
    let expected: f64 = (0..n)
        .map(|i| area_element(t.m.as_dmat4(), 0.8, (f64::from(i) + 0.5) * h) * h * 1.7)
        .sum();
    assert!(
        (f64::from(c.area()) - expected).abs() < 1e-5 * expected,
        "{} vs {expected}",
        c.area()
    );
    // E[1 / pdf] over area samples is the area.
    let mut rng = Pcg32::new(5, 9);
    let m = 20_000;
    let mean: f64 = (0..m)
        .map(|_| f64::from(1.0 / c.sample_area(Vec2::new(rng.next_f32(), rng.next_f32())).pdf_area))
        .sum::<f64>()
        / f64::from(m);
    // No noise: 1 / pdf depends on phi only and phi is uniform; a loose bound suffices.
    assert!((mean - expected).abs() < 0.01 * expected, "{mean} vs {expected}");
}

/// Area samples mapped back to (phi, z) against `pdf_area` times the area element: passes
/// only if the sampler's density is the pdf it reports, Jacobian included.
#[test]
fn area_sampling_matches_its_pdf() {
    let t = placed();
    let phi_max = 1.6 * PI;
    let c = Cylinder::new(0.8, -0.5, 1.2, phi_max, t, false);
    let m = t.m.as_dmat4();
    let report = Chi2Test::new(200_000, suite_seed()).rect(
        RectGrid {
            min: Vec2::new(0.0, -0.5),
            max: Vec2::new(phi_max, 1.2),
            bins: UVec2::new(24, 10),
        },
        |u, _| {
            let s = c.sample_area(u);
            assert!((s.pdf_area - c.pdf_area(&s.intr)).abs() < 1e-5 * s.pdf_area);
            let p = t.m_inv.transform_point3(s.intr.p);
            Some(Vec2::new(p.y.atan2(p.x).rem_euclid(2.0 * PI), p.z))
        },
        |q| {
            let p_obj = Vec3::new(0.8 * q.x.cos(), 0.8 * q.x.sin(), q.y);
            let pdf = c.pdf_area(&Interaction::point(t.point(p_obj)));
            (f64::from(pdf) * area_element(m, 0.8, f64::from(q.x))) as f32
        },
    );
    assert!(report.passes(SIGNIFICANCE), "{report}");
}
