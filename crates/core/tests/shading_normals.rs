//! The light-leak guard of shading normals (Veach 1997, section 5.3): a surface whose
//! interpolated normals tilt far from its face normal must not be lit through itself.

mod common;

use common::*;
use mcrender_core::color::Rgb;
use mcrender_core::math::Vec3;
use mcrender_core::scene::{DirectStrategy, GeometryDesc, SceneDescription};

/// The receiver of [`add_receiver`] (facing +y, seen from above) with every vertex normal
/// tilted 72 degrees towards +x, and a sphere light at height `light_y`, off to +x.
fn tilted_receiver(light_y: f32) -> SceneDescription {
    let mut d = empty_scene();
    add_receiver(&mut d, 0.8);
    let GeometryDesc::TriangleMesh(mesh) = &mut d.shapes[0].geometry else {
        unreachable!()
    };
    mesh.normals = Some(vec![Vec3::new(0.95, 0.31, 0.0).normalize(); 4]);
    aim_at_receiver(&mut d);
    add_sphere_light(&mut d, 0.3, Vec3::new(1.5, light_y, 0.0), Rgb::splat(5.0));
    d.integrator.max_depth = 1;
    d
}

#[test]
fn tilted_shading_normals_do_not_let_light_through_the_surface() {
    // Seen from the camera, the light below the surface is on the same side of the tilted
    // shading normal (a reflection for the lobe) but across the geometric surface.
    for strategy in DirectStrategy::ALL {
        let mut d = tilted_receiver(-0.6);
        d.integrator.direct = strategy;
        let out = render_desc(&d);
        let (mean, _) = mean_and_standard_error(&out);
        assert_eq!(mean, [0.0; 3], "lit from below, {}", strategy.name());
        assert_eq!(out.stats.nonfinite_samples, 0);

        // Control: the same light above the surface lights it.
        let mut d = tilted_receiver(0.6);
        d.integrator.direct = strategy;
        let (mean, _) = mean_and_standard_error(&render_desc(&d));
        assert!(
            mean.iter().all(|m| *m > 0.01),
            "lit from above, {}: {mean:?}",
            strategy.name()
        );
    }
}
