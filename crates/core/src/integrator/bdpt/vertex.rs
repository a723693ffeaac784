//! Path vertices of bidirectional path tracing (Veach 1997, section 10.2; pbrt-v4
//! `Vertex`): a camera or light endpoint, or a scattering point on a surface, with the
//! throughput `beta` of the subpath up to it and the area-measure densities of sampling it
//! from either side (`pdf_fwd` along the subpath's own direction, `pdf_rev` from the other
//! end), which the MIS weights compare.
//!
//! Densities are per unit area at points on surfaces, per unit solid angle at points at
//! infinity (the vertex of a ray that left the scene, and the origin of a light subpath
//! started from an infinite or distant light), and per unit area on the scene's bounding
//! disk for the position of a light subpath started at infinity (pbrt-v4's convention).

use crate::bsdf::{Bsdf, TransportMode};
use crate::color::Rgb;
use crate::light::Light;
use crate::math::{Ray, Vec3, PI};
use crate::scene::Scene;
use crate::shape::{Interaction, SurfaceInteraction};

/// What a vertex is. Most vertices are surface vertices, so the size difference is the
/// common case, not waste; boxing it would allocate per vertex.
#[derive(Clone, Copy, Debug)]
#[allow(clippy::large_enum_variant)]
pub enum VertexKind {
    /// The camera's lens point.
    Camera,
    /// A point on a light, or (light `None`) the end of a camera ray that left the scene,
    /// which sees every infinite light.
    Light(Option<u32>),
    /// A scattering point; `light` is the area light of the surface, if it emits.
    Surface {
        /// The hit.
        si: SurfaceInteraction,
        /// Its BSDF.
        bsdf: Bsdf,
        /// The surface's area light.
        light: Option<u32>,
    },
}

/// One vertex of a camera or light subpath.
#[derive(Clone, Copy, Debug)]
pub struct Vertex {
    /// Camera, light or surface.
    pub kind: VertexKind,
    /// Position, error bound and geometric normal (zero normal off surfaces).
    pub intr: Interaction,
    /// Throughput of the subpath from its endpoint up to and including this vertex.
    pub beta: Rgb,
    /// Density of this vertex sampled from the previous one of its subpath.
    pub pdf_fwd: f32,
    /// Density of this vertex sampled from the next one (the other direction).
    pub pdf_rev: f32,
    /// True when the scattering here was sampled from a specular lobe.
    pub delta: bool,
    /// True for a light endpoint at infinity: an escaped ray, an infinite or a distant
    /// light (pbrt-v4 `IsInfiniteLight`).
    pub at_infinity: bool,
}

/// Scene-wide data the densities need.
#[derive(Clone, Copy, Debug)]
pub struct Context<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// Radius of the scene's bounding sphere (for the density of rays from infinity).
    pub scene_radius: f32,
    /// Roughen near-specular BSDFs after the first non-specular bounce of a subpath.
    pub regularize: bool,
}

impl Vertex {
    /// The camera endpoint at `p` with throughput `beta`.
    #[must_use]
    pub fn camera(p: Interaction, beta: Rgb) -> Self {
        Self {
            kind: VertexKind::Camera,
            intr: p,
            beta,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
            delta: false,
            at_infinity: false,
        }
    }

    /// A light endpoint of light `light` of `scene` at `p` (normal zero off surfaces).
    #[must_use]
    pub fn light(scene: &Scene, light: u32, p: Interaction, beta: Rgb, pdf_fwd: f32) -> Self {
        let l = &scene.lights[light as usize];
        Self {
            kind: VertexKind::Light(Some(light)),
            intr: p,
            beta,
            pdf_fwd,
            pdf_rev: 0.0,
            delta: false,
            at_infinity: l.is_infinite() || matches!(l, Light::Distant(_)),
        }
    }

    /// The end of `ray`, which left the scene (pbrt places it one unit along the ray).
    #[must_use]
    pub fn escaped(ray: &Ray, beta: Rgb, pdf_fwd: f32) -> Self {
        Self {
            kind: VertexKind::Light(None),
            intr: Interaction::point(ray.o + ray.d),
            beta,
            pdf_fwd,
            pdf_rev: 0.0,
            delta: false,
            at_infinity: true,
        }
    }

    /// A surface vertex found from `prev` with solid-angle density `pdf_dir`.
    #[must_use]
    pub fn surface(
        si: SurfaceInteraction,
        bsdf: Bsdf,
        light: Option<u32>,
        beta: Rgb,
        pdf_dir: f32,
        prev: &Self,
    ) -> Self {
        let mut v = Self {
            kind: VertexKind::Surface { si, bsdf, light },
            intr: si.intr,
            beta,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
            delta: false,
            at_infinity: false,
        };
        v.pdf_fwd = prev.convert_density(pdf_dir, &v);
        v
    }

    /// The point.
    #[inline]
    #[must_use]
    pub fn p(&self) -> Vec3 {
        self.intr.p
    }

    /// Geometric normal (zero off surfaces).
    #[inline]
    #[must_use]
    pub fn ng(&self) -> Vec3 {
        self.intr.n
    }

    /// Shading normal at a surface vertex, the geometric one elsewhere.
    #[must_use]
    pub fn ns(&self) -> Vec3 {
        match &self.kind {
            VertexKind::Surface { si, .. } => si.ns,
            _ => self.intr.n,
        }
    }

    /// True for vertices with a surface normal.
    #[must_use]
    pub fn is_on_surface(&self) -> bool {
        self.intr.n != Vec3::ZERO
    }

    /// The light this vertex emits with, if any (`None` also for escaped rays).
    #[must_use]
    pub fn light_index(&self) -> Option<u32> {
        match self.kind {
            VertexKind::Light(l) => l,
            VertexKind::Surface { light, .. } => light,
            VertexKind::Camera => None,
        }
    }

    /// True when a path can end here by emission: a light endpoint or an emitting surface.
    #[must_use]
    pub fn is_light(&self) -> bool {
        matches!(self.kind, VertexKind::Light(_)) || matches!(self.kind, VertexKind::Surface { light: Some(_), .. })
    }

    /// True for a light endpoint of a point, spot or distant light.
    #[must_use]
    pub fn is_delta_light(&self, scene: &Scene) -> bool {
        matches!(self.kind, VertexKind::Light(Some(l)) if scene.lights[l as usize].is_delta())
    }

    /// True when a connection to another subpath can be made here: not at a purely
    /// specular surface and not at a light that emits in a single direction.
    #[must_use]
    pub fn is_connectible(&self, scene: &Scene) -> bool {
        match &self.kind {
            VertexKind::Camera | VertexKind::Light(None) => true,
            VertexKind::Light(Some(l)) => !matches!(scene.lights[*l as usize], Light::Distant(_)),
            VertexKind::Surface { bsdf, .. } => bsdf.flags().is_non_specular(),
        }
    }

    /// Turn a solid-angle density at this vertex towards `next` into an area density at
    /// `next` (unchanged when `next` is at infinity): `p_A = p_w |cos theta_next| / r^2`.
    #[must_use]
    pub fn convert_density(&self, pdf: f32, next: &Self) -> f32 {
        if next.at_infinity {
            return pdf;
        }
        let w = next.p() - self.p();
        let d2 = w.length_squared();
        if d2 == 0.0 {
            return 0.0;
        }
        let inv_d2 = 1.0 / d2;
        let mut pdf = pdf;
        if next.is_on_surface() {
            pdf *= next.ng().dot(w * inv_d2.sqrt()).abs();
        }
        pdf * inv_d2
    }

    /// The BSDF (or adjoint BSDF, for `mode` importance) scattering from this surface
    /// vertex towards `next`, with pbrt's correction for shading normals under importance
    /// transport; black at endpoints.
    #[must_use]
    pub fn f(&self, next: &Self, mode: TransportMode) -> Rgb {
        let VertexKind::Surface { si, bsdf, .. } = &self.kind else {
            return Rgb::BLACK;
        };
        let Some(wi) = (next.p() - self.p()).try_normalize() else {
            return Rgb::BLACK;
        };
        bsdf.f_mode(si.wo, wi, mode) * correct_shading_normal(si, si.wo, wi, mode)
    }

    /// Radiance emitted from this vertex towards `towards` (a light endpoint or an
    /// emitting surface; the escaped-ray vertex sums the infinite lights).
    #[must_use]
    pub fn le(&self, scene: &Scene, towards: &Self) -> Rgb {
        let Some(w) = (towards.p() - self.p()).try_normalize() else {
            return Rgb::BLACK;
        };
        match self.kind {
            VertexKind::Light(None) => {
                let mut l = Rgb::BLACK;
                for &i in &scene.infinite_lights {
                    l += scene.lights[i as usize].le(-w);
                }
                l
            }
            VertexKind::Surface { light: Some(i), .. } => match &scene.lights[i as usize] {
                Light::DiffuseArea(area) => area.l(self.ng(), w),
                _ => Rgb::BLACK,
            },
            _ => Rgb::BLACK,
        }
    }

    /// Area density of `next` sampled from this vertex, which was reached from `prev`
    /// (pbrt-v4 `Vertex::PDF`): the camera's directional importance density, a light's
    /// emission density, or the BSDF density, converted to area at `next`.
    #[must_use]
    pub fn pdf(&self, ctx: &Context<'_>, prev: Option<&Self>, next: &Self) -> f32 {
        if matches!(self.kind, VertexKind::Light(_)) {
            return self.pdf_light(ctx, next);
        }
        let Some(wn) = (next.p() - self.p()).try_normalize() else {
            return 0.0;
        };
        let pdf = match &self.kind {
            // The camera's density is per area at `next` (see `Camera::pdf_area_per_cos`:
            // an orthographic camera's is not a solid-angle density over r^2).
            VertexKind::Camera if !next.at_infinity && ctx.scene.camera.is_orthographic() => {
                let pdf = ctx.scene.camera.pdf_area_per_cos(self.p(), next.p());
                return if next.is_on_surface() {
                    pdf * next.ng().dot(wn).abs()
                } else {
                    pdf
                };
            }
            VertexKind::Camera => ctx.scene.camera.pdf_we(&Ray::new(self.p(), wn)).1,
            VertexKind::Surface { bsdf, .. } => {
                let Some(wp) = prev.and_then(|p| (p.p() - self.p()).try_normalize()) else {
                    return 0.0;
                };
                bsdf.pdf(wp, wn)
            }
            VertexKind::Light(_) => unreachable!("handled above"),
        };
        self.convert_density(pdf, next)
    }

    /// Area density of `next` as the second vertex of a light subpath starting at this
    /// light vertex (pbrt-v4 `PDFLight`): the emission's directional density over the
    /// squared distance (for lights at infinity the density on the scene's bounding disk),
    /// times the cosine at `next`.
    #[must_use]
    pub fn pdf_light(&self, ctx: &Context<'_>, next: &Self) -> f32 {
        let w = next.p() - self.p();
        let d2 = w.length_squared();
        if d2 == 0.0 {
            return 0.0;
        }
        let inv_d2 = 1.0 / d2;
        let w = w * inv_d2.sqrt();
        let mut pdf = if self.at_infinity {
            1.0 / (PI * ctx.scene_radius * ctx.scene_radius)
        } else {
            let Some(l) = self.light_index() else {
                return 0.0;
            };
            let (_, pdf_dir) = ctx.scene.lights[l as usize].pdf_le(&Ray::new(self.p(), w), self.ng());
            pdf_dir * inv_d2
        };
        if next.is_on_surface() {
            pdf *= next.ng().dot(w).abs();
        }
        pdf
    }

    /// Density of this light vertex as the origin of a light subpath (pbrt-v4
    /// `PDFLightOrigin`): light selection times the emission's positional density, or for
    /// lights at infinity the solid-angle density of the direction towards `next`.
    #[must_use]
    pub fn pdf_light_origin(&self, ctx: &Context<'_>, next: &Self) -> f32 {
        let Some(w) = (next.p() - self.p()).try_normalize() else {
            return 0.0;
        };
        if self.at_infinity {
            return infinite_light_density(ctx.scene, -w);
        }
        let Some(l) = self.light_index() else {
            return 0.0;
        };
        let pmf = ctx.scene.light_sampler.pmf(l as usize);
        let (pdf_pos, _) = ctx.scene.lights[l as usize].pdf_le(&Ray::new(self.p(), w), self.ng());
        pmf * pdf_pos
    }
}

/// Density of choosing an infinite light and sampling the direction `w` (pointing away
/// from the scene) from it, summed over the infinite lights.
#[must_use]
pub fn infinite_light_density(scene: &Scene, w: Vec3) -> f32 {
    scene
        .infinite_lights
        .iter()
        .map(|&i| scene.light_sampler.pmf(i as usize) * scene.lights[i as usize].pdf_li_direction(w))
        .sum()
}

/// pbrt-v4 `CorrectShadingNormal`: importance transported with shading normals needs
/// `|wo.ns| |wi.ng| / (|wo.ng| |wi.ns|)` to stay the adjoint of radiance (Veach 1997,
/// section 5.3); radiance needs nothing.
#[must_use]
pub fn correct_shading_normal(si: &SurfaceInteraction, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
    match mode {
        TransportMode::Radiance => 1.0,
        TransportMode::Importance => {
            let num = wo.dot(si.ns).abs() * wi.dot(si.n()).abs();
            let denom = wo.dot(si.n()).abs() * wi.dot(si.ns).abs();
            if denom == 0.0 {
                0.0
            } else {
                num / denom
            }
        }
    }
}
