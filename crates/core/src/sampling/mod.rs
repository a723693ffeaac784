//! Layer 1: random numbers, samplers, warps from the unit square with their pdfs and
//! inverses, 1-D distributions, MIS heuristics, and the chi-square harness.
//! TEMPORARY stand-in: replaced by the full module when the sampling branch merges.

use crate::math::{UVec2, Vec2, Vec3, PI};
use crate::scene::SamplerDesc;

/// PCG32.
#[derive(Clone, Debug)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    /// New stream.
    #[must_use]
    pub fn new(seq: u64, seed: u64) -> Self {
        let mut r = Self {
            state: 0,
            inc: (seq << 1) | 1,
        };
        r.next_u32();
        r.state = r.state.wrapping_add(seed);
        r.next_u32();
        r
    }
    /// Next u32.
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(self.inc);
        let xs = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xs.rotate_right(rot)
    }
    /// Next f32 in [0,1).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}

fn mix(mut h: u64) -> u64 {
    h ^= h >> 33;
    h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
    h ^= h >> 33;
    h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    h ^ (h >> 33)
}

/// Sampler.
#[derive(Clone, Debug)]
pub enum Sampler {
    /// Independent.
    Independent {
        /// spp
        spp: u32,
        /// seed
        seed: u64,
        /// rng
        rng: Pcg32,
    },
}

impl Sampler {
    /// New.
    #[must_use]
    pub fn new(d: &SamplerDesc) -> Self {
        Self::Independent {
            spp: d.samples_per_pixel,
            seed: d.seed,
            rng: Pcg32::new(0, 0),
        }
    }
    /// spp.
    #[must_use]
    pub fn samples_per_pixel(&self) -> u32 {
        match self {
            Self::Independent { spp, .. } => *spp,
        }
    }
    /// Start.
    pub fn start_pixel_sample(&mut self, pixel: UVec2, index: u32) {
        match self {
            Self::Independent { seed, rng, .. } => {
                let h = mix(mix(*seed ^ mix(((pixel.x as u64) << 32) | pixel.y as u64)));
                *rng = Pcg32::new(h, mix(h ^ index as u64));
            }
        }
    }
    /// 1d.
    pub fn get_1d(&mut self) -> f32 {
        match self {
            Self::Independent { rng, .. } => rng.next_f32(),
        }
    }
    /// 2d.
    pub fn get_2d(&mut self) -> Vec2 {
        Vec2::new(self.get_1d(), self.get_1d())
    }
    /// pixel 2d.
    pub fn get_pixel_2d(&mut self) -> Vec2 {
        self.get_2d()
    }
}

/// Concentric disk.
#[must_use]
pub fn sample_uniform_disk_concentric(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, PI / 4.0 * (o.y / o.x))
    } else {
        (o.y, PI / 2.0 - PI / 4.0 * (o.x / o.y))
    };
    r * Vec2::new(theta.cos(), theta.sin())
}

/// Cosine hemisphere.
#[must_use]
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = sample_uniform_disk_concentric(u);
    Vec3::new(d.x, d.y, (1.0 - d.length_squared()).max(0.0).sqrt())
}

/// Cosine pdf.
#[must_use]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta * crate::math::INV_PI
}

/// Uniform sphere.
#[must_use]
pub fn sample_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Uniform triangle barycentrics.
#[must_use]
pub fn sample_uniform_triangle(u: Vec2) -> [f32; 3] {
    let su0 = u.x.sqrt();
    let b0 = 1.0 - su0;
    let b1 = u.y * su0;
    [b0, b1, 1.0 - b0 - b1]
}

/// Power heuristic.
#[must_use]
pub fn power_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    let f = nf * f_pdf;
    let g = ng * g_pdf;
    if f.is_infinite() {
        return 1.0;
    }
    if f == 0.0 && g == 0.0 {
        return 0.0;
    }
    f * f / (f * f + g * g)
}
