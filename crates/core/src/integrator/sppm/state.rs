//! What SPPM carries from one iteration to the next ([`SppmState`]): per pixel the sum of
//! direct lighting `Ld`, the flux `tau`, the search radius and the photon count `N`, and
//! the number of iterations done. It is all a render needs to continue, so it is what a
//! checkpoint saves: [`SppmState::to_bytes`] and [`SppmState::from_bytes`] round-trip it
//! exactly (raw IEEE bits), and a render continued from it is bit-identical to one never
//! stopped.

use crate::color::Rgb;
use crate::film::Film;
use crate::math::PI;

use super::SppmSettings;

/// One pixel's statistics across iterations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct PixelState {
    /// Sum over iterations of emission and direct lighting.
    pub ld: Rgb,
    /// Accumulated flux, scaled as the radius shrinks.
    pub tau: Rgb,
    /// Search radius.
    pub radius: f32,
    /// Accumulated photon count.
    pub n: f32,
}

/// Bytes per pixel in [`SppmState::to_bytes`]: `ld`, `tau` (3 f32 each), radius, `N`.
const PIXEL_BYTES: usize = 8 * 4;
/// Bytes before the pixels: magic, width, height, iterations done.
const HEAD_BYTES: usize = 8 + 3 * 4;
/// First bytes of the serialised state (`v1`: the layout of this module's documentation).
const MAGIC: &[u8; 8] = b"SPPMst1\n";

/// The per-pixel statistics of an SPPM render and its iterations done.
#[derive(Clone, Debug, PartialEq)]
pub struct SppmState {
    width: u32,
    height: u32,
    pub(super) pixels: Vec<PixelState>,
    pub(super) iterations_done: u32,
}

impl SppmState {
    /// The state before the first iteration: every radius the initial one, nothing found.
    #[must_use]
    pub fn new(width: u32, height: u32, settings: &SppmSettings) -> Self {
        let pixel = PixelState {
            ld: Rgb::BLACK,
            tau: Rgb::BLACK,
            radius: settings.initial_radius,
            n: 0.0,
        };
        Self {
            width,
            height,
            pixels: vec![pixel; width as usize * height as usize],
            iterations_done: 0,
        }
    }

    /// Iterations completed so far.
    #[must_use]
    pub fn iterations_done(&self) -> u32 {
        self.iterations_done
    }

    /// Film width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Film height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The image of the iterations done: `Ld / iterations + tau / (N_photons pi r^2)` per
    /// pixel (Hachisuka and Jensen 2009, eq. 13), one sample per pixel (no variance).
    #[must_use]
    pub fn film(&self, settings: &SppmSettings) -> Film {
        let mut film = Film::new(self.width, self.height);
        let done = self.iterations_done;
        let n_photons = f64::from(done) * settings.photons_per_iteration as f64;
        for (i, s) in self.pixels.iter().enumerate() {
            let mut l = s.ld / done.max(1) as f32;
            if n_photons > 0.0 {
                let area = f64::from(PI) * f64::from(s.radius) * f64::from(s.radius);
                l += s.tau * (1.0 / (n_photons * area)) as f32;
            }
            let (x, y) = (i as u32 % self.width, i as u32 / self.width);
            film.pixel_mut(x, y)
                .add(if l.is_finite() { l } else { Rgb::BLACK }, 1.0);
        }
        film
    }

    /// The state as bytes: `"SPPMst1\n"`, width, height, iterations done (u32), then per
    /// pixel in row-major order `ld.rgb`, `tau.rgb`, radius, `N` (f32), all little endian.
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(HEAD_BYTES + PIXEL_BYTES * self.pixels.len());
        out.extend_from_slice(MAGIC);
        for v in [self.width, self.height, self.iterations_done] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        for p in &self.pixels {
            let v = [p.ld.r, p.ld.g, p.ld.b, p.tau.r, p.tau.g, p.tau.b, p.radius, p.n];
            for x in v {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        out
    }

    /// Read what [`Self::to_bytes`] wrote, for a film of `width` x `height`.
    ///
    /// # Errors
    /// A short description when the bytes are not such a state or are of another size.
    pub fn from_bytes(bytes: &[u8], width: u32, height: u32) -> Result<Self, String> {
        if bytes.len() < HEAD_BYTES || &bytes[..8] != MAGIC {
            return Err("not an SPPM state".into());
        }
        let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
        let (w, h, iterations_done) = (word(8), word(12), word(16));
        if (w, h) != (width, height) {
            return Err(format!("SPPM state of {w}x{h} pixels for a {width}x{height} film"));
        }
        let n = width as usize * height as usize;
        if n.checked_mul(PIXEL_BYTES).and_then(|b| b.checked_add(HEAD_BYTES)) != Some(bytes.len()) {
            return Err("SPPM state of the wrong size".into());
        }
        let float = |i: usize| f32::from_bits(word(HEAD_BYTES + 4 * i));
        let pixels = (0..n)
            .map(|p| {
                let b = 8 * p;
                PixelState {
                    ld: Rgb::new(float(b), float(b + 1), float(b + 2)),
                    tau: Rgb::new(float(b + 3), float(b + 4), float(b + 5)),
                    radius: float(b + 6),
                    n: float(b + 7),
                }
            })
            .collect();
        Ok(Self {
            width,
            height,
            pixels,
            iterations_done,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings() -> SppmSettings {
        SppmSettings {
            iterations: 4,
            photons_per_iteration: 10,
            initial_radius: 0.25,
            seed: 1,
            max_depth: 5,
        }
    }

    #[test]
    fn bytes_round_trip_exactly_and_bad_bytes_are_refused() {
        let mut s = SppmState::new(3, 2, &settings());
        s.pixels[4] = PixelState {
            ld: Rgb::new(0.1, 1e-30, f32::MAX),
            tau: Rgb::new(3.0, 0.0, -0.0),
            radius: 0.125,
            n: 17.5,
        };
        s.iterations_done = 3;
        let bytes = s.to_bytes();
        assert_eq!(bytes.len(), HEAD_BYTES + 6 * PIXEL_BYTES);
        let back = SppmState::from_bytes(&bytes, 3, 2).unwrap();
        assert_eq!(back.to_bytes(), bytes);
        assert_eq!(back.film(&settings()), s.film(&settings()));
        assert!(SppmState::from_bytes(&bytes, 2, 3).unwrap_err().contains("3x2"));
        assert!(SppmState::from_bytes(&bytes[..bytes.len() - 1], 3, 2).is_err());
        assert!(SppmState::from_bytes(b"SPPMst1", 3, 2).is_err());
        let mut other = bytes.clone();
        other[0] = b'x';
        assert!(SppmState::from_bytes(&other, 3, 2).is_err());
    }
}
