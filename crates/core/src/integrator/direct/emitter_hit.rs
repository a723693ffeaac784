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
/// The ray continues through `interface` surfaces (adding their emission, if any).
pub fn emitted_toward(scene: &Scene, si: &SurfaceInteraction, wi: Vec3, stats: &mut TraceStats) -> Rgb {
    let mut ray = si.spawn_ray(wi);
    let mut sum = Rgb::BLACK;
    loop {
        stats.rays += 1;
        let Some(hit) = scene.intersect(&ray) else {
            return scene
                .infinite_lights
                .iter()
                .fold(sum, |sum, &i| sum + scene.lights[i as usize].le(wi));
        };
        if let Some(Light::DiffuseArea(area)) = hit.primitive.light.map(|i| &scene.lights[i as usize]) {
            sum += area.l(hit.si.n(), hit.si.wo);
        }
        if !scene.passes_through(hit.primitive.material, &hit.si) {
            return sum;
        }
        ray = hit.si.spawn_ray(wi);
    }
}
