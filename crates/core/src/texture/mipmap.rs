//! MIP maps (pbrt-v4 section 10.4.3, `util/mipmap.cpp`): an image pyramid built once per
//! image, and its point, bilinear, trilinear and EWA lookups.
//!
//! Pyramid: pbrt-v4 first resamples an image whose sides are not powers of two up to the
//! next powers of two with a windowed sinc; we resample with an area-weighted box filter
//! instead (each new texel the exact average of the part of the image it covers), which
//! keeps the mean of the image exactly and never rings. Every further level averages 2x2
//! texels (2x1 once one side is 1 texel wide), down to 1x1.

use crate::color::Rgb;
use crate::math::Vec2;

/// How texel coordinates outside the image are brought back (pbrt-v4 `WrapMode`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum WrapMode {
    /// Tile the image.
    #[default]
    Repeat,
    /// Black outside.
    Black,
    /// Repeat the edge texels.
    Clamp,
    /// Mirror across the edges as pbrt-v4's equal-area octahedral sphere layout requires.
    OctahedralSphere,
}

/// Which lookup a MIP map does (pbrt-v4 `FilterFunction`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MipFilter {
    /// The nearest texel of the level chosen by the footprint.
    Point,
    /// Bilinear interpolation on the level chosen by the footprint.
    #[default]
    Bilinear,
    /// Bilinear on the two levels around the footprint, interpolated between them.
    Trilinear,
    /// Elliptically weighted average (Heckbert 1989) with a Gaussian weight.
    Ewa,
}

/// Filter settings of a lookup (pbrt-v4 `MIPMapFilterOptions`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MipFilterOptions {
    /// The lookup.
    pub filter: MipFilter,
    /// Largest ratio of the EWA ellipse's axes; longer ellipses are widened.
    pub max_anisotropy: f32,
}

impl Default for MipFilterOptions {
    fn default() -> Self {
        Self {
            filter: MipFilter::Bilinear,
            max_anisotropy: 8.0,
        }
    }
}

/// One level of the pyramid: linear RGB texels, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct MipLevel {
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// `width * height` texels, row by row.
    pub texels: Vec<Rgb>,
}

impl MipLevel {
    /// The texel at integer coordinates `(x, y)`, brought inside by `wrap`.
    #[must_use]
    pub fn texel(&self, x: i64, y: i64, wrap: WrapMode) -> Rgb {
        match remap(x, y, self.width as i64, self.height as i64, wrap) {
            Some((x, y)) => self.texels[y as usize * self.width + x as usize],
            None => Rgb::BLACK,
        }
    }

    /// Bilinear interpolation at `st` in [0, 1]^2 (texel centres at half-integers).
    #[must_use]
    pub fn bilerp(&self, st: Vec2, wrap: WrapMode) -> Rgb {
        let x = st.x * self.width as f32 - 0.5;
        let y = st.y * self.height as f32 - 0.5;
        let (xf, yf) = (x.floor(), y.floor());
        let (dx, dy) = (x - xf, y - yf);
        let (xi, yi) = (xf as i64, yf as i64);
        self.texel(xi, yi, wrap) * ((1.0 - dx) * (1.0 - dy))
            + self.texel(xi + 1, yi, wrap) * (dx * (1.0 - dy))
            + self.texel(xi, yi + 1, wrap) * ((1.0 - dx) * dy)
            + self.texel(xi + 1, yi + 1, wrap) * (dx * dy)
    }

    /// Mean of all texels.
    #[must_use]
    pub fn mean(&self) -> Rgb {
        let sum = self.texels.iter().fold([0.0f64; 3], |acc, t| {
            [
                acc[0] + f64::from(t.r),
                acc[1] + f64::from(t.g),
                acc[2] + f64::from(t.b),
            ]
        });
        let n = self.texels.len().max(1) as f64;
        Rgb::new((sum[0] / n) as f32, (sum[1] / n) as f32, (sum[2] / n) as f32)
    }
}

/// Integer texel coordinates inside a `w` x `h` image, or `None` for black (pbrt-v4
/// `RemapPixelCoords`).
fn remap(mut x: i64, mut y: i64, w: i64, h: i64, wrap: WrapMode) -> Option<(i64, i64)> {
    match wrap {
        WrapMode::Repeat => Some((x.rem_euclid(w), y.rem_euclid(h))),
        WrapMode::Clamp => Some((x.clamp(0, w - 1), y.clamp(0, h - 1))),
        WrapMode::Black => ((0..w).contains(&x) && (0..h).contains(&y)).then_some((x, y)),
        WrapMode::OctahedralSphere => {
            if x < 0 {
                x = -x;
                y = h - 1 - y;
            } else if x >= w {
                x = 2 * w - 1 - x;
                y = h - 1 - y;
            }
            if y < 0 {
                x = w - 1 - x;
                y = -y;
            } else if y >= h {
                x = w - 1 - x;
                y = 2 * h - 1 - y;
            }
            // Far outside (footprints wider than the image) fall back to clamping.
            Some((x.clamp(0, w - 1), y.clamp(0, h - 1)))
        }
    }
}

/// Size of the EWA weight table.
const EWA_LUT_SIZE: usize = 128;

/// pbrt-v4's EWA weights: `exp(-alpha r^2) - exp(-alpha)` for `r^2 = i / (N - 1)`,
/// `alpha = 2`.
fn ewa_weight(index: usize) -> f32 {
    const ALPHA: f32 = 2.0;
    let r2 = index as f32 / (EWA_LUT_SIZE - 1) as f32;
    (-ALPHA * r2).exp() - (-ALPHA).exp()
}

/// An image pyramid, finest level first.
///
/// Its `Debug` form names the size, the wrap mode and a 64-bit fingerprint of the texels,
/// never the texels themselves: scene descriptions are compared by their `Debug` text, and
/// printing 16 million texels for that took 18 s and gigabytes (issue 10).
#[derive(Clone, PartialEq)]
pub struct MipMap {
    levels: Vec<MipLevel>,
    wrap: WrapMode,
    ewa_lut: Vec<f32>,
    fingerprint: u64,
}

impl std::fmt::Debug for MipMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let base = &self.levels[0];
        f.debug_struct("MipMap")
            .field("size", &format_args!("{}x{}", base.width, base.height))
            .field("levels", &self.levels.len())
            .field("wrap", &self.wrap)
            .field("fingerprint", &format_args!("{:016x}", self.fingerprint))
            .finish()
    }
}

/// FNV-1a over the bits of every channel of `pixels` and the size: equal images have equal
/// fingerprints; different ones collide with probability about 2^-64.
fn fingerprint(width: usize, height: usize, pixels: &[Rgb]) -> u64 {
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |v: u64| h = (h ^ v).wrapping_mul(PRIME);
    eat(width as u64);
    eat(height as u64);
    for p in pixels {
        eat(u64::from(p.r.to_bits()) | (u64::from(p.g.to_bits()) << 32));
        eat(u64::from(p.b.to_bits()));
    }
    h
}

impl MipMap {
    /// The pyramid of a `width` x `height` linear RGB image (row 0 at the top).
    ///
    /// # Panics
    /// When the size is zero or does not match the pixel count.
    #[must_use]
    pub fn new(width: u32, height: u32, pixels: &[Rgb], wrap: WrapMode) -> Self {
        let (w, h) = (width as usize, height as usize);
        assert!(w > 0 && h > 0 && pixels.len() == w * h, "bad image size");
        let fingerprint = fingerprint(w, h, pixels);
        let base = MipLevel {
            width: w,
            height: h,
            texels: pixels.to_vec(),
        };
        let base = resample_to_power_of_two(base);
        let mut levels = vec![base];
        loop {
            let last = levels.last().expect("non-empty");
            if last.width == 1 && last.height == 1 {
                break;
            }
            let next = halve(last);
            levels.push(next);
        }
        Self {
            levels,
            wrap,
            ewa_lut: (0..EWA_LUT_SIZE).map(ewa_weight).collect(),
            fingerprint,
        }
    }

    /// The levels, finest first.
    #[must_use]
    pub fn levels(&self) -> &[MipLevel] {
        &self.levels
    }

    /// The wrap mode.
    #[must_use]
    pub fn wrap(&self) -> WrapMode {
        self.wrap
    }

    /// The texel `(x, y)` of `level`.
    fn texel(&self, level: usize, x: i64, y: i64) -> Rgb {
        self.levels[level].texel(x, y, self.wrap)
    }

    /// Bilinear lookup on `level`.
    #[must_use]
    pub fn bilerp(&self, level: usize, st: Vec2) -> Rgb {
        self.levels[level].bilerp(st, self.wrap)
    }

    /// The filtered value at `st` for a footprint spanned by the screen-space derivatives
    /// `dst0 = (ds/dx, dt/dx)` and `dst1 = (ds/dy, dt/dy)` (pbrt-v4 `MIPMap::Filter`).
    #[must_use]
    pub fn filter(&self, options: &MipFilterOptions, st: Vec2, mut dst0: Vec2, mut dst1: Vec2) -> Rgb {
        let n_levels = self.levels.len();
        if options.filter != MipFilter::Ewa {
            // The level whose texel spacing matches the footprint's largest extent.
            let width = 2.0 * dst0.abs().max_element().max(dst1.abs().max_element());
            let level = (n_levels - 1) as f32 + width.max(1e-8).log2();
            if level >= (n_levels - 1) as f32 {
                return self.texel(n_levels - 1, 0, 0);
            }
            let i_level = level.floor().max(0.0) as usize;
            return match options.filter {
                MipFilter::Point => {
                    let l = &self.levels[i_level];
                    let x = (st.x * l.width as f32 - 0.5).round() as i64;
                    let y = (st.y * l.height as f32 - 0.5).round() as i64;
                    self.texel(i_level, x, y)
                }
                MipFilter::Bilinear => self.bilerp(i_level, st),
                _ if i_level == 0 => self.bilerp(0, st),
                _ => {
                    let delta = level - i_level as f32;
                    self.bilerp(i_level, st) * (1.0 - delta) + self.bilerp(i_level + 1, st) * delta
                }
            };
        }
        // EWA: the longer axis first; clamp the eccentricity to max_anisotropy by widening
        // the shorter axis.
        if dst0.length_squared() < dst1.length_squared() {
            std::mem::swap(&mut dst0, &mut dst1);
        }
        let longer = dst0.length();
        let mut shorter = dst1.length();
        if shorter * options.max_anisotropy < longer && shorter > 0.0 {
            let scale = longer / (shorter * options.max_anisotropy);
            dst1 *= scale;
            shorter *= scale;
        }
        if shorter == 0.0 {
            return self.bilerp(0, st);
        }
        // The level where the shorter axis spans about one texel, blended with the next.
        let lod = ((n_levels - 1) as f32 + shorter.log2()).max(0.0);
        let ilod = lod.floor() as usize;
        let delta = lod - ilod as f32;
        self.ewa(ilod, st, dst0, dst1) * (1.0 - delta) + self.ewa(ilod + 1, st, dst0, dst1) * delta
    }

    /// EWA on one level: Gaussian-weighted average over the ellipse
    /// `A s^2 + B s t + C t^2 < 1` (pbrt-v4 section 10.4.4).
    fn ewa(&self, level: usize, st: Vec2, dst0: Vec2, dst1: Vec2) -> Rgb {
        if level >= self.levels.len() {
            return self.texel(self.levels.len() - 1, 0, 0);
        }
        let l = &self.levels[level];
        let res = Vec2::new(l.width as f32, l.height as f32);
        let st = st * res - 0.5;
        let (d0, d1) = (dst0 * res, dst1 * res);
        // Implicit ellipse coefficients, with one texel of extra width against aliasing.
        let mut a = d0.y * d0.y + d1.y * d1.y + 1.0;
        let mut b = -2.0 * (d0.x * d0.y + d1.x * d1.y);
        let mut c = d0.x * d0.x + d1.x * d1.x + 1.0;
        let inv_f = 1.0 / (a * c - b * b * 0.25);
        a *= inv_f;
        b *= inv_f;
        c *= inv_f;
        // Bounding box of the ellipse.
        let det = -b * b + 4.0 * a * c;
        let inv_det = 1.0 / det;
        let u_sqrt = (det * c).max(0.0).sqrt();
        let v_sqrt = (a * det).max(0.0).sqrt();
        let s0 = (st.x - 2.0 * inv_det * u_sqrt).ceil() as i64;
        let s1 = (st.x + 2.0 * inv_det * u_sqrt).floor() as i64;
        let t0 = (st.y - 2.0 * inv_det * v_sqrt).ceil() as i64;
        let t1 = (st.y + 2.0 * inv_det * v_sqrt).floor() as i64;
        let mut sum = Rgb::BLACK;
        let mut sum_w = 0.0f32;
        for it in t0..=t1 {
            let tt = it as f32 - st.y;
            for is in s0..=s1 {
                let ss = is as f32 - st.x;
                let r2 = a * ss * ss + b * ss * tt + c * tt * tt;
                if r2 < 1.0 {
                    let index = ((r2 * EWA_LUT_SIZE as f32) as usize).min(EWA_LUT_SIZE - 1);
                    let w = self.ewa_lut[index];
                    sum += self.texel(level, is, it) * w;
                    sum_w += w;
                }
            }
        }
        if sum_w > 0.0 {
            sum / sum_w
        } else {
            self.bilerp(level, (st + 0.5) / res)
        }
    }
}

/// The image resampled up to power-of-two sides by area weighting (a no-op for images
/// whose sides are powers of two).
fn resample_to_power_of_two(level: MipLevel) -> MipLevel {
    let (w, h) = (level.width.next_power_of_two(), level.height.next_power_of_two());
    if (w, h) == (level.width, level.height) {
        return level;
    }
    let wx = box_weights(level.width, w);
    let wy = box_weights(level.height, h);
    let mut texels = vec![Rgb::BLACK; w * h];
    for (y, row_w) in wy.iter().enumerate() {
        for (x, col_w) in wx.iter().enumerate() {
            let mut sum = Rgb::BLACK;
            for &(sy, fy) in row_w {
                for &(sx, fx) in col_w {
                    sum += level.texels[sy * level.width + sx] * (fx * fy);
                }
            }
            texels[y * w + x] = sum;
        }
    }
    MipLevel {
        width: w,
        height: h,
        texels,
    }
}

/// For each of `n_new` equal cells over `[0, n_old)`, the old texels it overlaps and the
/// fraction of the cell each covers (the fractions of one cell sum to 1).
fn box_weights(n_old: usize, n_new: usize) -> Vec<Vec<(usize, f32)>> {
    let scale = n_old as f64 / n_new as f64;
    (0..n_new)
        .map(|i| {
            let (lo, hi) = (i as f64 * scale, (i + 1) as f64 * scale);
            let first = lo.floor() as usize;
            let last = (hi.ceil() as usize).min(n_old);
            (first..last)
                .filter_map(|j| {
                    let overlap = hi.min((j + 1) as f64) - lo.max(j as f64);
                    (overlap > 0.0).then(|| (j, (overlap / scale) as f32))
                })
                .collect()
        })
        .collect()
}

/// The next coarser level: the average of each 2x2 block (2x1 or 1x2 when one side has
/// already reached 1).
fn halve(l: &MipLevel) -> MipLevel {
    let (w, h) = ((l.width / 2).max(1), (l.height / 2).max(1));
    let (fx, fy) = (l.width / w, l.height / h);
    let norm = 1.0 / (fx * fy) as f32;
    let mut texels = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let mut sum = Rgb::BLACK;
            for dy in 0..fy {
                for dx in 0..fx {
                    sum += l.texels[(fy * y + dy) * l.width + fx * x + dx];
                }
            }
            texels.push(sum * norm);
        }
    }
    MipLevel {
        width: w,
        height: h,
        texels,
    }
}
