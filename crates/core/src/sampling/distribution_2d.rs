//! Piecewise-constant 2-D distributions over a rectangle (environment maps, tabulated
//! filters): a marginal distribution over rows and one conditional distribution per row.

use super::PiecewiseConstant1D;
use crate::math::{UVec2, Vec2};

/// A piecewise-constant density over the rectangle [`min`, `max`] proportional to a
/// `resolution.x` x `resolution.y` table, sampled by first choosing a row (y) from the
/// marginal distribution, then a column (x) from that row's conditional distribution.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseConstant2D {
    /// One distribution over x per row.
    conditional: Vec<PiecewiseConstant1D>,
    /// Distribution over y of the rows' integrals.
    marginal: PiecewiseConstant1D,
    min: Vec2,
    max: Vec2,
}

impl PiecewiseConstant2D {
    /// The distribution of `values` (row-major, `resolution.x` values per row, row 0 at
    /// `min.y`) on equal cells of [`min`, `max`]. All-zero values sample uniformly.
    ///
    /// # Panics
    /// If `values.len()` is not `resolution.x * resolution.y`, or on the conditions of
    /// [`PiecewiseConstant1D::new`].
    #[must_use]
    pub fn new(values: &[f32], resolution: UVec2, min: Vec2, max: Vec2) -> Self {
        let (nx, ny) = (resolution.x as usize, resolution.y as usize);
        assert_eq!(values.len(), nx * ny, "need resolution.x * resolution.y values");
        let conditional: Vec<_> = values
            .chunks_exact(nx)
            .map(|row| PiecewiseConstant1D::new(row, min.x, max.x))
            .collect();
        let row_integrals: Vec<f32> = conditional.iter().map(PiecewiseConstant1D::integral).collect();
        let marginal = PiecewiseConstant1D::new(&row_integrals, min.y, max.y);
        Self {
            conditional,
            marginal,
            min,
            max,
        }
    }

    /// Integral of the tabulated function over the rectangle.
    #[inline]
    #[must_use]
    pub fn integral(&self) -> f32 {
        self.marginal.integral()
    }

    /// The domain `(min, max)`.
    #[inline]
    #[must_use]
    pub fn domain(&self) -> (Vec2, Vec2) {
        (self.min, self.max)
    }

    /// A sample `(p, pdf, cell)` for `u` in [0, 1)^2: a point of the rectangle, its density
    /// per unit area and its cell (column, row). `u.y` picks the row, `u.x` the column.
    #[inline]
    #[must_use]
    pub fn sample(&self, u: Vec2) -> (Vec2, f32, UVec2) {
        let (y, pdf_y, row) = self.marginal.sample(u.y);
        let (x, pdf_x, col) = self.conditional[row].sample(u.x);
        (Vec2::new(x, y), pdf_x * pdf_y, UVec2::new(col as u32, row as u32))
    }

    /// The density of [`sample`](Self::sample) at `p` (0 outside the rectangle).
    #[inline]
    #[must_use]
    pub fn pdf(&self, p: Vec2) -> f32 {
        let pdf_y = self.marginal.pdf(p.y);
        if pdf_y == 0.0 {
            return 0.0;
        }
        pdf_y * self.conditional[self.row_of(p.y)].pdf(p.x)
    }

    /// The `u` for which [`sample`](Self::sample) returns `p` (clamped to the rectangle).
    #[inline]
    #[must_use]
    pub fn invert(&self, p: Vec2) -> Vec2 {
        let p = p.clamp(self.min, self.max);
        Vec2::new(
            self.conditional[self.row_of(p.y)].invert(p.x),
            self.marginal.invert(p.y),
        )
    }

    /// The row holding `y` in [min.y, max.y].
    #[inline]
    fn row_of(&self, y: f32) -> usize {
        let n = self.conditional.len();
        (((y - self.min.y) / (self.max.y - self.min.y) * n as f32) as usize).min(n - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::{suite_seed, Chi2Test, RectGrid, SIGNIFICANCE};
    use crate::sampling::Pcg32;

    /// 4 x 3 values with an empty row and empty cells.
    const VALUES: [f32; 12] = [1.0, 0.0, 3.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.5, 4.0, 1.0, 0.25];

    fn distribution() -> PiecewiseConstant2D {
        PiecewiseConstant2D::new(&VALUES, UVec2::new(4, 3), Vec2::new(-1.0, 0.0), Vec2::new(1.0, 3.0))
    }

    #[test]
    fn integral_pdf_and_inverse() {
        let d = distribution();
        // Cells are 0.5 x 1.
        assert!((d.integral() - 11.75 * 0.5).abs() < 1e-5);
        assert!((d.pdf(Vec2::new(-0.25, 2.5)) - 4.0 / 5.875).abs() < 1e-6);
        assert_eq!(d.pdf(Vec2::new(0.0, 1.5)), 0.0);
        assert_eq!(d.pdf(Vec2::new(0.0, 3.5)), 0.0);
        let mut rng = Pcg32::new(5, 5);
        for _ in 0..10_000 {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let (p, pdf, cell) = d.sample(u);
            assert!(VALUES[(cell.y * 4 + cell.x) as usize] > 0.0);
            assert!((pdf - d.pdf(p)).abs() <= 1e-6 * pdf, "{u} -> {p}");
            let v = d.invert(p);
            assert!((v - u).abs().max_element() < 1e-5, "{u} -> {p} -> {v}");
        }
    }

    #[test]
    fn chi2_piecewise_constant_2d() {
        let d = distribution();
        let grid = RectGrid {
            min: Vec2::new(-1.0, 0.0),
            max: Vec2::new(1.0, 3.0),
            bins: UVec2::new(10, 9),
        };
        let report = Chi2Test::new(1_000_000, suite_seed()).rect(grid, |u, _| Some(d.sample(u).0), |p| d.pdf(p));
        report.assert_passes(SIGNIFICANCE);
        assert!(
            (report.pdf_integral - 1.0).abs() < 1e-5,
            "pdf integral {}",
            report.pdf_integral
        );
    }
}
