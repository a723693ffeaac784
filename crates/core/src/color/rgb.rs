//! `Rgb`: a linear-sRGB triple used for radiance, reflectance and throughput.

use std::ops::{Add, AddAssign, Div, DivAssign, Index, Mul, MulAssign, Sub};

/// Linear RGB (sRGB primaries). Radiometric, not display-encoded.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rgb {
    /// Red.
    pub r: f32,
    /// Green.
    pub g: f32,
    /// Blue.
    pub b: f32,
}

impl Rgb {
    /// Black.
    pub const BLACK: Self = Self::splat(0.0);
    /// White (1, 1, 1).
    pub const WHITE: Self = Self::splat(1.0);

    /// From components.
    #[inline]
    #[must_use]
    pub const fn new(r: f32, g: f32, b: f32) -> Self {
        Self { r, g, b }
    }

    /// All three components equal to `v`.
    #[inline]
    #[must_use]
    pub const fn splat(v: f32) -> Self {
        Self { r: v, g: v, b: v }
    }

    /// Luminance Y of linear sRGB (Rec. 709 weights).
    #[inline]
    #[must_use]
    pub fn luminance(self) -> f32 {
        0.212_671 * self.r + 0.715_160 * self.g + 0.072_169 * self.b
    }

    /// Largest component.
    #[inline]
    #[must_use]
    pub fn max_component(self) -> f32 {
        self.r.max(self.g).max(self.b)
    }

    /// Mean of the components.
    #[inline]
    #[must_use]
    pub fn average(self) -> f32 {
        (self.r + self.g + self.b) / 3.0
    }

    /// True when all components are zero.
    #[inline]
    #[must_use]
    pub fn is_black(self) -> bool {
        self.r == 0.0 && self.g == 0.0 && self.b == 0.0
    }

    /// True when no component is NaN or infinite.
    #[inline]
    #[must_use]
    pub fn is_finite(self) -> bool {
        self.r.is_finite() && self.g.is_finite() && self.b.is_finite()
    }

    /// Component-wise map.
    #[inline]
    #[must_use]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Self::new(f(self.r), f(self.g), f(self.b))
    }

    /// Components as an array.
    #[inline]
    #[must_use]
    pub fn to_array(self) -> [f32; 3] {
        [self.r, self.g, self.b]
    }
}

impl From<[f32; 3]> for Rgb {
    fn from(a: [f32; 3]) -> Self {
        Self::new(a[0], a[1], a[2])
    }
}

impl Index<usize> for Rgb {
    type Output = f32;
    fn index(&self, i: usize) -> &f32 {
        match i {
            0 => &self.r,
            1 => &self.g,
            _ => &self.b,
        }
    }
}

impl Add for Rgb {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self::new(self.r + o.r, self.g + o.g, self.b + o.b)
    }
}

impl AddAssign for Rgb {
    #[inline]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl Sub for Rgb {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self::new(self.r - o.r, self.g - o.g, self.b - o.b)
    }
}

impl Mul for Rgb {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        Self::new(self.r * o.r, self.g * o.g, self.b * o.b)
    }
}

impl MulAssign for Rgb {
    #[inline]
    fn mul_assign(&mut self, o: Self) {
        *self = *self * o;
    }
}

impl Mul<f32> for Rgb {
    type Output = Self;
    #[inline]
    fn mul(self, s: f32) -> Self {
        Self::new(self.r * s, self.g * s, self.b * s)
    }
}

impl Mul<Rgb> for f32 {
    type Output = Rgb;
    #[inline]
    fn mul(self, c: Rgb) -> Rgb {
        c * self
    }
}

impl MulAssign<f32> for Rgb {
    #[inline]
    fn mul_assign(&mut self, s: f32) {
        *self = *self * s;
    }
}

impl Div<f32> for Rgb {
    type Output = Self;
    #[inline]
    fn div(self, s: f32) -> Self {
        Self::new(self.r / s, self.g / s, self.b / s)
    }
}

impl DivAssign<f32> for Rgb {
    #[inline]
    fn div_assign(&mut self, s: f32) {
        *self = *self / s;
    }
}
