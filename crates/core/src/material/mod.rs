//! Layer 3: materials turn a surface interaction into a BSDF. A [`MaterialDesc`] is one
//! material of the scene description; its parameters are textures ([`crate::texture`])
//! evaluated at each hit's [`TextureContext`], so [`MaterialDesc::bsdf`] resolves them
//! (alphas from roughness, conductor indices from a reflectance) per hit. Constant
//! textures give the same BSDF at every hit.
//!
//! One file per material: its parameters, their validation ([`MaterialDesc::validate`],
//! called when a scene is built) and the BSDF it makes. The coated materials build their
//! stochastic `LayeredBxdf` per hit from their evaluated textures (a small `Copy` value).
//!
//! Four materials are not surfaces themselves: [`MaterialDesc::Mix`] names two others
//! and picks one per shading point ([`MaterialDesc::mix_choice`]; the scene follows the
//! choice, see `Scene::bsdf`), [`MaterialDesc::NormalMap`] and [`MaterialDesc::BumpMap`]
//! move the shading frame and name the material shaded in it, and [`MaterialDesc::Interface`] has no BSDF at all, so
//! rays pass through it.

mod bump_map;
mod checks;
mod coated_conductor;
mod coated_diffuse;
mod conductor;
mod dielectric;
mod diffuse;
mod diffuse_transmission;
mod metallic_roughness;
mod mix;
mod normal_map;
mod params;
mod plastic;
#[cfg(test)]
mod test_support;
mod thin_dielectric;

pub use bump_map::{BumpHeight, BumpMapMaterial};
pub use checks::{check_finite, check_non_negative, float_constants, rgb_constant, InvalidParameter};
pub use coated_conductor::CoatedConductorMaterial;
pub use coated_diffuse::CoatedDiffuseMaterial;
pub use conductor::ConductorMaterial;
pub use dielectric::DielectricMaterial;
pub use diffuse::DiffuseMaterial;
pub use diffuse_transmission::DiffuseTransmissionMaterial;
pub use metallic_roughness::MetallicRoughnessMaterial;
pub use mix::MixMaterial;
pub use normal_map::{MapStyle, NormalMapMaterial};
pub use plastic::PlasticMaterial;
pub use thin_dielectric::ThinDielectricMaterial;

use crate::bsdf::Bsdf;
use crate::shape::SurfaceInteraction;
use crate::texture::TextureContext;

/// Index into the scene description's materials.
pub type MaterialId = u32;

/// A material. Texturable parameters (as in pbrt-v4) are `RgbTexture`s or
/// `FloatTexture`s; constants convert with `.into()` (`Rgb::splat(0.5).into()`).
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialDesc {
    /// Lambertian reflection (pbrt `diffuse`).
    Diffuse(DiffuseMaterial),
    /// A metal (pbrt `conductor`).
    Conductor(ConductorMaterial),
    /// Glass, water (pbrt `dielectric`).
    Dielectric(DielectricMaterial),
    /// A thin slab such as a window pane (pbrt `thindielectric`).
    ThinDielectric(ThinDielectricMaterial),
    /// Lambertian reflection and transmission (pbrt `diffusetransmission`).
    DiffuseTransmission(DiffuseTransmissionMaterial),
    /// A coated diffuse surface (pbrt `coateddiffuse`).
    CoatedDiffuse(CoatedDiffuseMaterial),
    /// A coated metal (pbrt `coatedconductor`).
    CoatedConductor(CoatedConductorMaterial),
    /// Mitsuba 3's `plastic` and `roughplastic`.
    Plastic(PlasticMaterial),
    /// Another material under a normal map (Mitsuba 3's `normalmap`, pbrt-v4's
    /// `normalmap` parameter).
    NormalMap(NormalMapMaterial),
    /// Another material under a bump map (Mitsuba 3's `bumpmap`, pbrt-v4's
    /// `displacement` parameter).
    BumpMap(BumpMapMaterial),
    /// One of two materials per shading point (pbrt `mix`).
    Mix(MixMaterial),
    /// glTF 2.0's metallic-roughness material.
    MetallicRoughness(MetallicRoughnessMaterial),
    /// No surface at all (pbrt `interface`, which marks medium boundaries): rays pass
    /// straight through, shadow rays included.
    Interface,
}

/// What the rest of the renderer calls a material: its description, whose textures
/// [`MaterialDesc::bsdf`] evaluates per hit.
pub type Material = MaterialDesc;

impl MaterialDesc {
    /// The material a (validated) description asks for: the description itself.
    #[must_use]
    pub fn from_desc(desc: &Self) -> Self {
        desc.clone()
    }

    /// Check the parameters of material `index` among `count` materials (references to
    /// other materials in range; cycles are the scene's to check, see [`Self::children`]).
    pub fn validate(&self, index: usize, count: usize) -> Result<(), InvalidParameter> {
        match self {
            Self::Diffuse(m) => m.validate(index),
            Self::Conductor(m) => m.validate(index),
            Self::Dielectric(m) => m.validate(index),
            Self::ThinDielectric(m) => m.validate(index),
            Self::DiffuseTransmission(m) => m.validate(index),
            Self::CoatedDiffuse(m) => m.validate(index),
            Self::CoatedConductor(m) => m.validate(index),
            Self::Plastic(m) => m.validate(index),
            Self::NormalMap(m) => m.validate(index, count),
            Self::BumpMap(m) => m.validate(index, count),
            Self::Mix(m) => m.validate(index, count),
            Self::MetallicRoughness(m) => m.validate(index),
            Self::Interface => Ok(()),
        }
    }

    /// The materials this one refers to (the two of a mix, the one under a normal map).
    #[must_use]
    pub fn children(&self) -> &[MaterialId] {
        match self {
            Self::Mix(m) => &m.materials,
            Self::NormalMap(m) => std::slice::from_ref(&m.material),
            Self::BumpMap(m) => std::slice::from_ref(&m.material),
            _ => &[],
        }
    }

    /// For [`Self::Mix`], the index of the material used at `si` (see
    /// [`MixMaterial::choose`]); `None` for every other material.
    #[must_use]
    pub fn mix_choice(&self, si: &SurfaceInteraction, ctx: &TextureContext) -> Option<MaterialId> {
        match self {
            Self::Mix(m) => Some(m.choose(si, ctx)),
            _ => None,
        }
    }

    /// For [`Self::NormalMap`] and [`Self::BumpMap`], move the shading frame of `si` (see
    /// [`NormalMapMaterial`], [`BumpMapMaterial`]; `ctx` the texture context at `si`, with
    /// the pixel footprint when [`Self::is_textured`]) and return the inner material;
    /// `None` for every other material.
    #[must_use]
    pub fn apply_frame(&self, si: &mut SurfaceInteraction, ctx: &TextureContext) -> Option<MaterialId> {
        match self {
            Self::NormalMap(m) => {
                m.apply(si);
                Some(m.material)
            }
            Self::BumpMap(m) => {
                m.apply(si, ctx);
                Some(m.material)
            }
            _ => None,
        }
    }

    /// The material under a normal or bump map; `None` for every other material.
    #[must_use]
    pub fn frame_inner(&self) -> Option<MaterialId> {
        match self {
            Self::NormalMap(m) => Some(m.material),
            Self::BumpMap(m) => Some(m.material),
            _ => None,
        }
    }

    /// True when some parameter is a non-constant texture, so [`Self::bsdf`] needs a
    /// texture context with a footprint.
    #[must_use]
    pub fn is_textured(&self) -> bool {
        match self {
            Self::Diffuse(m) => m.is_textured(),
            Self::Conductor(m) => m.is_textured(),
            Self::Dielectric(m) => m.is_textured(),
            Self::DiffuseTransmission(m) => m.is_textured(),
            Self::CoatedDiffuse(m) => m.is_textured(),
            Self::CoatedConductor(m) => m.is_textured(),
            Self::Plastic(m) => m.is_textured(),
            Self::Mix(m) => !m.amount.is_constant(),
            Self::MetallicRoughness(m) => m.is_textured(),
            // (pbrt's offsets follow the pixel footprint.)
            Self::BumpMap(m) => m.needs_footprint(),
            // (Resolved to the inner material before a BSDF is built.)
            Self::ThinDielectric(_) | Self::NormalMap(_) | Self::Interface => false,
        }
    }

    /// The BSDF at a hit, in the shading frame of `si.ns` with `si.dpdu` as first
    /// tangent, guarded by the geometric normal `si.n()`, with the textures evaluated at
    /// `ctx`; `None` for [`Self::Interface`], and for [`Self::Mix`] and
    /// [`Self::NormalMap`] and [`Self::BumpMap`] (resolve them first with [`Self::mix_choice`] and
    /// [`Self::apply_frame`]).
    #[must_use]
    pub fn bsdf(&self, si: &SurfaceInteraction, ctx: &TextureContext) -> Option<Bsdf> {
        // The BSDF is made in each arm, not from one lobe value the arms share: a shared
        // value is built field by field in memory and then copied in 16-byte loads, each of
        // which waited for the narrower stores (failed store-to-load forwarding).
        let with = |bxdf| Some(Bsdf::new(si.ns, si.dpdu, si.n(), bxdf));
        match self {
            Self::Diffuse(m) => with(m.bxdf(ctx)),
            Self::Conductor(m) => with(m.bxdf(ctx)),
            Self::Dielectric(m) => with(m.bxdf(ctx)),
            Self::ThinDielectric(m) => with(m.bxdf()),
            Self::DiffuseTransmission(m) => with(m.bxdf(ctx)),
            Self::CoatedDiffuse(m) => with(m.bxdf(ctx)),
            Self::CoatedConductor(m) => with(m.bxdf(ctx)),
            Self::MetallicRoughness(m) => with(m.bxdf(ctx)),
            Self::Plastic(m) => with(m.bxdf(ctx)),
            Self::Mix(_) | Self::NormalMap(_) | Self::BumpMap(_) | Self::Interface => None,
        }
    }
}
