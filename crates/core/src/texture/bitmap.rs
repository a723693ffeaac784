//! Mitsuba's `bitmap` texture: the full-resolution image (no MIP pyramid) looked up at
//! the mapped coordinates with nearest or bilinear interpolation, texel centres at
//! `(i + 0.5) / width`, row 0 at `t = 1` (as [`super::ImageTexture`]), and Mitsuba's
//! wrap modes. Being unfiltered, it shows every detail of the image inside a pixel, so a
//! pixel's expected value is the average of the image over the pixel footprint, as in
//! Mitsuba.

use std::sync::Arc;

use super::{TextureContext, TextureMapping};
use crate::color::Rgb;
use crate::math::Vec2;

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
