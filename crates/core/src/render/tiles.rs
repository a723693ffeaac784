//! Cutting the image into rectangular tiles.

/// A rectangle of pixels `[x0, x1) x [y0, y1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// Left column.
    pub x0: u32,
    /// Top row.
    pub y0: u32,
    /// One past the right column.
    pub x1: u32,
    /// One past the bottom row.
    pub y1: u32,
}

impl Tile {
    /// Number of pixels.
    #[must_use]
    pub fn pixel_count(&self) -> u64 {
        u64::from(self.x1 - self.x0) * u64::from(self.y1 - self.y0)
    }

    /// Image coordinates of the `i`-th pixel in row-major tile order.
    #[must_use]
    pub fn pixel_at(&self, i: usize) -> (u32, u32) {
        let w = (self.x1 - self.x0) as usize;
        (self.x0 + (i % w) as u32, self.y0 + (i / w) as u32)
    }
}

/// Tiles of side `size` covering a `width x height` image, row by row.
#[must_use]
pub fn tiles(width: u32, height: u32, size: u32) -> Vec<Tile> {
    tiles_within(
        Tile {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        },
        size,
    )
}

/// Tiles of side `size` covering the pixels of `window`, row by row from its corner.
#[must_use]
pub fn tiles_within(window: Tile, size: u32) -> Vec<Tile> {
    let size = size.max(1);
    let mut v = Vec::new();
    for y0 in (window.y0..window.y1).step_by(size as usize) {
        for x0 in (window.x0..window.x1).step_by(size as usize) {
            v.push(Tile {
                x0,
                y0,
                x1: x0.saturating_add(size).min(window.x1),
                y1: y0.saturating_add(size).min(window.y1),
            });
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_every_pixel_once() {
        let (w, h) = (37, 21);
        let mut seen = vec![0; w * h];
        for t in tiles(w as u32, h as u32, 8) {
            for i in 0..t.pixel_count() as usize {
                let (x, y) = t.pixel_at(i);
                seen[y as usize * w + x as usize] += 1;
            }
        }
        assert!(seen.iter().all(|&c| c == 1));
    }

    #[test]
    fn tiles_within_cover_the_window_only() {
        let window = Tile {
            x0: 3,
            y0: 5,
            x1: 20,
            y1: 9,
        };
        let covered: u64 = tiles_within(window, 8).iter().map(Tile::pixel_count).sum();
        assert_eq!(covered, 17 * 4);
        for t in tiles_within(window, 8) {
            assert!(t.x0 >= 3 && t.x1 <= 20 && t.y0 >= 5 && t.y1 <= 9 && t.x0 < t.x1 && t.y0 < t.y1);
        }
    }
}
