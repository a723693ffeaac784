//! Mitsuba's `bitmap` texture: the full-resolution image (no MIP pyramid) looked up at
//! the mapped coordinates with nearest or bilinear interpolation, texel centres at
//! `(i + 0.5) / width`, row 0 at `t = 1` (as [`super::ImageTexture`]), and Mitsuba's
//! wrap modes. Being unfiltered, it shows every detail of the image inside a pixel, so a
//! pixel's expected value is the average of the image over the pixel footprint, as in
//! Mitsuba.

use std::sync::Arc;

use super::{TextureContext, TextureMapping};
use crate::color::Rgb;
use crate::math::{Vec2, Vec3};

/// How coordinates outside `[0, 1)` are brought back (Mitsuba's `wrap_mode`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BitmapWrap {
    /// Tile the image.
    #[default]
    Repeat,
    /// Tile mirrored copies.
    Mirror,
    /// Repeat the edge texels.
    Clamp,
}

/// Lookup of a [`BitmapTexture`] (Mitsuba's `filter_type`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BitmapFilter {
    /// The texel the point falls in.
    Nearest,
    /// Bilinear interpolation of the four nearest texel centres.
    #[default]
    Bilinear,
}

/// An unfiltered image on a surface.
#[derive(Clone, Debug, PartialEq)]
pub struct BitmapTexture {
    /// Coordinates.
    pub mapping: TextureMapping,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width * height` linear RGB texels, row 0 at the top.
    pub texels: Arc<Vec<Rgb>>,
    /// Lookup.
    pub filter: BitmapFilter,
    /// Wrap mode.
    pub wrap: BitmapWrap,
}

impl BitmapTexture {
    /// The value at `ctx`.
    #[must_use]
    pub fn evaluate_rgb(&self, ctx: &TextureContext) -> Rgb {
        let c = self.mapping.map(ctx);
        self.lookup(Vec2::new(c.st.x, 1.0 - c.st.y))
    }

    /// The value at image coordinates `st` (`(0, 0)` the top-left corner, `(1, 1)` the
    /// bottom-right one).
    #[must_use]
    pub fn lookup(&self, st: Vec2) -> Rgb {
        let (w, h) = (self.width as i64, self.height as i64);
        let x = st.x * self.width as f32;
        let y = st.y * self.height as f32;
        match self.filter {
            BitmapFilter::Nearest => self.texel(x.floor() as i64, y.floor() as i64, w, h),
            BitmapFilter::Bilinear => {
                let (x, y) = (x - 0.5, y - 0.5);
                let (xf, yf) = (x.floor(), y.floor());
                let (dx, dy) = (x - xf, y - yf);
                let (xi, yi) = (xf as i64, yf as i64);
                self.texel(xi, yi, w, h) * ((1.0 - dx) * (1.0 - dy))
                    + self.texel(xi + 1, yi, w, h) * (dx * (1.0 - dy))
                    + self.texel(xi, yi + 1, w, h) * ((1.0 - dx) * dy)
                    + self.texel(xi + 1, yi + 1, w, h) * (dx * dy)
            }
        }
    }

    /// The gradient `(df/du, df/dv)` at `ctx` of `f` = the luminance of
    /// [`Self::evaluate_rgb`] (Mitsuba's `eval_1_grad`): the exact derivative of the bilinear
    /// interpolation inside the texel cell, chained through the mapping (whose derivatives
    /// with respect to `u` and `v` come from [`TextureMapping::map`] with a unit
    /// footprint along `u` and `v`, `dp_du` and `dp_dv` the surface's); zero for nearest
    /// lookups, which are piecewise constant.
    #[must_use]
    pub fn luminance_gradient(&self, ctx: &TextureContext, dp_du: Vec3, dp_dv: Vec3) -> Vec2 {
        if self.filter == BitmapFilter::Nearest {
            return Vec2::ZERO;
        }
        let unit = TextureContext {
            dpdx: dp_du,
            dpdy: dp_dv,
            dudx: 1.0,
            dudy: 0.0,
            dvdx: 0.0,
            dvdy: 1.0,
            ..*ctx
        };
        let c = self.mapping.map(&unit);
        let (w, h) = (self.width as i64, self.height as i64);
        let x = c.st.x * self.width as f32 - 0.5;
        let y = (1.0 - c.st.y) * self.height as f32 - 0.5;
        let (xf, yf) = (x.floor(), y.floor());
        let (dx, dy) = (x - xf, y - yf);
        let (xi, yi) = (xf as i64, yf as i64);
        let f = |i: i64, j: i64| self.texel(xi + i, yi + j, w, h).luminance();
        let (f00, f10, f01, f11) = (f(0, 0), f(1, 0), f(0, 1), f(1, 1));
        // Partials of the bilinear patch in texel units.
        let fx = (1.0 - dy) * (f10 - f00) + dy * (f11 - f01);
        let fy = (1.0 - dx) * (f01 - f00) + dx * (f11 - f10);
        // x = s W - 1/2, y = (1 - t) H - 1/2.
        let (fs, ft) = (fx * self.width as f32, -fy * self.height as f32);
        // (c.dsdx, c.dsdy) = (ds/du, ds/dv), likewise for t.
        Vec2::new(fs * c.dsdx + ft * c.dtdx, fs * c.dsdy + ft * c.dtdy)
    }

    fn texel(&self, x: i64, y: i64, w: i64, h: i64) -> Rgb {
        let (x, y) = (wrap(x, w, self.wrap), wrap(y, h, self.wrap));
        self.texels[(y * w + x) as usize]
    }
}

/// Texel index `i` brought into `[0, n)`.
fn wrap(i: i64, n: i64, mode: BitmapWrap) -> i64 {
    match mode {
        BitmapWrap::Repeat => i.rem_euclid(n),
        BitmapWrap::Clamp => i.clamp(0, n - 1),
        BitmapWrap::Mirror => {
            let m = i.rem_euclid(2 * n);
            if m < n {
                m
            } else {
                2 * n - 1 - m
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(filter: BitmapFilter, wrap: BitmapWrap) -> BitmapTexture {
        BitmapTexture {
            mapping: TextureMapping::default(),
            width: 2,
            height: 1,
            texels: Arc::new(vec![Rgb::splat(0.0), Rgb::splat(1.0)]),
            filter,
            wrap,
        }
    }

    #[test]
    fn bilinear_interpolates_between_texel_centres() {
        let t = ramp(BitmapFilter::Bilinear, BitmapWrap::Clamp);
        assert_eq!(t.lookup(Vec2::new(0.25, 0.5)), Rgb::splat(0.0));
        assert_eq!(t.lookup(Vec2::new(0.5, 0.5)), Rgb::splat(0.5));
        assert_eq!(t.lookup(Vec2::new(0.75, 0.5)), Rgb::splat(1.0));
        // Repeat wraps the right edge onto the left texel.
        let r = ramp(BitmapFilter::Bilinear, BitmapWrap::Repeat);
        assert_eq!(r.lookup(Vec2::new(1.0, 0.5)), Rgb::splat(0.5));
    }

    #[test]
    fn the_luminance_gradient_is_the_bilinear_patch_s_derivative() {
        // A 4 x 2 image whose luminance rises by 0.1 per texel along x and 0.3 per row
        // downwards (so falls with t), under a mapping s = 2 u, t = 3 v.
        let texels = (0..8)
            .map(|i| Rgb::splat(0.1 * (i % 4) as f32 + 0.3 * (i / 4) as f32))
            .collect();
        let mut t = BitmapTexture {
            mapping: TextureMapping::Uv {
                su: 2.0,
                sv: 3.0,
                du: 0.0,
                dv: 0.0,
            },
            width: 4,
            height: 2,
            texels: Arc::new(texels),
            filter: BitmapFilter::Bilinear,
            wrap: BitmapWrap::Clamp,
        };
        let ctx = TextureContext {
            uv: Vec2::new(0.2, 0.2),
            ..TextureContext::default()
        };
        let g = t.luminance_gradient(&ctx, Vec3::X, Vec3::Y);
        // df/ds = 0.1 * 4, df/dt = -0.3 * 2; times ds/du = 2, dt/dv = 3.
        assert!((g.x - 0.8).abs() < 1e-4 && (g.y + 1.8).abs() < 1e-4, "{g}");
        // The same by central differences of the lookups.
        let f = |u: f32, v: f32| {
            t.evaluate_rgb(&TextureContext {
                uv: Vec2::new(u, v),
                ..ctx
            })
            .luminance()
        };
        let e = 1e-3;
        let fd = Vec2::new(f(0.2 + e, 0.2) - f(0.2 - e, 0.2), f(0.2, 0.2 + e) - f(0.2, 0.2 - e)) / (2.0 * e);
        assert!((g - fd).length() < 1e-2, "{g} vs {fd}");
        t.filter = BitmapFilter::Nearest;
        assert_eq!(t.luminance_gradient(&ctx, Vec3::X, Vec3::Y), Vec2::ZERO);
    }

    #[test]
    fn nearest_and_the_wrap_modes() {
        let t = ramp(BitmapFilter::Nearest, BitmapWrap::Repeat);
        assert_eq!(t.lookup(Vec2::new(0.4, 0.5)), Rgb::splat(0.0));
        assert_eq!(t.lookup(Vec2::new(1.6, 0.5)), Rgb::splat(1.0));
        let m = ramp(BitmapFilter::Nearest, BitmapWrap::Mirror);
        // Texels -1 and -2 mirror onto 0 and 1.
        assert_eq!(m.lookup(Vec2::new(-0.25, 0.5)), Rgb::splat(0.0));
        assert_eq!(m.lookup(Vec2::new(-0.75, 0.5)), Rgb::splat(1.0));
        let c = ramp(BitmapFilter::Nearest, BitmapWrap::Clamp);
        assert_eq!(c.lookup(Vec2::new(-3.0, 0.5)), Rgb::splat(0.0));
        assert_eq!(c.lookup(Vec2::new(7.0, 0.5)), Rgb::splat(1.0));
    }
}
