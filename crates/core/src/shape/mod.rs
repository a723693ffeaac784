//! Layer 2: shapes. Ray intersection with error-bounded hit points, surface interactions,
//! and uniform-area sampling for area lights.

mod bilinear;
mod cylinder;
mod disk;
mod interaction;
mod mesh;
mod sphere;
mod triangle;

pub use bilinear::BilinearPatch;
pub use cylinder::Cylinder;
pub use disk::Disk;
pub use interaction::{Interaction, MeshPoint, SurfaceInteraction};
pub use mesh::{BilinearMesh, TriangleMesh};
pub use sphere::{Sphere, SphereClip};
pub use triangle::Triangle;

use crate::math::{Bounds3, Ray, Vec2};

/// A point sampled on a shape's surface, with its density per unit area.
#[derive(Clone, Copy, Debug)]
pub struct ShapeSample {
    /// The point, its normal and error bound.
    pub intr: Interaction,
    /// Density per unit area (world space) of having sampled this point.
    pub pdf_area: f32,
    /// Surface parameterisation at the point (as [`SurfaceInteraction::uv`]), for
    /// textures such as an area light's alpha.
    pub uv: Vec2,
}

/// The result of a ray-shape test: distance and the shape-specific data needed to build a
/// [`SurfaceInteraction`] later, only for the closest hit.
#[derive(Clone, Copy, Debug)]
pub struct ShapeHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Barycentrics (triangles), the patch's `(u, v, 0)` (bilinear patches) or the
    /// object-space hit point (spheres, disks, cylinders).
    pub data: [f32; 3],
}

/// The closed set of shapes.
#[derive(Clone, Debug)]
pub enum Shape {
    /// One triangle of a mesh.
    Triangle(Triangle),
    /// A sphere.
    Sphere(Sphere),
    /// A disk, annulus or sector.
    Disk(Disk),
    /// An open cylinder, possibly cut in azimuth.
    Cylinder(Cylinder),
    /// One bilinear patch of a mesh.
    Bilinear(BilinearPatch),
}

/// Forward a method call to the variant.
macro_rules! dispatch {
    ($self:ident, $s:ident => $e:expr) => {
        match $self {
            Shape::Triangle($s) => $e,
            Shape::Sphere($s) => $e,
            Shape::Disk($s) => $e,
            Shape::Cylinder($s) => $e,
            Shape::Bilinear($s) => $e,
        }
    };
}

impl Shape {
    /// World-space bounds.
    #[must_use]
    pub fn bounds(&self) -> Bounds3 {
        dispatch!(self, s => s.bounds())
    }

    /// Closest intersection with `ray` in `(0, t_max)`.
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        dispatch!(self, s => s.intersect(ray, t_max))
    }

    /// The full surface interaction for a hit found by [`Self::intersect`].
    #[must_use]
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        dispatch!(self, s => s.interaction(ray, hit))
    }

    /// [`Self::interaction`] written into `si`; in place for triangles (the common case in
    /// a render's inner loop), where a returned interaction would be copied.
    pub fn interaction_into(&self, ray: &Ray, hit: &ShapeHit, si: &mut SurfaceInteraction) {
        match self {
            Self::Triangle(t) => t.interaction_into(ray, hit, si),
            _ => *si = self.interaction(ray, hit),
        }
    }

    /// Surface area in world space.
    #[must_use]
    pub fn area(&self) -> f32 {
        dispatch!(self, s => s.area())
    }

    /// A point uniformly distributed by area (exactly so for triangles, disks, cylinders, uniformly
    /// scaled spheres and parallelogram patches; the returned pdf is always the true
    /// density).
    #[must_use]
    pub fn sample_area(&self, u: Vec2) -> ShapeSample {
        dispatch!(self, s => s.sample_area(u))
    }

    /// Density per unit area of [`Self::sample_area`] at a point `intr` of the surface.
    #[must_use]
    pub fn pdf_area(&self, intr: &Interaction) -> f32 {
        dispatch!(self, s => s.pdf_area(intr))
    }
}
