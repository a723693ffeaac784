//! What a loader says about the sampler: [`SamplerDesc`], consumed by [`super::Sampler`].

/// Which sample generator to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerKind {
    /// Independent uniform random numbers from a PCG stream.
    Independent,
    /// Stratified samples (pbrt `stratified`): every dimension falls in its own stratum of
    /// an `x_samples` x `y_samples` grid (2-D) or of `x_samples * y_samples` intervals (1-D),
    /// the strata shuffled independently per dimension; jittered inside the stratum, or at
    /// its centre without `jitter`.
    Stratified {
        /// Strata along x of each 2-D dimension pair.
        x_samples: u32,
        /// Strata along y of each 2-D dimension pair.
        y_samples: u32,
        /// Random position inside the stratum (else its centre).
        jitter: bool,
    },
    /// Owen-scrambled Sobol' points (Burley 2020, "Practical Hash-based Owen Scrambling"),
    /// with a per-pixel shuffle of the sequence; used for pbrt's `sobol`, `zsobol`, `halton`,
    /// `pmj02bn` and `paddedsobol`.
    OwenSobol,
}

/// Sampler settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SamplerDesc {
    /// The generator.
    pub kind: SamplerKind,
    /// Samples per pixel.
    pub samples_per_pixel: u32,
    /// Seed; together with pixel and sample index it fixes every random number.
    pub seed: u64,
}

impl Default for SamplerDesc {
    fn default() -> Self {
        Self {
            kind: SamplerKind::Independent,
            samples_per_pixel: 16,
            seed: 0,
        }
    }
}
