//! What MLT carries from one work unit to the next ([`MltState`]), and so what a checkpoint
//! saves: the bootstrap's result, every chain, and the film's splat sums.
//!
//! The bootstrap's result is the normalisation `b` and, for every chain not yet started,
//! the bootstrap state it starts from: chain starts are drawn once, when the bootstrap
//! ends, so the bootstrap's luminances (`bootstrapsamples x (maxdepth + 1)` of them, 6.6
//! million for pbrt's defaults at depth 65) are neither stored nor recomputed on resume.
//! A started chain is saved whole ([`super::chain::Chain`]: its primary sample space
//! vector with each dimension's last change, iteration counters, generators, current path
//! and luminance), a finished one as a mark. The splat sums are fixed point
//! ([`SplatSum`]), so they continue exactly.
//!
//! [`MltState::to_bytes`] and [`MltState::from_bytes`] round-trip it exactly: a render
//! continued from it is bit-identical to one never stopped.

use crate::bytes::{ByteReader, ByteWriter};
use crate::film::{Film, PixelStats, SplatSum};

use super::chain::Chain;
use super::MltSettings;

/// First bytes of the serialised state (`v1`: the layout of [`MltState::to_bytes`]).
const MAGIC: &[u8; 8] = b"MLTstv1\n";

/// Where one chain is.
#[derive(Clone, Debug)]
pub(super) enum ChainSlot {
    /// Not started; starts from this bootstrap state.
    Pending(u64),
    /// Started, with mutations left.
    Running(Box<Chain>),
    /// All its mutations made.
    Done,
}

/// An MLT render between two work units.
#[derive(Clone, Debug)]
pub struct MltState {
    /// Splat sums of every mutation made, each splat scaled by `b`; no samples counted.
    pub(super) film: Film,
    /// Whether the bootstrap is done (`b` and the chains' starts are known).
    pub(super) bootstrapped: bool,
    /// The normalisation: the estimated integral of the luminance over all paths.
    pub(super) b: f64,
    /// Every chain, in index order (none before the bootstrap).
    pub(super) chains: Vec<ChainSlot>,
    /// Mutations made, over all chains.
    pub(super) mutations: u64,
    /// Proposals accepted, over all chains.
    pub(super) accepted: u64,
}

impl MltState {
    /// The state of a render not yet started (its bootstrap to do).
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            film: Film::new(width, height),
            bootstrapped: false,
            b: 0.0,
            chains: Vec::new(),
            mutations: 0,
            accepted: 0,
        }
    }

    /// Whether the bootstrap is done.
    #[must_use]
    pub fn is_bootstrapped(&self) -> bool {
        self.bootstrapped
    }

    /// Whether every chain made all its mutations.
    #[must_use]
    pub fn is_finished(&self) -> bool {
        self.bootstrapped && self.chains.iter().all(|c| matches!(c, ChainSlot::Done))
    }

    /// The normalisation `b` (0 before the bootstrap).
    #[must_use]
    pub fn b(&self) -> f64 {
        self.b
    }

    /// Mutations made so far.
    #[must_use]
    pub fn mutations(&self) -> u64 {
        self.mutations
    }

    /// Proposals accepted so far.
    #[must_use]
    pub fn accepted(&self) -> u64 {
        self.accepted
    }

    /// The image so far: the splat sums over `mutationsperpixel` samples per pixel when
    /// finished, else over the share of them made (rounded up; 0 before any).
    #[must_use]
    pub fn film(&self, settings: &MltSettings) -> Film {
        let mut film = self.film.clone();
        let mpp = u64::from(settings.mutations_per_pixel);
        let spp = if self.is_finished() {
            mpp
        } else {
            let total = total_mutations(settings, film.width(), film.height());
            (u128::from(mpp) * u128::from(self.mutations)).div_ceil(u128::from(total.max(1))) as u64
        };
        film.add_samples_per_pixel(spp);
        film
    }

    /// The state as bytes, little endian: `"MLTstv1\n"`, width, height (u32), bootstrapped
    /// (u8), `b` (f64), mutations, accepted (u64), the number of chains (u32), then per
    /// chain a tag (u8: 0 not started, followed by its bootstrap state as u64; 1 running,
    /// followed by [`Chain::write`]'s bytes; 2 finished), then per pixel in row-major order
    /// the three splat sums (i128, fixed point in units of 2^-64).
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut w = ByteWriter::new();
        w.bytes(MAGIC);
        w.u32(self.film.width());
        w.u32(self.film.height());
        w.u8(u8::from(self.bootstrapped));
        w.f64(self.b);
        w.u64(self.mutations);
        w.u64(self.accepted);
        w.u32(self.chains.len() as u32);
        for c in &self.chains {
            match c {
                ChainSlot::Pending(start) => {
                    w.u8(0);
                    w.u64(*start);
                }
                ChainSlot::Running(chain) => {
                    w.u8(1);
                    chain.write(&mut w);
                }
                ChainSlot::Done => w.u8(2),
            }
        }
        for s in self.film.splat_sums() {
            for v in s.to_fixed() {
                w.i128(v);
            }
        }
        w.into_bytes()
    }

    /// Read what [`Self::to_bytes`] wrote, for a `width` x `height` render with `settings`.
    ///
    /// # Errors
    /// A short description when the bytes are not such a state, or one of another size or
    /// other settings.
    pub fn from_bytes(bytes: &[u8], width: u32, height: u32, settings: &MltSettings) -> Result<Self, String> {
        let mut r = ByteReader::new(bytes);
        if r.take(MAGIC.len()).ok() != Some(&MAGIC[..]) {
            return Err("not an MLT state".into());
        }
        let (w, h) = (r.u32()?, r.u32()?);
        if (w, h) != (width, height) {
            return Err(format!("MLT state of {w}x{h} pixels for a {width}x{height} film"));
        }
        let bootstrapped = match r.u8()? {
            0 => false,
            1 => true,
            v => return Err(format!("a bootstrap flag of {v}")),
        };
        let (b, mutations, accepted) = (r.f64()?, r.u64()?, r.u64()?);
        let n = r.u32()?;
        let expected = if bootstrapped { settings.chains } else { 0 };
        if n != expected {
            return Err(format!("MLT state of {n} chains, {expected} expected"));
        }
        let total = total_mutations(settings, width, height);
        let n_bootstrap = u64::from(settings.bootstrap_samples) * (u64::from(settings.max_depth) + 1);
        let mut chains = Vec::with_capacity(n.min(1 << 20) as usize);
        let mut made = 0u64;
        for c in 0..u64::from(n) {
            let quota = chain_mutations(c, u64::from(n), total);
            chains.push(match r.u8()? {
                0 => {
                    let start = r.u64()?;
                    if start >= n_bootstrap {
                        return Err(format!("chain {c} starts at bootstrap state {start} of {n_bootstrap}"));
                    }
                    ChainSlot::Pending(start)
                }
                1 => {
                    let chain = Chain::read(&mut r, settings, n_bootstrap).map_err(|e| format!("chain {c}: {e}"))?;
                    if chain.done >= quota {
                        return Err(format!(
                            "chain {c} running after {} of its {quota} mutations",
                            chain.done
                        ));
                    }
                    made += chain.done;
                    ChainSlot::Running(Box::new(chain))
                }
                2 => {
                    made += quota;
                    ChainSlot::Done
                }
                v => return Err(format!("chain {c} has tag {v}")),
            });
        }
        // A render whose bootstrap found no light finishes with no mutation made.
        if mutations != made && !(mutations == 0 && b == 0.0) {
            return Err(format!("MLT state of {mutations} mutations whose chains made {made}"));
        }
        let pixels = width as usize * height as usize;
        if r.remaining() != pixels * 48 {
            return Err("MLT state of the wrong size".into());
        }
        let mut splats = Vec::with_capacity(pixels);
        for _ in 0..pixels {
            splats.push(SplatSum::from_fixed([r.i128()?, r.i128()?, r.i128()?]));
        }
        r.finish()?;
        let film = Film::from_parts(width, height, vec![PixelStats::default(); pixels], splats, 0)
            .ok_or("MLT state of the wrong size")?;
        Ok(Self {
            film,
            bootstrapped,
            b,
            chains,
            mutations,
            accepted,
        })
    }
}

/// All the mutations of a render: `mutationsperpixel` per pixel.
pub(super) fn total_mutations(settings: &MltSettings, width: u32, height: u32) -> u64 {
    u64::from(settings.mutations_per_pixel) * u64::from(width) * u64::from(height)
}

/// Chain `c`'s share of `total` mutations over `chains` chains (the shares differ by at
/// most one and add up to `total`).
pub(super) fn chain_mutations(c: u64, chains: u64, total: u64) -> u64 {
    let at = |c: u64| (u128::from(c) * u128::from(total) / u128::from(chains.max(1))) as u64;
    at(c + 1) - at(c)
}
