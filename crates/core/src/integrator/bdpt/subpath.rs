//! Sampling the two subpaths (pbrt-v4 `GenerateCameraSubpath`, `GenerateLightSubpath`,
//! `RandomWalk`): a camera ray or a ray emitted by a light, continued by BSDF sampling.
//! Every vertex records its forward density (converted to area at the vertex) and the
//! reverse density of the vertex before it, so that the MIS weights can later compare
//! every way of sampling the same path. There is no Russian roulette: subpaths end at the
//! depth limit, when they leave the scene, or when the BSDF gives no sample.

use super::vertex::{infinite_light_density, Context, Vertex};
use crate::bsdf::TransportMode;
use crate::color::Rgb;
use crate::integrator::TraceStats;
use crate::math::Ray;
use crate::sampling::SampleSource;
use crate::shape::Interaction;

/// The camera subpath of `ray`: the camera vertex, then at most `max_vertices - 1` more.
pub fn camera_subpath(
    ctx: &Context<'_>,
    ray: Ray,
    sampler: &mut impl SampleSource,
    max_vertices: usize,
    path: &mut Vec<Vertex>,
    stats: &mut TraceStats,
) {
    path.clear();
    if max_vertices == 0 {
        return;
    }
    path.push(Vertex::camera(Interaction::point(ray.o), Rgb::WHITE));
    let (_, pdf_dir) = ctx.scene.camera.pdf_we(&ray);
    random_walk(
        ctx,
        ray,
        sampler,
        Rgb::WHITE,
        pdf_dir,
        max_vertices - 1,
        TransportMode::Radiance,
        path,
        stats,
    );
    // The first vertex's area density from the camera's own rule (the orthographic
    // camera's is not the solid-angle density over r^2 that the walk applied).
    if ctx.scene.camera.is_orthographic() && path.len() > 1 && !path[1].at_infinity {
        path[1].pdf_fwd = path[0].pdf(ctx, None, &path[1]);
    }
}

/// A light subpath: a light chosen by power, a ray emitted from it, then at most
/// `max_vertices - 1` more vertices. Leaves `path` empty when the light gives no sample.
pub fn light_subpath(
    ctx: &Context<'_>,
    sampler: &mut impl SampleSource,
    max_vertices: usize,
    path: &mut Vec<Vertex>,
    stats: &mut TraceStats,
) {
    path.clear();
    if max_vertices == 0 {
        return;
    }
    let scene = ctx.scene;
    let u_light = sampler.get_1d();
    let u_pos = sampler.get_2d();
    let u_dir = sampler.get_2d();
    let Some((index, pmf)) = scene.light_sampler.sample(u_light) else {
        return;
    };
    let light = &scene.lights[index];
    let Some(les) = light.sample_le(u_pos, u_dir) else {
        return;
    };
    let v0 = Vertex::light(scene, index as u32, les.intr, les.le, les.pdf_pos * pmf);
    let beta = les.initial_throughput(pmf);
    path.push(v0);
    random_walk(
        ctx,
        les.ray,
        sampler,
        beta,
        les.pdf_dir,
        max_vertices - 1,
        TransportMode::Importance,
        path,
        stats,
    );
    // A light at infinity: the second vertex's density is that of the ray's origin on the
    // scene's bounding disk (per unit area, projected onto the surface there), and the
    // origin's is the solid-angle density of the direction (pbrt-v4's convention).
    if path[0].at_infinity {
        if path.len() > 1 {
            let mut pdf = les.pdf_pos;
            if path[1].is_on_surface() {
                pdf *= les.ray.d.dot(path[1].ng()).abs();
            }
            path[1].pdf_fwd = pdf;
        }
        path[0].pdf_fwd = infinite_light_density(scene, -les.ray.d);
    }
}

/// Extend `path` (whose last vertex emitted `ray` with throughput `beta` and solid-angle
/// density `pdf_dir`) by at most `max_new` vertices.
#[allow(clippy::too_many_arguments)]
fn random_walk(
    ctx: &Context<'_>,
    mut ray: Ray,
    sampler: &mut impl SampleSource,
    mut beta: Rgb,
    pdf_dir: f32,
    max_new: usize,
    mode: TransportMode,
    path: &mut Vec<Vertex>,
    stats: &mut TraceStats,
) {
    if max_new == 0 {
        return;
    }
    let scene = ctx.scene;
    let mut pdf_fwd = pdf_dir;
    let mut added = 0;
    let mut any_non_specular = false;
    loop {
        // Intersect; a camera ray that leaves the scene ends at the infinite lights.
        stats.rays += 1;
        let Some(hit) = scene.intersect(&ray) else {
            if mode == TransportMode::Radiance {
                path.push(Vertex::escaped(&ray, beta, pdf_fwd));
            }
            break;
        };
        let si = hit.si;
        // Pass through surfaces without a BSDF (`interface`) without making a vertex.
        let Some(mut bsdf) = scene.bsdf(hit.primitive.material, &si) else {
            ray = si.spawn_ray(ray.d);
            continue;
        };
        // Possibly regularize: roughen near-specular surfaces once the subpath has
        // scattered diffusely or glossily (pbrt-v4's `regularize`).
        if ctx.regularize && any_non_specular {
            bsdf.regularize();
        }
        let prev = path.last().expect("a subpath starts at an endpoint");
        let vertex = Vertex::surface(si, bsdf, hit.primitive.light, beta, pdf_fwd, prev);
        path.push(vertex);
        added += 1;
        if added >= max_new {
            break;
        }

        // Sample the BSDF (its adjoint on light subpaths) for the next direction.
        let uc = sampler.get_1d();
        let u = sampler.get_2d();
        let Some(bs) = bsdf.sample_f_mode(si.wo, uc, u, mode) else {
            break;
        };
        // A stochastic BSDF's sampled pdf is only proportional to the density; MIS needs the
        // (estimated) density itself.
        pdf_fwd = if bs.pdf_is_proportional {
            bsdf.pdf(si.wo, bs.wi)
        } else {
            bs.pdf
        };
        any_non_specular |= !bs.flags.is_specular();
        beta *= bs.f * (bs.wi.dot(si.ns).abs() / bs.pdf);
        beta *= super::vertex::correct_shading_normal(&si, si.wo, bs.wi, mode);
        // Reverse density: the previous vertex sampled from this one.
        let mut pdf_rev = bsdf.pdf(bs.wi, si.wo);
        let n = path.len();
        if bs.flags.is_specular() {
            path[n - 1].delta = true;
            pdf_rev = 0.0;
            pdf_fwd = 0.0;
        }
        let (head, tail) = path.split_at_mut(n - 1);
        head[n - 2].pdf_rev = tail[0].convert_density(pdf_rev, &head[n - 2]);
        if beta.is_black() {
            break;
        }
        ray = si.spawn_ray(bs.wi);
    }
}
