//! Tracing a ray to see which emitted radiance it finds: the building block of the
//! techniques that find light only by hitting it.

use crate::color::Rgb;
use crate::integrator::TraceStats;
use crate::light::Light;
use crate::math::Vec3;
use crate::scene::Scene;
use crate::shape::SurfaceInteraction;

/// Radiance emitted towards `si` by whatever the ray from `si` in direction `wi` hits first
/// (black for non-emitters; the infinite lights' emission for rays that leave the scene).
pub fn emitted_toward(scene: &Scene, si: &SurfaceInteraction, wi: Vec3, stats: &mut TraceStats) -> Rgb {
    stats.rays += 1;
    let ray = si.spawn_ray(wi);
    let Some(hit) = scene.intersect(&ray) else {
        return scene
            .infinite_lights
            .iter()
            .fold(Rgb::BLACK, |sum, &i| sum + scene.lights[i as usize].le(wi));
    };
    match hit.primitive.light.map(|i| &scene.lights[i as usize]) {
        Some(Light::DiffuseArea(area)) => area.l(hit.si.n(), hit.si.wo),
        _ => Rgb::BLACK,
    }
}
