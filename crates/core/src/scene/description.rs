//! The plain scene description that loaders produce and [`super::Scene::build`] consumes.
//!
//! Everything here is already resolved: transforms are matrices, named materials are indices,
//! meshes are in world space. No strings, files or parsing state reach the core.

pub use crate::camera::{CameraDesc, Projection};
use crate::color::Rgb;
pub use crate::film::{FilmDesc, FilterDesc, Reconstruction};
pub use crate::light::{EnvMapping, LightSelection, SpotFalloff};
pub use crate::material::{
    CoatedConductorMaterial, CoatedDiffuseMaterial, ConductorMaterial, DielectricMaterial, DiffuseMaterial,
    DiffuseTransmissionMaterial, MaterialDesc, MaterialId, MetallicRoughnessMaterial, MixMaterial, NormalMapMaterial,
    PlasticMaterial, ThinDielectricMaterial,
};
use crate::math::{Transform, Vec2, Vec3, Vec4};
pub use crate::sampling::{SamplerDesc, SamplerKind};
pub use crate::texture::{FloatTexture, RgbTexture};

/// A whole scene: what to render and how.
#[derive(Clone, Debug)]
pub struct SceneDescription {
    /// The camera.
    pub camera: CameraDesc,
    /// Image size.
    pub film: FilmDesc,
    /// Pixel reconstruction filter.
    pub filter: FilterDesc,
    /// How camera samples become pixels (filter sampling or splatting).
    pub reconstruction: Reconstruction,
    /// Sample generator and sample count.
    pub sampler: SamplerDesc,
    /// Light transport algorithm.
    pub integrator: IntegratorDesc,
    /// Materials, referred to by shapes through [`MaterialId`].
    pub materials: Vec<MaterialDesc>,
    /// Geometry.
    pub shapes: Vec<ShapeDesc>,
    /// Lights that are not attached to shapes (point lights, ...).
    pub lights: Vec<LightDesc>,
    /// Geometry defined once and placed by [`Self::instances`] (pbrt `ObjectBegin`).
    pub objects: Vec<ObjectDesc>,
    /// Placements of [`Self::objects`] (pbrt `ObjectInstance`); each shares its object's
    /// BVH rather than copying it.
    pub instances: Vec<InstanceDesc>,
}

/// Shapes defined once for instancing. Their transforms lead to the object's own space,
/// which each instance places in the world. They cannot emit (as in pbrt-v4).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjectDesc {
    /// The shapes, in object space (meshes already transformed there).
    pub shapes: Vec<ShapeDesc>,
}

/// One placement of an object.
#[derive(Clone, Debug, PartialEq)]
pub struct InstanceDesc {
    /// Index into [`SceneDescription::objects`].
    pub object: u32,
    /// World-from-object transform.
    pub world_from_instance: Transform,
}

/// Which light transport algorithm.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum IntegratorKind {
    /// Paths of any length (pbrt `path`).
    #[default]
    Path,
    /// Emission plus direct lighting at the first hit only (`Integrator "direct"`).
    Direct,
    /// Bidirectional path tracing (`Integrator "bdpt"`).
    Bdpt,
    /// Light tracing: paths from the lights connected to the camera (`Integrator
    /// "lightpath"`).
    LightPath,
    /// Stochastic progressive photon mapping (`Integrator "sppm"`), rendered by its own
    /// driver (`integrator::sppm::render`).
    Sppm,
    /// Metropolis light transport on primary sample space over BDPT paths (`Integrator
    /// "mlt"`), rendered by its own driver (`integrator::mlt::render`).
    Mlt,
}

/// Parameters of `Integrator "mlt"` (pbrt-v4's names and defaults; `maxdepth` is the
/// integrator's own).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MltDesc {
    /// Bootstrap samples per path depth (`bootstrapsamples`, default 100000).
    pub bootstrap_samples: u32,
    /// Markov chains (`chains`, default 1000).
    pub chains: u32,
    /// Mutations per pixel over all chains (`mutationsperpixel`, default 100).
    pub mutations_per_pixel: u32,
    /// Probability of a large step, a fresh uniform sample (`largestepprobability`, 0.3).
    pub large_step_probability: f32,
    /// Standard deviation of a small step's perturbation (`sigma`, default 0.01).
    pub sigma: f32,
    /// Roughen near-specular surfaces after a non-specular bounce (`regularize`).
    pub regularize: bool,
}

impl Default for MltDesc {
    fn default() -> Self {
        Self {
            bootstrap_samples: 100_000,
            chains: 1000,
            mutations_per_pixel: 100,
            large_step_probability: 0.3,
            sigma: 0.01,
            regularize: false,
        }
    }
}

/// Settings of bidirectional path tracing (pbrt `Integrator "bdpt"`, plus a strategy
/// filter for studying the strategies one at a time).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BdptDesc {
    /// Roughen near-specular surfaces after the first non-specular bounce (pbrt-v4's
    /// `regularize`): biased, but makes caustic paths connectible.
    pub regularize: bool,
    /// Write one image per strategy `(s, t)`, unweighted (pbrt's `visualizestrategies`).
    pub visualize_strategies: bool,
    /// Write one image per strategy `(s, t)`, MIS-weighted (pbrt's `visualizeweights`).
    pub visualize_weights: bool,
    /// Weight the strategies by multiple importance sampling (off: each counts in full,
    /// so only one strategy at a time gives a meaningful image).
    pub mis: bool,
    /// Keep only the contribution of the strategy `(s, t)`.
    pub strategy: Option<(u32, u32)>,
}

impl Default for BdptDesc {
    fn default() -> Self {
        Self {
            regularize: false,
            visualize_strategies: false,
            visualize_weights: false,
            mis: true,
            strategy: None,
        }
    }
}

/// Parameters of `Integrator "sppm"` (pbrt-v4's names and defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SppmDesc {
    /// Camera and photon passes (`numiterations`, default 64).
    pub iterations: u32,
    /// Photons per pass (`photonsperiteration`); `None` (pbrt's -1) = the pixel count.
    pub photons_per_iteration: Option<u64>,
    /// Initial search radius (`radius`, default 1).
    pub radius: f32,
    /// Seed (`seed`); `None` = the sampler's seed.
    pub seed: Option<u64>,
}

impl Default for SppmDesc {
    fn default() -> Self {
        Self {
            iterations: 64,
            photons_per_iteration: None,
            radius: 1.0,
            seed: None,
        }
    }
}

/// How the direct lighting at each path vertex is estimated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DirectStrategy {
    /// Directions uniform over the hemisphere of the surface, p = 1 / (2 pi).
    UniformHemisphere,
    /// Directions cosine-distributed over the hemisphere, p = cos(theta) / pi.
    CosineHemisphere,
    /// Points on the lights (uniform by area for area lights), converted to solid angle.
    LightArea,
    /// Directions sampled from the BSDF.
    Bsdf,
    /// Light and BSDF sampling combined by the power heuristic.
    #[default]
    Mis,
}

impl DirectStrategy {
    /// All strategies, in the order of the lecture.
    pub const ALL: [Self; 5] = [
        Self::UniformHemisphere,
        Self::CosineHemisphere,
        Self::LightArea,
        Self::Bsdf,
        Self::Mis,
    ];

    /// The name used on the command line and in scene files.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::UniformHemisphere => "uniform-hemisphere",
            Self::CosineHemisphere => "cosine-hemisphere",
            Self::LightArea => "light-area",
            Self::Bsdf => "bsdf",
            Self::Mis => "mis",
        }
    }

    /// True when the strategy finds light only by tracing rays that hit emitters, so it
    /// cannot see lights without area (point, spot, distant).
    #[must_use]
    pub const fn needs_emitter_hits(self) -> bool {
        matches!(self, Self::UniformHemisphere | Self::CosineHemisphere | Self::Bsdf)
    }
}

/// When to end paths at random (Russian roulette). Survivors are divided by their
/// survival probability, so the estimate stays unbiased.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum RussianRoulette {
    /// Never: paths end at the depth limit or when they escape.
    Off,
    /// pbrt-v4's rule: from the second bounce on, once the largest component of the path
    /// throughput `beta` is below 1, stop with probability `1 - max(beta)`.
    #[default]
    Throughput,
    /// Mitsuba 3's rule (`path.cpp`): from bounce `start_depth` on (Mitsuba's `rr_depth`,
    /// 5 by default), continue with probability `min(max(beta), 0.95)`. Later than pbrt's,
    /// so short paths, which carry most of the light, are not cut.
    Delayed {
        /// First bounce after which roulette is played.
        start_depth: u32,
    },
    /// The lecture's rule: when the luminance of the throughput is below `threshold`, stop
    /// with probability `probability`.
    Threshold {
        /// Throughput luminance below which roulette is played.
        threshold: f32,
        /// Probability of stopping, in [0, 1).
        probability: f32,
    },
}

/// Integrator settings (pbrt `Integrator "path"`, plus mcrender's estimator choices).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegratorDesc {
    /// Path or direct lighting only.
    pub kind: IntegratorKind,
    /// Maximum number of scattering events: 0 = emission only, 1 = direct lighting, ...
    pub max_depth: u32,
    /// Direct-lighting estimator.
    pub direct: DirectStrategy,
    /// Direct-lighting samples per path vertex.
    pub light_samples: u32,
    /// Russian roulette.
    pub russian_roulette: RussianRoulette,
    /// Bidirectional path tracing settings (used by [`IntegratorKind::Bdpt`]).
    pub bdpt: BdptDesc,
    /// SPPM parameters (used by [`IntegratorKind::Sppm`]).
    pub sppm: SppmDesc,
    /// MLT parameters (used by [`IntegratorKind::Mlt`]).
    pub mlt: MltDesc,
    /// How next-event estimation chooses a light.
    pub light_selection: LightSelection,
}

impl Default for IntegratorDesc {
    fn default() -> Self {
        Self {
            kind: IntegratorKind::Path,
            max_depth: 5,
            direct: DirectStrategy::Mis,
            light_samples: 1,
            russian_roulette: RussianRoulette::Throughput,
            bdpt: BdptDesc::default(),
            sppm: SppmDesc::default(),
            mlt: MltDesc::default(),
            light_selection: LightSelection::Power,
        }
    }
}

/// The emission of an area light attached to a shape (pbrt `AreaLightSource "diffuse"`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaLightDesc {
    /// Emitted radiance, with pbrt's `scale` already applied.
    pub radiance: Rgb,
    /// Emit on both sides instead of only on the side the surface normal points to.
    pub two_sided: bool,
    /// pbrt's `power` (W): when set, the radiance of every primitive the shape is made of
    /// is multiplied by `power / (pi A (two_sided ? 2 : 1))`, `A` that primitive's area.
    /// As in pbrt-v4, which makes one light per primitive, this is per primitive: each
    /// triangle of an emitting mesh emits `power` (times the luminance of `radiance`'s
    /// colour relative to white, which pbrt does not normalise away for RGB emission).
    pub power: Option<f32>,
}

/// One shape with its material and optional emission.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeDesc {
    /// The geometry.
    pub geometry: GeometryDesc,
    /// Its material.
    pub material: MaterialId,
    /// Emission, if the shape is an area light.
    pub area_light: Option<AreaLightDesc>,
    /// Flip the surface normal: pbrt's `ReverseOrientation` xor "the transform swaps
    /// handedness". Decides on which side a one-sided area light emits.
    pub flip_normals: bool,
    /// Alpha cut-out (pbrt `"float alpha"` / `"texture alpha"`): where it is `<= 0` the
    /// shape is absent, where it is in `(0, 1)` present with that probability per ray;
    /// `None` (or a constant `>= 1`) is opaque, with no test at all.
    pub alpha: Option<FloatTexture>,
}

/// Geometry of a shape.
#[derive(Clone, Debug, PartialEq)]
pub enum GeometryDesc {
    /// A triangle mesh, already transformed to world space.
    TriangleMesh(TriangleMeshDesc),
    /// A mesh of bilinear patches (pbrt-v4 `bilinearmesh`), already in world space. The
    /// geometric normal is `dp/du x dp/dv`, flipped by [`ShapeDesc::flip_normals`] unless
    /// shading normals are given.
    BilinearMesh(BilinearMeshDesc),
    /// A full sphere of `radius` around the origin of its object space.
    Sphere {
        /// Radius.
        radius: f32,
        /// World-from-object transform.
        world_from_object: Transform,
        /// Lowest height kept (pbrt `zmin`; `-radius` or below for no cut).
        z_min: f32,
        /// Highest height kept (pbrt `zmax`; `radius` or above for no cut).
        z_max: f32,
        /// Largest azimuth kept, in degrees (pbrt `phimax`; 360 for no cut).
        phi_max: f32,
    },
    /// A disk in the plane `z = height` of its object space, centred on the z axis, with an
    /// optional hole and an angular extent (pbrt-v4 `disk`). Its normal is object-space `+z`.
    Disk {
        /// Height of the plane.
        height: f32,
        /// Outer radius.
        radius: f32,
        /// Inner radius (0 = no hole).
        inner_radius: f32,
        /// Angular extent in radians, in `(0, 2 pi]`.
        phi_max: f32,
        /// World-from-object transform.
        world_from_object: Transform,
    },
    /// An open cylinder of `radius` around the z axis of its object space, from `z_min` to
    /// `z_max`, swept from azimuth 0 to `phi_max` (pbrt-v4 `cylinder`). Its normal points
    /// away from the axis.
    Cylinder {
        /// Radius.
        radius: f32,
        /// Lower end (pbrt `zmin`).
        z_min: f32,
        /// Upper end (pbrt `zmax`), above `z_min`.
        z_max: f32,
        /// Angular extent in radians, in `(0, 2 pi]`.
        phi_max: f32,
        /// World-from-object transform.
        world_from_object: Transform,
    },
}

impl GeometryDesc {
    /// A whole sphere (no `zmin`/`zmax`/`phimax` cut).
    #[must_use]
    pub fn full_sphere(radius: f32, world_from_object: Transform) -> Self {
        Self::Sphere {
            radius,
            world_from_object,
            z_min: -radius,
            z_max: radius,
            phi_max: 360.0,
        }
    }
}

/// A triangle mesh in world space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMeshDesc {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Three vertex indices per triangle.
    pub indices: Vec<u32>,
    /// Optional per-vertex shading normals (world space, same length as `positions`).
    pub normals: Option<Vec<Vec3>>,
    /// Optional per-vertex texture coordinates.
    pub uvs: Option<Vec<Vec2>>,
    /// Optional per-vertex shading tangents (world space `xyz`) with the handedness `w`
    /// (+1 or -1) of the bitangent `w (n x t)`, as glTF's `TANGENT`. Without them the
    /// tangent is dp/du from the uvs.
    pub tangents: Option<Vec<Vec4>>,
}

/// A bilinear patch mesh in world space: each patch is
/// `p(u, v) = lerp(u, lerp(v, p00, p01), lerp(v, p10, p11))` for `(u, v)` in `[0, 1]^2`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BilinearMeshDesc {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Four vertex indices per patch, in pbrt-v4's order `p00, p10, p01, p11`.
    pub indices: Vec<u32>,
    /// Optional per-vertex shading normals (world space, same length as `positions`),
    /// interpolated bilinearly.
    pub normals: Option<Vec<Vec3>>,
    /// Optional per-vertex texture coordinates, interpolated bilinearly; without them a
    /// patch's texture coordinates are its `(u, v)`.
    pub uvs: Option<Vec<Vec2>>,
}

/// A light that is not a shape. Directions and positions are in world space; pbrt's
/// `scale`, `power` and `illuminance` are already applied to the emitted quantities, except
/// for [`ImageInfiniteLightDesc::scale`].
#[derive(Clone, Debug, PartialEq)]
pub enum LightDesc {
    /// An isotropic point light (pbrt `point`).
    Point {
        /// World position.
        position: Vec3,
        /// Radiant intensity (W/sr per channel).
        intensity: Rgb,
    },
    /// A cone of light with a smooth falloff at its edge (pbrt `spot`).
    Spot(SpotLightDesc),
    /// Parallel light from one direction, as from a very distant source (pbrt `distant`).
    Distant {
        /// Unit direction from the scene towards the light.
        direction: Vec3,
        /// Radiance, which equals the irradiance on a surface facing the light.
        radiance: Rgb,
    },
    /// The same radiance from every direction, from infinitely far away (pbrt `infinite`
    /// with `L`).
    UniformInfinite {
        /// Radiance.
        radiance: Rgb,
    },
    /// Radiance from infinitely far away, read from an environment image (pbrt `infinite`
    /// with `filename`).
    ImageInfinite(ImageInfiniteLightDesc),
}

/// A spot light: intensity `I` inside a cone around the light's +z axis, falling off
/// to zero between the cone angles (smoothly as pbrt-v4 or linearly in angle as Mitsuba 3),
/// optionally with a projected image.
#[derive(Clone, Debug, PartialEq)]
pub struct SpotLightDesc {
    /// World-from-light transform: the light sits at the light-space origin and points
    /// along light-space +z.
    pub world_from_light: Transform,
    /// Radiant intensity on the axis (W/sr per channel).
    pub intensity: Rgb,
    /// Cosine of the angle where the falloff starts (full intensity inside it).
    pub cos_falloff_start: f32,
    /// Cosine of the angle where the intensity reaches zero (`<= cos_falloff_start`).
    pub cos_falloff_end: f32,
    /// The falloff's shape.
    pub falloff: SpotFalloff,
    /// An image projected along the cone (see [`crate::light::SpotLight::projection`]).
    pub projection: Option<RgbTexture>,
}

/// A linear RGB image, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImageDesc {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels, row by row from the top.
    pub pixels: Vec<Rgb>,
}

/// An environment-map light.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageInfiniteLightDesc {
    /// The emitted radiance per direction, before `scale`.
    pub image: RgbImageDesc,
    /// How the image covers the sphere.
    pub mapping: EnvMapping,
    /// Factor applied to every pixel (pbrt's `scale`, times the `illuminance`
    /// normalisation).
    pub scale: f32,
    /// World-from-light transform of directions (the CTM at the `LightSource`). Its linear
    /// part should be a rotation, possibly scaled; other linear maps are honoured exactly
    /// (directions are renormalised and the sampling pdf carries the Jacobian).
    pub world_from_light: Transform,
}
