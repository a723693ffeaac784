//! Tests of what the stratified and Sobol' samplers promise beyond uniform values: the
//! unscrambled Sobol' sequence, stratification and net properties, and lower integration
//! error than independent sampling on smooth integrands.

use super::sobol::{sobol_u32, sobol_u32_reversed, SOBOL_DIMENSIONS};
use super::Sampler;
use super::{SamplerDesc, SamplerKind};
use crate::math::UVec2;

fn make(kind: SamplerKind, spp: u32, seed: u64) -> Sampler {
    Sampler::new(&SamplerDesc {
        kind,
        samples_per_pixel: spp,
        seed,
    })
}

fn stratified(x_samples: u32, y_samples: u32) -> SamplerKind {
    SamplerKind::Stratified {
        x_samples,
        y_samples,
        jitter: true,
    }
}

fn unit(x: u32) -> f64 {
    f64::from(x) / 4_294_967_296.0
}

/// The nibble tables give the bit-by-bit points, reversed, in every dimension: for the
/// single bits (each column), small indices and scrambled-looking ones.
#[test]
fn sobol_tables_match_the_matrices() {
    let mut x = 0x9e37_79b9u32;
    for dim in 0..SOBOL_DIMENSIONS {
        let singles = (0..32).map(|b| 1u32 << b);
        let hashed = (0..2000).map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x
        });
        for index in (0..256).chain(singles).chain(hashed).chain([u32::MAX]) {
            assert_eq!(
                sobol_u32_reversed(index, dim),
                sobol_u32(index, dim).reverse_bits(),
                "dim {dim} index {index}"
            );
        }
    }
}

#[test]
fn sobol_first_points_match_the_unscrambled_sequence() {
    let first = |dim| (0..8).map(|i| unit(sobol_u32(i, dim))).collect::<Vec<_>>();
    // Dimension 0 is van der Corput; 1 and 2 are Joe and Kuo's dimensions 2 and 3.
    assert_eq!(first(0), [0.0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875]);
    assert_eq!(first(1), [0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875]);
    assert_eq!(first(2), [0.0, 0.5, 0.75, 0.25, 0.375, 0.875, 0.625, 0.125]);
}

#[test]
fn every_sobol_dimension_is_a_0_1_sequence_and_all_differ() {
    // Each aligned block of 2^m points has one point in each interval of width 2^-m.
    for dim in 0..SOBOL_DIMENSIONS {
        for m in 0..=10u32 {
            for block in 0..4u32 {
                let mut seen = vec![false; 1 << m];
                for i in 0..1u32 << m {
                    let cell = (sobol_u32((block << m) | i, dim) >> (31 - m) >> 1) as usize;
                    assert!(!seen[cell], "dim {dim} m {m} block {block}");
                    seen[cell] = true;
                }
            }
        }
    }
    // No two dimensions share their first 64 points.
    let points: Vec<Vec<u32>> = (0..SOBOL_DIMENSIONS)
        .map(|d| (0..64).map(|i| sobol_u32(i, d)).collect())
        .collect();
    for a in 0..SOBOL_DIMENSIONS {
        for b in a + 1..SOBOL_DIMENSIONS {
            assert_ne!(points[a], points[b], "dims {a} and {b}");
        }
    }
}

/// Whether `points` (2^m of them) have exactly one point in every elementary interval
/// of area 2^-m: [i 2^-a, (i+1) 2^-a) x [j 2^-(m-a), (j+1) 2^-(m-a)).
fn is_0_m_2_net(points: &[(f32, f32)], m: u32) -> bool {
    (0..=m).all(|a| {
        let (nx, ny) = (1usize << a, 1usize << (m - a));
        let mut seen = vec![false; nx * ny];
        points.iter().all(|&(x, y)| {
            let cell = (x * nx as f32) as usize + nx * (y * ny as f32) as usize;
            !std::mem::replace(&mut seen[cell], true)
        })
    })
}

#[test]
fn scrambled_sobol_pixel_samples_form_0_m_2_nets() {
    for m in 0..=8u32 {
        let spp = 1u32 << m;
        for seed in [0u64, 1, 12345] {
            let mut s = make(SamplerKind::OwenSobol, spp, seed);
            for p in 0..16u32 {
                let pixel = UVec2::new(p % 4, p / 4 + 100);
                let points: Vec<(f32, f32)> = (0..spp)
                    .map(|i| {
                        s.start_pixel_sample(pixel, i);
                        let u = s.get_pixel_2d();
                        (u.x, u.y)
                    })
                    .collect();
                assert!(is_0_m_2_net(&points, m), "m {m} seed {seed} pixel {pixel}");
            }
        }
    }
    // The scrambling is real: the first point differs between pixels.
    let mut s = make(SamplerKind::OwenSobol, 16, 0);
    s.start_pixel_sample(UVec2::new(0, 0), 0);
    let a = s.get_pixel_2d();
    s.start_pixel_sample(UVec2::new(1, 0), 0);
    assert_ne!(a, s.get_pixel_2d());
}

/// Draws `dims` values of each of the `spp` samples of `pixel` (by `get_1d`).
fn columns(s: &mut Sampler, pixel: UVec2, spp: u32, dims: usize) -> Vec<Vec<f32>> {
    let mut cols = vec![Vec::new(); dims];
    for i in 0..spp {
        s.start_pixel_sample(pixel, i);
        for col in &mut cols {
            col.push(s.get_1d());
        }
    }
    cols
}

fn one_per_interval(values: &[f32]) -> bool {
    let n = values.len();
    let mut seen = vec![false; n];
    values
        .iter()
        .all(|&v| !std::mem::replace(&mut seen[(v * n as f32) as usize], true))
}

#[test]
fn every_dimension_is_stratified_for_sobol_and_stratified() {
    // 100 dimensions run past the Sobol' table into the padded ones.
    for kind in [SamplerKind::OwenSobol, stratified(4, 4)] {
        let mut s = make(kind, 16, 3);
        for p in 0..8u32 {
            for (dim, col) in columns(&mut s, UVec2::new(p, 2 * p), 16, 100).iter().enumerate() {
                assert!(one_per_interval(col), "{kind:?} pixel {p} dim {dim}: {col:?}");
            }
        }
    }
}

#[test]
fn stratified_puts_one_sample_in_each_stratum() {
    for jitter in [true, false] {
        let kind = SamplerKind::Stratified {
            x_samples: 3,
            y_samples: 5,
            jitter,
        };
        let mut s = make(kind, 15, 9);
        for p in 0..8u32 {
            let pixel = UVec2::new(p, 7);
            let mut grids = [[[0u32; 5]; 3]; 2];
            let mut line = [0u32; 15];
            for i in 0..15 {
                s.start_pixel_sample(pixel, i);
                let a = s.get_pixel_2d();
                let c = s.get_1d();
                let b = s.get_2d();
                for (grid, u) in grids.iter_mut().zip([a, b]) {
                    grid[(u.x * 3.0) as usize][(u.y * 5.0) as usize] += 1;
                    if !jitter {
                        // Centres of the strata.
                        assert!(((u.x * 3.0).fract() - 0.5).abs() < 1e-5, "{u}");
                    }
                }
                line[(c * 15.0) as usize] += 1;
            }
            assert!(grids.iter().flatten().flatten().all(|&n| n == 1), "{grids:?}");
            assert!(line.iter().all(|&n| n == 1), "{line:?}");
        }
    }
}

/// RMS error, over `pixels` pixels, of the `spp`-sample estimate of an integral whose
/// integrand is evaluated from a started sampler.
fn rms_error(kind: SamplerKind, spp: u32, exact: f64, f: impl Fn(&mut Sampler) -> f64) -> f64 {
    let pixels = 400u32;
    let mut sum_sq = 0.0;
    for p in 0..pixels {
        let mut s = make(kind, spp, u64::from(p % 5));
        let pixel = UVec2::new(p % 20, p / 20);
        let mean = (0..spp)
            .map(|i| {
                s.start_pixel_sample(pixel, i);
                f(&mut s)
            })
            .sum::<f64>()
            / f64::from(spp);
        sum_sq += (mean - exact).powi(2);
    }
    (sum_sq / f64::from(pixels)).sqrt()
}

/// Independent, stratified and Sobol' RMS errors at 64 samples per pixel.
fn errors(exact: f64, f: impl Fn(&mut Sampler) -> f64 + Copy) -> [f64; 3] {
    [SamplerKind::Independent, stratified(8, 8), SamplerKind::OwenSobol].map(|kind| rms_error(kind, 64, exact, f))
}

#[test]
fn sobol_and_stratified_beat_independent_on_a_smooth_2d_integrand() {
    // The integral of (x + y)^2 over the unit square is 7/6.
    let [independent, stratified, sobol] = errors(7.0 / 6.0, |s| {
        let u = s.get_pixel_2d();
        f64::from(u.x + u.y).powi(2)
    });
    eprintln!("(x+y)^2 RMSE: independent {independent:.2e}, stratified {stratified:.2e}, sobol {sobol:.2e}");
    assert!(stratified < 0.5 * independent && sobol < 0.5 * independent);
}

#[test]
fn sobol_and_stratified_beat_independent_in_later_dimensions() {
    // After the pixel dimensions: the integral over [0,1)^4 of
    // cos(a) e^(b + c) (1 + d)^2 / 3 is sin(1) (e - 1)^2 7/9.
    let exact = 1f64.sin() * (1f64.exp() - 1.0).powi(2) * 7.0 / 9.0;
    let [independent, stratified, sobol] = errors(exact, |s| {
        s.get_pixel_2d();
        let a = f64::from(s.get_1d());
        let bc = s.get_2d();
        let d = f64::from(s.get_1d());
        a.cos() * f64::from(bc.x + bc.y).exp() * (1.0 + d).powi(2) / 3.0
    });
    eprintln!("4-D RMSE: independent {independent:.2e}, stratified {stratified:.2e}, sobol {sobol:.2e}");
    assert!(stratified < 0.5 * independent && sobol < 0.5 * independent);
}

/// The per-pixel cache of the Sobol' points' high digits gives the values a fresh sampler
/// gives, when pixels alternate and when a pixel's shuffled index crosses into another
/// block of 256 (where the cached digits change), in the table's dimensions and the padded ones after them.
#[test]
fn sobol_cache_matches_a_fresh_sampler() {
    let dims = SOBOL_DIMENSIONS + 6;
    let values = |s: &mut Sampler, pixel: UVec2, index: u32| {
        s.start_pixel_sample(pixel, index);
        (0..dims).map(|_| s.get_1d()).collect::<Vec<_>>()
    };
    let (a, b) = (UVec2::new(3, 5), UVec2::new(4, 5));
    let mut reused = make(SamplerKind::OwenSobol, 1024, 7);
    for index in 0..600 {
        // Pixel `a` also runs through consecutive samples, where only the index changes.
        let pixels: &[UVec2] = if index % 5 == 0 { &[a, b, a] } else { &[a] };
        for &pixel in pixels {
            let fresh = values(&mut make(SamplerKind::OwenSobol, 1024, 7), pixel, index);
            assert_eq!(values(&mut reused, pixel, index), fresh, "{pixel} sample {index}");
        }
    }
}
