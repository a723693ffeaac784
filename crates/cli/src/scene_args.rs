//! Arguments shared by every command that renders: the scene, overrides of the file's
//! settings, and the estimator choices of the lab.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use mcrender_core::scene::{
    DirectStrategy, IntegratorKind, Reconstruction, RussianRoulette, SamplerKind, SceneDescription,
};
use mcrender_core::scene::{MAX_PIXELS, MAX_RESOLUTION};
use mcrender_formats::limits::LoadLimits;
use mcrender_formats::pbrt::{load_str, LoadedScene};
use mcrender_formats::{load_with, quoted, LoadOptions};

use crate::builtin;

/// Which integrator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum IntegratorChoice {
    /// Paths of any length.
    Path,
    /// Emission and direct lighting at the first hit only.
    Direct,
    /// Bidirectional path tracing.
    Bdpt,
    /// Light tracing: paths from the lights, connected to the camera.
    Lightpath,
    /// Stochastic progressive photon mapping (the scene's or pbrt's SPPM parameters).
    Sppm,
    /// Metropolis light transport over bidirectional paths (the scene's or pbrt's MLT
    /// parameters).
    Mlt,
}

/// Russian roulette presets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RouletteChoice {
    /// No Russian roulette.
    Off,
    /// pbrt-v4's rule (the default): stop with probability 1 - max(throughput) after the second bounce.
    Throughput,
    /// Mitsuba 3's rule: from the fifth bounce, continue with probability min(max(throughput), 0.95).
    Mitsuba,
}

/// Sampler overrides.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SamplerChoice {
    /// Independent uniform random numbers.
    Independent,
    /// Jittered stratified samples (grid chosen from the sample count).
    Stratified,
    /// Owen-scrambled Sobol' points.
    Sobol,
}

/// How camera samples become pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ReconstructionChoice {
    /// pbrt-v4's filter importance sampling: each sample counts for its own pixel.
    Sample,
    /// Mitsuba 3's splatting: each sample counts for every pixel the filter covers (less
    /// noise per sample with wide filters; path, direct, BDPT and light tracing only).
    Splat,
}

/// The scene and what to override in it.
#[derive(Args, Debug, Default, Clone)]
pub struct SceneArgs {
    /// Scene file (pbrt-v4, or Mitsuba 3 `.xml`); the built-in Cornell box when omitted.
    pub scene: Option<PathBuf>,
    /// `NAME=VALUE`: set a Mitsuba scene's `$NAME` parameter (overrides its `<default>`).
    #[arg(short = 'D', value_parser = parse_define)]
    pub define: Vec<(String, String)>,
    /// Samples per pixel.
    #[arg(long)]
    pub spp: Option<u32>,
    /// Image size as WIDTHxHEIGHT, e.g. 640x480.
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Maximum path depth (0 = emission only, 1 = direct lighting, 2 = one bounce, ...).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Worker threads (default: all cores). The image does not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Random seed.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Sample generator (default: the scene file's).
    #[arg(long, value_enum)]
    pub sampler: Option<SamplerChoice>,
    /// Integrator.
    #[arg(long, value_enum)]
    pub integrator: Option<IntegratorChoice>,
    /// Direct-lighting estimator: uniform-hemisphere, cosine-hemisphere, light-area, bsdf or mis.
    #[arg(long, value_parser = parse_strategy)]
    pub direct: Option<DirectStrategy>,
    /// Direct-lighting samples per path vertex.
    #[arg(long)]
    pub light_samples: Option<u32>,
    /// Russian roulette preset (see --rr-threshold and --rr-prob for the lecture's rule).
    #[arg(long, value_enum, conflicts_with_all = ["rr_threshold", "rr_prob"])]
    pub rr: Option<RouletteChoice>,
    /// Lecture's Russian roulette: play when the throughput's luminance is below this (default 1).
    #[arg(long)]
    pub rr_threshold: Option<f32>,
    /// Lecture's Russian roulette: probability of stopping when played (default 0.5).
    #[arg(long)]
    pub rr_prob: Option<f32>,
    /// Pixel reconstruction: filter sampling (pbrt's way, the default for pbrt scenes) or
    /// splatting (Mitsuba's, its scenes' default with filters other than the box).
    #[arg(long, value_enum)]
    pub reconstruction: Option<ReconstructionChoice>,
    /// Memory the render may use (film, images, meshes, BVH), e.g. 8G or 50%; default 75%
    /// of physical memory. A scene that needs more is refused before anything is allocated.
    #[arg(long, value_parser = crate::preflight::parse_bytes)]
    pub max_memory: Option<u64>,
}

/// Parse `WIDTHxHEIGHT`.
pub fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, found {}", quoted(s)))?;
    let parse = |v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|_| format!("expected WIDTHxHEIGHT with whole numbers, found {}", quoted(s)))
    };
    let (w, h) = (parse(w)?, parse(h)?);
    if w == 0 || h == 0 || w > MAX_RESOLUTION || h > MAX_RESOLUTION || u64::from(w) * u64::from(h) > MAX_PIXELS {
        return Err(format!(
            "{w}x{h}: expected sides between 1 and {MAX_RESOLUTION} and at most {MAX_PIXELS} pixels"
        ));
    }
    Ok((w, h))
}

/// Parse `NAME=VALUE`.
pub fn parse_define(s: &str) -> Result<(String, String), String> {
    match s.split_once('=') {
        Some((n, v)) if !n.is_empty() => Ok((n.to_string(), v.to_string())),
        _ => Err(format!("expected NAME=VALUE, found \"{s}\"")),
    }
}

/// Parse a direct-lighting strategy name.
pub fn parse_strategy(s: &str) -> Result<DirectStrategy, String> {
    DirectStrategy::ALL.into_iter().find(|d| d.name() == s).ok_or_else(|| {
        let names: Vec<_> = DirectStrategy::ALL.iter().map(|d| d.name()).collect();
        format!("expected one of {}, found {}", names.join(", "), quoted(s))
    })
}

impl SceneArgs {
    /// Load the scene (or the built-in one); returns it with a short name for output files.
    pub fn load(&self) -> Result<(LoadedScene, String)> {
        let (loaded, stem) = match &self.scene {
            Some(path) => {
                let options = LoadOptions {
                    defines: self.define.clone(),
                    limits: LoadLimits {
                        max_memory: self.memory_limit(),
                    },
                };
                let loaded = load_with(path, &options).map_err(anyhow::Error::new)?;
                let stem = path
                    .file_stem()
                    .map_or_else(|| "render".to_string(), |s| s.to_string_lossy().into_owned());
                (loaded, stem)
            }
            None => (
                load_str(builtin::SOURCE, builtin::NAME, Path::new(".")).map_err(anyhow::Error::new)?,
                "cornell-box".into(),
            ),
        };
        for w in &loaded.warnings {
            eprintln!("mcrender: {w}");
        }
        Ok((loaded, stem))
    }

    /// The memory limit: `--max-memory`, else the default share of physical memory.
    pub fn memory_limit(&self) -> u64 {
        self.max_memory.unwrap_or_else(crate::preflight::default_max_memory)
    }

    /// Apply the overrides to a description.
    pub fn apply(&self, desc: &mut SceneDescription) -> Result<()> {
        if let Some(spp) = self.spp {
            desc.sampler.samples_per_pixel = spp;
        }
        if let Some((w, h)) = self.resolution {
            desc.film.width = w;
            desc.film.height = h;
        }
        if let Some(d) = self.max_depth {
            desc.integrator.max_depth = d;
        }
        if let Some(s) = self.seed {
            desc.sampler.seed = s;
        }
        if let Some(kind) = self.sampler {
            desc.sampler.kind = match kind {
                SamplerChoice::Independent => SamplerKind::Independent,
                // A grid that does not multiply to the sample count makes the sampler choose
                // the most nearly square one (the same rule as overriding --spp).
                SamplerChoice::Stratified => SamplerKind::Stratified {
                    x_samples: 0,
                    y_samples: 0,
                    jitter: true,
                },
                SamplerChoice::Sobol => SamplerKind::OwenSobol,
            };
        }
        if let Some(i) = self.integrator {
            desc.integrator.kind = match i {
                IntegratorChoice::Path => IntegratorKind::Path,
                IntegratorChoice::Direct => IntegratorKind::Direct,
                IntegratorChoice::Bdpt => IntegratorKind::Bdpt,
                IntegratorChoice::Lightpath => IntegratorKind::LightPath,
                IntegratorChoice::Sppm => IntegratorKind::Sppm,
                IntegratorChoice::Mlt => IntegratorKind::Mlt,
            };
        }
        match self.reconstruction {
            Some(ReconstructionChoice::Sample) => desc.reconstruction = Reconstruction::FilterSampling,
            Some(ReconstructionChoice::Splat) => desc.reconstruction = Reconstruction::FilterSplatting,
            // Integrators with their own driver fill the film themselves: a Mitsuba scene's
            // splatting gives way to them unless asked for (then the scene is refused).
            None if matches!(desc.integrator.kind, IntegratorKind::Sppm | IntegratorKind::Mlt) => {
                desc.reconstruction = Reconstruction::FilterSampling;
            }
            None => {}
        }
        if let Some(d) = self.direct {
            desc.integrator.direct = d;
        }
        if let Some(n) = self.light_samples {
            if n == 0 {
                bail!("--light-samples: expected at least 1, found 0");
            }
            desc.integrator.light_samples = n;
        }
        match (self.rr, self.rr_threshold, self.rr_prob) {
            (Some(RouletteChoice::Off), ..) => desc.integrator.russian_roulette = RussianRoulette::Off,
            (Some(RouletteChoice::Throughput), ..) => desc.integrator.russian_roulette = RussianRoulette::Throughput,
            (Some(RouletteChoice::Mitsuba), ..) => {
                desc.integrator.russian_roulette = RussianRoulette::Delayed { start_depth: 5 };
            }
            (None, None, None) => {}
            (None, t, q) => {
                let (threshold, probability) = (t.unwrap_or(1.0), q.unwrap_or(0.5));
                if !(threshold.is_finite() && threshold >= 0.0) {
                    bail!("--rr-threshold: expected a non-negative number, found {threshold}");
                }
                if !(0.0..1.0).contains(&probability) {
                    bail!("--rr-prob: expected a probability in [0, 1), found {probability}");
                }
                desc.integrator.russian_roulette = RussianRoulette::Threshold { threshold, probability };
            }
        }
        Ok(())
    }
}
