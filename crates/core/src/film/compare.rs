//! Comparing two images of the same size: MSE, relative MSE, per-channel means, and the
//! relative error of block means (which averages per-pixel noise away and keeps bias).

use super::REL_MSE_EPSILON;
use crate::color::Rgb;

/// Offset in the denominator of the block-mean relative error, `|a - b| / (|b| + eps)`, so
/// (nearly) black blocks of the reference do not dominate.
pub const BLOCK_REL_EPSILON: f64 = 0.01;

/// Default block size (pixels per side) for block means.
pub const DEFAULT_BLOCK: u32 = 8;

/// Why two images cannot be compared or an image cannot be downsampled.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CompareError {
    /// The images (or a pixel buffer and its stated size) differ in size.
    #[error("size mismatch: {a_width}x{a_height} vs {b_width}x{b_height}")]
    SizeMismatch {
        /// Width of the first image.
        a_width: u32,
        /// Height of the first image.
        a_height: u32,
        /// Width of the second image.
        b_width: u32,
        /// Height of the second image.
        b_height: u32,
    },
    /// A pixel buffer's length is not `width * height`.
    #[error("{len} pixels for a {width}x{height} image")]
    BadBuffer {
        /// Buffer length.
        len: usize,
        /// Stated width.
        width: u32,
        /// Stated height.
        height: u32,
    },
    /// The downsampling factor is zero or does not divide the size.
    #[error(
        "cannot box-downsample a {width}x{height} image by {factor}: the factor must be positive and divide both sides"
    )]
    BadFactor {
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// Requested factor.
        factor: u32,
    },
    /// A block size of zero.
    #[error("block size must be positive")]
    ZeroBlock,
}

/// Measurements comparing image `a` against image `b` (the reference).
#[derive(Clone, Debug, PartialEq)]
pub struct ImageComparison {
    /// Width of both images.
    pub width: u32,
    /// Height of both images.
    pub height: u32,
    /// Block side in pixels used for the block means.
    pub block: u32,
    /// Mean squared error over pixels and channels.
    pub mse: f64,
    /// Relative MSE, `(a - b)^2 / (b^2 + REL_MSE_EPSILON)` averaged over pixels and channels
    /// (the definition of [`super::FilmStatistics`]).
    pub rel_mse: f64,
    /// Mean of `a` per channel.
    pub mean_a: [f64; 3],
    /// Mean of `b` per channel.
    pub mean_b: [f64; 3],
    /// Per channel, the mean over blocks of `|a_blk - b_blk| / (|b_blk| + BLOCK_REL_EPSILON)`.
    pub block_rel_mean: [f64; 3],
    /// Per channel, the maximum over blocks of the same.
    pub block_rel_max: [f64; 3],
    /// Number of blocks (partial blocks at the right and bottom edges included).
    pub blocks: usize,
}

impl ImageComparison {
    /// Compare `a` with reference `b`, both `width x height`, row-major, using
    /// `block x block` pixel blocks (partial blocks at the right and bottom edges are
    /// averaged over the pixels they have).
    ///
    /// # Errors
    /// When a buffer length is not `width * height`, or `block` is zero.
    pub fn new(a: &[Rgb], b: &[Rgb], width: u32, height: u32, block: u32) -> Result<Self, CompareError> {
        let n = width as usize * height as usize;
        for len in [a.len(), b.len()] {
            if len != n {
                return Err(CompareError::BadBuffer { len, width, height });
            }
        }
        if block == 0 {
            return Err(CompareError::ZeroBlock);
        }
        let np = n.max(1) as f64;
        let (mut se, mut rse) = (0.0f64, 0.0f64);
        let (mut sa, mut sb) = ([0.0f64; 3], [0.0f64; 3]);
        for (pa, pb) in a.iter().zip(b) {
            for c in 0..3 {
                let (x, r) = (f64::from(pa[c]), f64::from(pb[c]));
                let d = x - r;
                se += d * d;
                rse += d * d / (r * r + REL_MSE_EPSILON);
                sa[c] += x;
                sb[c] += r;
            }
        }
        let (bx, by) = (width.div_ceil(block), height.div_ceil(block));
        let mut rel_sum = [0.0f64; 3];
        let mut rel_max = [0.0f64; 3];
        for j in 0..by {
            for i in 0..bx {
                let (ma, mb) = block_means(a, b, width, height, i * block, j * block, block);
                for c in 0..3 {
                    let e = (ma[c] - mb[c]).abs() / (mb[c].abs() + BLOCK_REL_EPSILON);
                    rel_sum[c] += e;
                    rel_max[c] = rel_max[c].max(e);
                }
            }
        }
        let blocks = (bx * by) as usize;
        let nb = blocks.max(1) as f64;
        Ok(Self {
            width,
            height,
            block,
            mse: se / (3.0 * np),
            rel_mse: rse / (3.0 * np),
            mean_a: sa.map(|s| s / np),
            mean_b: sb.map(|s| s / np),
            block_rel_mean: rel_sum.map(|s| s / nb),
            block_rel_max: rel_max,
            blocks,
        })
    }

    /// Per channel, `(mean_a - mean_b) / mean_b` (0 where both are 0).
    #[must_use]
    pub fn mean_rel_diff(&self) -> [f64; 3] {
        std::array::from_fn(|c| {
            let d = self.mean_a[c] - self.mean_b[c];
            if d == 0.0 {
                0.0
            } else {
                d / self.mean_b[c]
            }
        })
    }
}

/// Per-channel means of `a` and `b` over the block at `(x0, y0)`, clipped to the image.
#[allow(clippy::too_many_arguments)]
fn block_means(a: &[Rgb], b: &[Rgb], width: u32, height: u32, x0: u32, y0: u32, block: u32) -> ([f64; 3], [f64; 3]) {
    let (x1, y1) = ((x0 + block).min(width), (y0 + block).min(height));
    let (mut ma, mut mb) = ([0.0f64; 3], [0.0f64; 3]);
    for y in y0..y1 {
        for x in x0..x1 {
            let k = y as usize * width as usize + x as usize;
            for c in 0..3 {
                ma[c] += f64::from(a[k][c]);
                mb[c] += f64::from(b[k][c]);
            }
        }
    }
    let cnt = f64::from((x1 - x0) * (y1 - y0));
    (ma.map(|s| s / cnt), mb.map(|s| s / cnt))
}

/// Per-channel block means of one image (`block x block`, partial edge blocks averaged over
/// what they have), row-major over blocks: `(blocks_x, blocks_y, means)`.
///
/// # Errors
/// When the buffer length is not `width * height`, or `block` is zero.
pub fn block_means_of(
    img: &[Rgb],
    width: u32,
    height: u32,
    block: u32,
) -> Result<(u32, u32, Vec<[f64; 3]>), CompareError> {
    if img.len() != width as usize * height as usize {
        return Err(CompareError::BadBuffer {
            len: img.len(),
            width,
            height,
        });
    }
    if block == 0 {
        return Err(CompareError::ZeroBlock);
    }
    let (bx, by) = (width.div_ceil(block), height.div_ceil(block));
    let mut out = Vec::with_capacity((bx * by) as usize);
    for j in 0..by {
        for i in 0..bx {
            out.push(block_means(img, img, width, height, i * block, j * block, block).0);
        }
    }
    Ok((bx, by, out))
}

/// Box-downsample `img` (`width x height`, row-major) by an integer `factor`: each output
/// pixel is the mean of a `factor x factor` square. Returns `(width / factor, height / factor,
/// pixels)`.
///
/// # Errors
/// When `factor` is zero or does not divide both sides, or the buffer length is wrong.
pub fn downsample_box(img: &[Rgb], width: u32, height: u32, factor: u32) -> Result<(u32, u32, Vec<Rgb>), CompareError> {
    if img.len() != width as usize * height as usize {
        return Err(CompareError::BadBuffer {
            len: img.len(),
            width,
            height,
        });
    }
    if factor == 0 || !width.is_multiple_of(factor) || !height.is_multiple_of(factor) {
        return Err(CompareError::BadFactor { width, height, factor });
    }
    let (w, h) = (width / factor, height / factor);
    let mut out = Vec::with_capacity(w as usize * h as usize);
    let inv = 1.0 / f64::from(factor * factor);
    for y in 0..h {
        for x in 0..w {
            let mut s = [0.0f64; 3];
            for dy in 0..factor {
                for dx in 0..factor {
                    let p = img[(y * factor + dy) as usize * width as usize + (x * factor + dx) as usize];
                    for (c, v) in s.iter_mut().enumerate() {
                        *v += f64::from(p[c]);
                    }
                }
            }
            out.push(Rgb::new((s[0] * inv) as f32, (s[1] * inv) as f32, (s[2] * inv) as f32));
        }
    }
    Ok((w, h, out))
}

/// Per-pixel relative error `|a - b| / (|b| + BLOCK_REL_EPSILON)`, averaged over channels.
///
/// # Panics
/// When the buffers differ in length.
#[must_use]
pub fn pixel_rel_error(a: &[Rgb], b: &[Rgb]) -> Vec<f64> {
    assert_eq!(a.len(), b.len(), "images of different sizes");
    a.iter()
        .zip(b)
        .map(|(pa, pb)| {
            (0..3)
                .map(|c| {
                    let r = f64::from(pb[c]);
                    (f64::from(pa[c]) - r).abs() / (r.abs() + BLOCK_REL_EPSILON)
                })
                .sum::<f64>()
                / 3.0
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9 * (1.0 + b.abs())
    }

    #[test]
    fn identical_images_have_zero_error() {
        let img: Vec<Rgb> = (0..12).map(|i| Rgb::new(i as f32, 0.5, 2.0)).collect();
        let c = ImageComparison::new(&img, &img, 4, 3, 2).unwrap();
        assert_eq!(c.mse, 0.0);
        assert_eq!(c.rel_mse, 0.0);
        assert_eq!(c.block_rel_mean, [0.0; 3]);
        assert_eq!(c.block_rel_max, [0.0; 3]);
        assert_eq!(c.blocks, 4); // 2x2 blocks, the bottom row partial
        assert!(close(c.mean_a[0], 5.5));
        assert_eq!(c.mean_a, c.mean_b);
    }

    #[test]
    fn hand_computed_values() {
        // 2x2 images; b = 1 everywhere; a = 1 except pixel (1, 0) red = 3.
        let b = vec![Rgb::splat(1.0); 4];
        let mut a = b.clone();
        a[1] = Rgb::new(3.0, 1.0, 1.0);
        let c = ImageComparison::new(&a, &b, 2, 2, 2).unwrap();
        // One squared difference of 4 among 12 values.
        assert!(close(c.mse, 4.0 / 12.0));
        assert!(close(c.rel_mse, 4.0 / 1.01 / 12.0));
        assert!(close(c.mean_a[0], 1.5));
        assert!(close(c.mean_b[0], 1.0));
        // One block: red block means 1.5 vs 1 -> 0.5 / 1.01.
        assert!(close(c.block_rel_mean[0], 0.5 / 1.01));
        assert!(close(c.block_rel_max[0], 0.5 / 1.01));
        assert_eq!(c.block_rel_mean[1], 0.0);
        assert!(close(c.mean_rel_diff()[0], 0.5));

        // Blocks of 1 pixel: four blocks, one with error 2 / 1.01.
        let c = ImageComparison::new(&a, &b, 2, 2, 1).unwrap();
        assert!(close(c.block_rel_mean[0], 2.0 / 1.01 / 4.0));
        assert!(close(c.block_rel_max[0], 2.0 / 1.01));
    }

    #[test]
    fn zero_mean_noise_averages_away_in_blocks() {
        // A checkerboard of +-0.5 around 1: large per-pixel error, no block error.
        let b = vec![Rgb::splat(1.0); 16];
        let a: Vec<Rgb> = (0..16)
            .map(|k| Rgb::splat(if (k % 4 + k / 4) % 2 == 0 { 1.5 } else { 0.5 }))
            .collect();
        let c = ImageComparison::new(&a, &b, 4, 4, 2).unwrap();
        assert!(close(c.mse, 0.25));
        assert!(c.block_rel_max.iter().all(|&e| e < 1e-12));
    }

    #[test]
    fn rejects_bad_sizes() {
        let a = vec![Rgb::BLACK; 4];
        assert!(matches!(
            ImageComparison::new(&a, &a[..3], 2, 2, 8),
            Err(CompareError::BadBuffer { len: 3, .. })
        ));
        assert_eq!(ImageComparison::new(&a, &a, 2, 2, 0), Err(CompareError::ZeroBlock));
    }

    #[test]
    fn downsample_box_averages_squares() {
        // 4x2 -> 2x1 by 2.
        let img: Vec<Rgb> = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]
            .iter()
            .map(|&v| Rgb::splat(v))
            .collect();
        let (w, h, out) = downsample_box(&img, 4, 2, 2).unwrap();
        assert_eq!((w, h), (2, 1));
        assert_eq!(out, vec![Rgb::splat(3.5), Rgb::splat(5.5)]);
        let (w, h, same) = downsample_box(&img, 4, 2, 1).unwrap();
        assert_eq!((w, h, same), (4, 2, img.clone()));
        assert!(matches!(
            downsample_box(&img, 4, 2, 3),
            Err(CompareError::BadFactor { factor: 3, .. })
        ));
        assert!(matches!(
            downsample_box(&img, 4, 2, 0),
            Err(CompareError::BadFactor { .. })
        ));
        let e = downsample_box(&img, 4, 2, 4).unwrap_err().to_string();
        assert!(e.contains("4x2") && e.contains("divide"), "{e}");
    }

    #[test]
    fn pixel_rel_error_per_pixel() {
        let b = vec![Rgb::splat(1.0), Rgb::BLACK];
        let a = vec![Rgb::new(2.0, 1.0, 1.0), Rgb::BLACK];
        let e = pixel_rel_error(&a, &b);
        assert!(close(e[0], 1.0 / 1.01 / 3.0));
        assert_eq!(e[1], 0.0);
    }
}
