//! Warps: maps from uniform samples in [0, 1)^2 (or [0, 1)) to other domains, each as a
//! triplet `sample_x` / `x_pdf` / `invert_x` (the inverse maps a point back to the `u`
//! that produces it). Directional pdfs are per unit solid angle, planar ones per unit area.

mod bilinear;
mod cone;
mod disk;
mod equal_area;
mod hemisphere;
mod sphere;
mod tent;
mod triangle;

pub use bilinear::{bilinear_pdf, invert_bilinear, invert_linear, linear_pdf, sample_bilinear, sample_linear};
pub use cone::{invert_uniform_cone, sample_uniform_cone, uniform_cone_pdf};
pub use disk::{
    invert_uniform_disk_concentric, invert_uniform_disk_polar, sample_uniform_disk_concentric,
    sample_uniform_disk_polar, uniform_disk_pdf,
};
pub use equal_area::{equal_area_sphere_to_square, equal_area_square_to_sphere};
pub use hemisphere::{
    cosine_hemisphere_pdf, invert_cosine_hemisphere, invert_uniform_hemisphere, sample_cosine_hemisphere,
    sample_uniform_hemisphere, uniform_hemisphere_pdf,
};
pub use sphere::{invert_uniform_sphere, sample_uniform_sphere, uniform_sphere_pdf};
pub use tent::{invert_tent, sample_tent, tent_pdf};
pub use triangle::{invert_uniform_triangle, sample_uniform_triangle};

use crate::math::INV_2PI;
use crate::sampling::ONE_MINUS_EPSILON;

/// The azimuth of `(x, y)` as a fraction of a full turn, in [0, 1): the inverse of
/// `phi = 2 pi u`.
#[inline]
fn azimuth_fraction(x: f32, y: f32) -> f32 {
    let phi = y.atan2(x);
    let phi = if phi < 0.0 { phi + std::f32::consts::TAU } else { phi };
    (phi * INV_2PI).min(ONE_MINUS_EPSILON)
}

/// Helpers for the warp tests: a deterministic spread of `u` values including the edges.
#[cfg(test)]
mod test_points {
    use crate::math::Vec2;
    use crate::sampling::{Pcg32, ONE_MINUS_EPSILON};

    /// Corners, edges, a regular grid and random points of [0, 1)^2.
    pub(super) fn unit_square() -> Vec<Vec2> {
        let edge = [0.0, 1e-6, 0.25, 0.5, 0.75, 1.0 - 1e-6, ONE_MINUS_EPSILON];
        let mut points: Vec<Vec2> = edge
            .iter()
            .flat_map(|&x| edge.iter().map(move |&y| Vec2::new(x, y)))
            .collect();
        points.extend((0..32 * 32).map(|i| Vec2::new((i % 32) as f32 + 0.5, (i / 32) as f32 + 0.5) / 32.0));
        let mut rng = Pcg32::new(1, 2);
        points.extend((0..4096).map(|_| Vec2::new(rng.next_f32(), rng.next_f32())));
        points
    }
}
