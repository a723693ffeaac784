//! Scene-wide options (the directives before `WorldBegin`): `Camera`, `Film`,
//! `PixelFilter`, `Sampler`, `Integrator`, `Accelerator`, plus `Option` and `ColorSpace`.

use glam::Vec2;
use mcrender_core::math::Transform;
use mcrender_core::scene::{
    BdptDesc, CameraDesc, DirectStrategy, FilmDesc, FilterDesc, IntegratorDesc, IntegratorKind, LightSelection,
    MltDesc, Projection, RussianRoulette, SamplerDesc, SamplerKind, SppmDesc,
};

use super::builder::SceneBuilder;
use super::params::ParamSet;
use crate::error::{Location, SceneError};

/// Largest accepted image side, in pixels.
const MAX_RESOLUTION: i32 = 32_768;
/// Largest accepted pixel count.
const MAX_PIXELS: i64 = 1 << 28;

/// What the options block (before `WorldBegin`) sets.
#[derive(Debug, Default)]
pub struct SceneOptions {
    /// `Camera`.
    pub camera: CameraDesc,
    /// `Film`'s resolution.
    pub film: FilmDesc,
    /// `PixelFilter`.
    pub filter: FilterDesc,
    /// `Sampler` (its seed is resolved at the end, see [`Self::sampler_seed`]).
    pub sampler: SamplerDesc,
    /// The `Sampler`'s own `seed` parameter, which wins over [`Self::option_seed`].
    pub sampler_seed: Option<i32>,
    /// `Option "seed"`.
    pub option_seed: Option<i32>,
    /// `Integrator`.
    pub integrator: IntegratorDesc,
    /// `Film`'s `filename`.
    pub output_filename: Option<String>,
}

impl SceneBuilder {
    /// `Camera "perspective" ...` or `Camera "orthographic" ...`: the CTM is
    /// camera-from-world.
    pub fn camera(&mut self, kind: &str, params: &ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_options("Camera", loc)?;
        let projection = match kind {
            "perspective" => Projection::Perspective,
            "orthographic" => Projection::Orthographic,
            "realistic" | "spherical" => {
                return Err(SceneError::unsupported(
                    loc,
                    format!("camera type \"{kind}\" is not supported yet (cameras: perspective, orthographic)"),
                ))
            }
            _ => return Err(SceneError::syntax(loc, format!("unknown camera type \"{kind}\""))),
        };
        let camera_from_world = self.ctm_transform("the camera", loc)?;
        let world_from_camera = camera_from_world.inverse();
        self.set_camera_coordinate_system(world_from_camera.m);

        // The orthographic camera has no field of view (an unread "fov" is reported unused).
        let fov = match projection {
            Projection::Perspective => params.float("fov", 90.0)?,
            Projection::Orthographic => 90.0,
        };
        if !(fov > 0.0 && fov < 180.0) {
            return Err(param_error(params, "fov", "must be between 0 and 180 degrees"));
        }
        let lens_radius = params.float("lensradius", 0.0)?;
        if lens_radius < 0.0 {
            return Err(param_error(params, "lensradius", "must not be negative"));
        }
        let focal_distance = params.float("focaldistance", 1e6)?;
        if focal_distance <= 0.0 {
            return Err(param_error(params, "focaldistance", "must be positive"));
        }
        let mut screen_window = None;
        if let Some(p) = params.floats("screenwindow")? {
            let [x0, x1, y0, y1] = p.floats()[..] else {
                return Err(SceneError::syntax(
                    &p.loc,
                    "parameter \"float screenwindow\" needs 4 values",
                ));
            };
            if !(x0 < x1 && y0 < y1) {
                return Err(SceneError::invalid(
                    &p.loc,
                    "screenwindow must be [xmin xmax ymin ymax] with min < max",
                ));
            }
            screen_window = Some([x0, x1, y0, y1]);
        }
        if let Some(p) = params.floats("frameaspectratio")? {
            let [frame] = p.floats()[..] else {
                return Err(SceneError::syntax(
                    &p.loc,
                    "parameter \"float frameaspectratio\" needs 1 value",
                ));
            };
            if frame <= 0.0 {
                return Err(SceneError::invalid(&p.loc, "frameaspectratio must be positive"));
            }
            // pbrt's screen window for a frame aspect ratio, unless one is given explicitly.
            if screen_window.is_none() {
                screen_window = Some(if frame > 1.0 {
                    [-frame, frame, -1.0, 1.0]
                } else {
                    [-1.0, 1.0, -1.0 / frame, 1.0 / frame]
                });
            }
        }
        self.options.camera = CameraDesc {
            projection,
            world_from_camera: Transform {
                m: world_from_camera.m,
                m_inv: world_from_camera.m_inv,
            },
            fov_degrees: fov,
            lens_radius,
            focal_distance,
            screen_window,
        };
        self.warn_unused(params);
        Ok(())
    }

    /// `Film "rgb" ...` (`gbuffer` and `spectral` render as `rgb`, with a warning).
    pub fn film(&mut self, kind: &str, params: &ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_options("Film", loc)?;
        match kind {
            "rgb" => {}
            "gbuffer" | "spectral" => {
                self.warn(
                    loc,
                    format!("film \"{kind}\" is not implemented yet; rendering as \"rgb\""),
                );
            }
            _ => return Err(SceneError::syntax(loc, format!("unknown film type \"{kind}\""))),
        }
        let width = resolution(params, "xresolution", 1280)?;
        let height = resolution(params, "yresolution", 720)?;
        if i64::from(width) * i64::from(height) > MAX_PIXELS {
            return Err(SceneError::invalid(
                loc,
                format!("film resolution {width}x{height} is too large (at most {MAX_PIXELS} pixels)"),
            ));
        }
        for cropping in ["cropwindow", "pixelbounds"] {
            if let Some(p) = params.get(cropping) {
                p.mark_used();
                return Err(SceneError::unsupported(
                    &p.loc,
                    format!("parameter \"{}\" of {} is not supported yet", p.decl(), params.owner),
                ));
            }
        }
        self.options.film = FilmDesc {
            width: width as u32,
            height: height as u32,
        };
        self.options.output_filename = params.string("filename")?.map(|(name, _)| name);
        self.warn_unused(params);
        Ok(())
    }

    /// `PixelFilter "box" | "triangle" | "gaussian" | "mitchell"`; `lanczos` falls back to
    /// the default Gaussian with a warning.
    pub fn pixel_filter(&mut self, kind: &str, params: &ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_options("PixelFilter", loc)?;
        let default_radius = match kind {
            "box" => 0.5,
            "triangle" => 2.0,
            "gaussian" => 1.5,
            "mitchell" => 2.0,
            "lanczos" => {
                self.warn(
                    loc,
                    format!(
                        "pixel filter \"{kind}\" is not implemented yet; using \"gaussian\" with its defaults (radius 1.5, sigma 0.5)"
                    ),
                );
                self.options.filter = FilterDesc::default();
                self.warn_unused(params);
                return Ok(());
            }
            _ => return Err(SceneError::syntax(loc, format!("unknown pixel filter \"{kind}\""))),
        };
        let radius = Vec2::new(
            positive(params, "xradius", default_radius)?,
            positive(params, "yradius", default_radius)?,
        );
        self.options.filter = match kind {
            "box" => FilterDesc::Box { radius },
            "triangle" => FilterDesc::Triangle { radius },
            "mitchell" => FilterDesc::Mitchell {
                radius,
                b: finite_float(params, "B", 1.0 / 3.0)?,
                c: finite_float(params, "C", 1.0 / 3.0)?,
            },
            _ => FilterDesc::Gaussian {
                radius,
                sigma: positive(params, "sigma", 0.5)?,
            },
        };
        self.warn_unused(params);
        Ok(())
    }

    /// `Sampler "..."`: `independent`; `stratified` (`xsamples`, `ysamples`, `jitter`); and
    /// `sobol`, `zsobol`, `halton`, `pmj02bn`, `paddedsobol`, which all use the Owen-scrambled
    /// Sobol' sampler (their `randomization` is accepted; the points are always Owen-scrambled).
    pub fn sampler(&mut self, kind: &str, params: &ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_options("Sampler", loc)?;
        let (sampler_kind, spp) = match kind {
            "independent" | "sobol" | "zsobol" | "halton" | "pmj02bn" | "paddedsobol" => {
                let spp = params.int("pixelsamples", 16)?;
                if spp <= 0 {
                    return Err(param_error(params, "pixelsamples", "must be at least 1"));
                }
                if kind == "independent" {
                    (SamplerKind::Independent, spp)
                } else {
                    if let Some((name, loc)) = params.string("randomization")? {
                        if !matches!(name.as_str(), "owen" | "fastowen" | "permutedigits" | "none") {
                            return Err(SceneError::invalid(
                                &loc,
                                format!(
                                    "expected a randomization (owen, fastowen, permutedigits, none), found \"{name}\""
                                ),
                            ));
                        }
                    }
                    (SamplerKind::OwenSobol, spp)
                }
            }
            "stratified" => {
                // pbrt's stratified sampler takes xsamples * ysamples samples per pixel.
                let x = params.int("xsamples", 4)?;
                let y = params.int("ysamples", 4)?;
                if x <= 0 || y <= 0 {
                    return Err(SceneError::invalid(loc, "xsamples and ysamples must be at least 1"));
                }
                let spp = x
                    .checked_mul(y)
                    .ok_or_else(|| SceneError::invalid(loc, "xsamples * ysamples is too large"))?;
                let kind = SamplerKind::Stratified {
                    x_samples: x as u32,
                    y_samples: y as u32,
                    jitter: params.bool("jitter", true)?,
                };
                (kind, spp)
            }
            _ => return Err(SceneError::syntax(loc, format!("unknown sampler \"{kind}\""))),
        };
        if let Some(p) = params.ints("seed")? {
            p.mark_used();
            let [seed] = p.ints()[..] else {
                return Err(SceneError::syntax(&p.loc, "parameter \"integer seed\" needs 1 value"));
            };
            self.options.sampler_seed = Some(seed);
        } else {
            self.options.sampler_seed = None;
        }
        self.options.sampler.kind = sampler_kind;
        self.options.sampler.samples_per_pixel = spp as u32;
        self.warn_unused(params);
        Ok(())
    }

    /// `Integrator "path"`, `"direct"`, `"bdpt"` (with `regularize`,
    /// `visualizestrategies`, `visualizeweights`), `"lightpath"`, `"sppm"` and `"mlt"` (with
    /// their parameters); other pbrt integrators fall back to path with a warning.
    pub fn integrator(&mut self, kind: &str, params: &ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_options("Integrator", loc)?;
        let integrator_kind = match kind {
            "direct" | "directlighting" => IntegratorKind::Direct,
            "bdpt" => IntegratorKind::Bdpt,
            "lightpath" => IntegratorKind::LightPath,
            "sppm" => IntegratorKind::Sppm,
            "mlt" => IntegratorKind::Mlt,
            _ => IntegratorKind::Path,
        };
        match kind {
            "path" | "direct" | "directlighting" | "bdpt" | "lightpath" | "sppm" | "mlt" => {}
            "volpath" => self.warn(
                loc,
                "integrator \"volpath\" renders as \"path\" (participating media are not supported)",
            ),
            "simplepath" | "randomwalk" | "ambientocclusion" | "simplevolpath" => {
                self.warn(
                    loc,
                    format!("integrator \"{kind}\" is not implemented yet; using \"path\""),
                );
            }
            _ => return Err(SceneError::syntax(loc, format!("unknown integrator \"{kind}\""))),
        }
        let max_depth = params.int("maxdepth", 5)?;
        if max_depth < 0 {
            return Err(param_error(params, "maxdepth", "must not be negative"));
        }
        let direct = match params.string("direct")? {
            None => DirectStrategy::Mis,
            Some((name, loc)) => DirectStrategy::ALL
                .into_iter()
                .find(|d| d.name() == name)
                .ok_or_else(|| {
                    let names: Vec<_> = DirectStrategy::ALL.iter().map(|d| d.name()).collect();
                    SceneError::invalid(
                        &loc,
                        format!("expected a direct strategy ({}), found \"{name}\"", names.join(", ")),
                    )
                })?,
        };
        let light_samples = params.int("lightsamples", 1)?;
        if light_samples < 1 {
            return Err(param_error(params, "lightsamples", "must be at least 1"));
        }
        let russian_roulette = russian_roulette(params)?;
        let bdpt = if integrator_kind == IntegratorKind::Bdpt {
            BdptDesc {
                regularize: params.bool("regularize", false)?,
                visualize_strategies: params.bool("visualizestrategies", false)?,
                visualize_weights: params.bool("visualizeweights", false)?,
                ..BdptDesc::default()
            }
        } else {
            BdptDesc::default()
        };
        let sppm = if integrator_kind == IntegratorKind::Sppm {
            sppm_params(params)?
        } else {
            SppmDesc::default()
        };
        let mlt = if integrator_kind == IntegratorKind::Mlt {
            mlt_params(params)?
        } else {
            MltDesc::default()
        };
        self.options.integrator = IntegratorDesc {
            kind: integrator_kind,
            max_depth: max_depth as u32,
            direct,
            light_samples: light_samples as u32,
            russian_roulette,
            bdpt,
            sppm,
            mlt,
            light_selection: LightSelection::Power,
        };
        self.warn_unused(params);
        Ok(())
    }

    /// `Accelerator`: mcrender always builds its own BVH.
    pub fn accelerator(&mut self, kind: &str, params: &ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_options("Accelerator", loc)?;
        match kind {
            "bvh" | "kdtree" => {
                self.warn(
                    loc,
                    format!("Accelerator \"{kind}\" ignored; mcrender always uses its own BVH"),
                );
                params.params().iter().for_each(|p| p.mark_used());
                Ok(())
            }
            _ => Err(SceneError::syntax(loc, format!("unknown accelerator \"{kind}\""))),
        }
    }

    /// `ColorSpace "name"`: only sRGB, the space mcrender renders in.
    pub fn color_space(&mut self, name: &str, loc: &Location) -> Result<(), SceneError> {
        match name {
            "srgb" => Ok(()),
            "aces2065-1" | "rec2020" | "dci-p3" => Err(SceneError::unsupported(
                loc,
                format!("color space \"{name}\" is not supported yet (only \"srgb\")"),
            )),
            _ => Err(SceneError::syntax(loc, format!("unknown color space \"{name}\""))),
        }
    }

    /// `Option "name" value` (pbrt's command-line options set from the file).
    pub fn option(&mut self, name: &str, value: &str, loc: &Location) -> Result<(), SceneError> {
        // Accept both `Option "seed" 3` and `Option "integer seed" 3`.
        let bare = name.split_whitespace().last().unwrap_or("");
        let normalized: String = bare
            .chars()
            .filter(|c| *c != '_' && *c != '-')
            .collect::<String>()
            .to_lowercase();
        match normalized.as_str() {
            "seed" => {
                let seed = value.parse::<i32>().map_err(|_| {
                    SceneError::syntax(
                        loc,
                        format!("expected an integer value for Option \"seed\", found \"{value}\""),
                    )
                })?;
                self.options.option_seed = Some(seed);
            }
            "disablepixeljitter"
            | "disabletexturefiltering"
            | "disablewavelengthjitter"
            | "displacementedgescale"
            | "msereferenceimage"
            | "msereferenceout"
            | "forcediffuse"
            | "pixelstats"
            | "wavefront" => {
                self.warn(loc, format!("Option \"{bare}\" is not supported and was ignored"));
            }
            _ => return Err(SceneError::syntax(loc, format!("unknown option \"{bare}\""))),
        }
        Ok(())
    }
}

/// An invalid value for the parameter `name` of `params` (which must exist).
fn param_error(params: &ParamSet, name: &str, what: &str) -> SceneError {
    match params.get(name) {
        Some(p) => SceneError::invalid(&p.loc, format!("parameter \"{}\" of {} {what}", p.decl(), params.owner)),
        None => SceneError::invalid(&params.loc, format!("parameter \"{name}\" of {} {what}", params.owner)),
    }
}

/// A positive float parameter.
fn positive(params: &ParamSet, name: &str, default: f32) -> Result<f32, SceneError> {
    let v = params.float(name, default)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(param_error(params, name, "must be positive"))
    }
}

/// A float parameter that must be finite.
fn finite_float(params: &ParamSet, name: &str, default: f32) -> Result<f32, SceneError> {
    let v = params.float(name, default)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(param_error(params, name, "must be finite"))
    }
}

/// An image resolution parameter in `1..=MAX_RESOLUTION`.
fn resolution(params: &ParamSet, name: &str, default: i32) -> Result<i32, SceneError> {
    let v = params.int(name, default)?;
    if (1..=MAX_RESOLUTION).contains(&v) {
        Ok(v)
    } else {
        Err(param_error(
            params,
            name,
            &format!("must be between 1 and {MAX_RESOLUTION}, found {v}"),
        ))
    }
}

/// mcrender's Russian roulette parameters of `Integrator`: `"string russianroulette"`
/// (`"off"`, `"throughput"` = pbrt's rule, the default, or `"threshold"`), and for the
/// lecture's rule `"float rrthreshold"` and `"float rrprobability"` (giving either selects it).
/// `Integrator "sppm"`'s parameters: `numiterations`, `photonsperiteration` (-1: the pixel
/// count), `radius`, `seed`.
fn sppm_params(params: &ParamSet) -> Result<SppmDesc, SceneError> {
    let iterations = params.int("numiterations", 64)?;
    if iterations < 1 {
        return Err(param_error(params, "numiterations", "must be at least 1"));
    }
    let photons = params.int("photonsperiteration", -1)?;
    if photons == 0 || photons < -1 {
        return Err(param_error(
            params,
            "photonsperiteration",
            "must be positive (or -1: the pixel count)",
        ));
    }
    let radius = params.float("radius", 1.0)?;
    if !(radius.is_finite() && radius > 0.0) {
        return Err(param_error(params, "radius", "must be a positive number"));
    }
    let seed = match params.get("seed") {
        Some(_) => Some(u64::from(params.int("seed", 0)?.unsigned_abs())),
        None => None,
    };
    Ok(SppmDesc {
        iterations: iterations as u32,
        photons_per_iteration: (photons > 0).then_some(photons as u64),
        radius,
        seed,
    })
}

/// `Integrator "mlt"`'s parameters: `bootstrapsamples`, `chains`, `mutationsperpixel`,
/// `largestepprobability`, `sigma`, `regularize` (pbrt-v4's defaults).
fn mlt_params(params: &ParamSet) -> Result<MltDesc, SceneError> {
    let d = MltDesc::default();
    let positive = |name: &str, default: u32| -> Result<u32, SceneError> {
        let v = params.int(name, default as i32)?;
        if v < 1 {
            return Err(param_error(params, name, "must be at least 1"));
        }
        Ok(v as u32)
    };
    let bootstrap_samples = positive("bootstrapsamples", d.bootstrap_samples)?;
    let chains = positive("chains", d.chains)?;
    let mutations_per_pixel = positive("mutationsperpixel", d.mutations_per_pixel)?;
    let large_step_probability = params.float("largestepprobability", d.large_step_probability)?;
    if !(0.0..=1.0).contains(&large_step_probability) {
        return Err(param_error(params, "largestepprobability", "must be in [0, 1]"));
    }
    let sigma = params.float("sigma", d.sigma)?;
    if !(sigma.is_finite() && sigma > 0.0) {
        return Err(param_error(params, "sigma", "must be a positive number"));
    }
    Ok(MltDesc {
        bootstrap_samples,
        chains,
        mutations_per_pixel,
        large_step_probability,
        sigma,
        regularize: params.bool("regularize", false)?,
    })
}

fn russian_roulette(params: &ParamSet) -> Result<RussianRoulette, SceneError> {
    let threshold = params.get("rrthreshold").is_some() || params.get("rrprobability").is_some();
    let mode = params.string("russianroulette")?;
    let mode_name = mode.as_ref().map(|(m, _)| m.as_str());
    match (mode_name, threshold) {
        (Some("off"), false) => Ok(RussianRoulette::Off),
        (None | Some("throughput"), false) => Ok(RussianRoulette::Throughput),
        (Some("mitsuba"), false) => {
            let start = params.int("rrdepth", 5)?;
            if start < 0 {
                return Err(param_error(params, "rrdepth", "must be a non-negative bounce count"));
            }
            Ok(RussianRoulette::Delayed {
                start_depth: start as u32,
            })
        }
        (None | Some("threshold"), _) => {
            let t = params.float("rrthreshold", 1.0)?;
            let q = params.float("rrprobability", 0.5)?;
            if !(t.is_finite() && t >= 0.0) {
                return Err(param_error(params, "rrthreshold", "must be a non-negative number"));
            }
            if !(0.0..1.0).contains(&q) {
                return Err(param_error(params, "rrprobability", "must be in [0, 1)"));
            }
            Ok(RussianRoulette::Threshold {
                threshold: t,
                probability: q,
            })
        }
        (Some(other), _) => {
            let loc = &mode.as_ref().expect("mode given").1;
            Err(SceneError::invalid(
                loc,
                format!("expected russianroulette \"off\", \"throughput\", \"mitsuba\" (with rrdepth) or \"threshold\" (with rrthreshold/rrprobability), found \"{other}\""),
            ))
        }
    }
}
