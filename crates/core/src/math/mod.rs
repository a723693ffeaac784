//! Layer 0: vectors (re-exported from glam), rays, bounding boxes, orthonormal frames,
//! transforms and the floating-point error bookkeeping used to offset ray origins.

mod bounds;
mod float;
mod frame;
pub mod quadrature;
mod ray;
mod rounding;
pub mod simd;
mod transform;

pub use bounds::Bounds3;
pub use float::{gamma, next_float_down, next_float_up, offset_ray_origin, SHADOW_EPSILON};
pub use frame::Frame;
pub use glam::{Mat3, Mat4, UVec2, Vec2, Vec3, Vec4};
pub use ray::Ray;
pub use rounding::{ceil_to_i64, floor_to_i64};
pub use transform::Transform;

/// pi, as `f32`.
pub const PI: f32 = std::f32::consts::PI;
/// 1 / pi.
pub const INV_PI: f32 = std::f32::consts::FRAC_1_PI;
/// 1 / (2 pi).
pub const INV_2PI: f32 = 0.5 * std::f32::consts::FRAC_1_PI;
/// 1 / (4 pi).
pub const INV_4PI: f32 = 0.25 * std::f32::consts::FRAC_1_PI;

/// `x` squared.
#[inline]
#[must_use]
pub fn sqr(x: f32) -> f32 {
    x * x
}

/// Square root clamped at zero, so tiny negative rounding errors do not give NaN.
#[inline]
#[must_use]
pub fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}
