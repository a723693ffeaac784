//! pbrt's `mix`: one of two materials per shading point, chosen deterministically.

use super::checks::{check_finite, check_reference, float_constants, InvalidParameter};
use super::MaterialId;
use crate::sampling::hash_u64s;
use crate::shape::SurfaceInteraction;
use crate::texture::{FloatTexture, TextureContext};

/// One of two materials per shading point (pbrt `mix`): the second with probability
/// `amount`, chosen by a hash of the point and `wo`.
#[derive(Clone, Debug, PartialEq)]
pub struct MixMaterial {
    /// The two materials (indices into the scene's materials; no cycles).
    pub materials: [MaterialId; 2],
    /// Probability of the second, clamped to [0, 1] (pbrt default 0.5).
    pub amount: FloatTexture,
}

impl MixMaterial {
    /// Check the parameters of material `index` among `count` materials.
    pub fn validate(&self, index: usize, count: usize) -> Result<(), InvalidParameter> {
        check_finite(
            &format!("amount of material {index}"),
            &float_constants(&[&self.amount]),
        )?;
        for m in self.materials {
            check_reference(index, "mixes", m, count)?;
        }
        Ok(())
    }

    /// The index of the material used at `si` (pbrt-v4 `MixMaterial::ChooseMaterial`), with
    /// `amount` evaluated at `ctx`: the first when `amount <= 0`, the second when `amount >=
    /// 1`, else the second when a hash of the point, `wo` and the two indices, mapped to
    /// [0, 1), is below `amount`.
    #[must_use]
    pub fn choose(&self, si: &SurfaceInteraction, ctx: &TextureContext) -> MaterialId {
        let (materials, amount) = (self.materials, self.amount.evaluate(ctx));
        if amount <= 0.0 {
            return materials[0];
        }
        if amount >= 1.0 {
            return materials[1];
        }
        let p = si.p();
        let bits = |v: f32| u64::from(v.to_bits());
        let h = hash_u64s(&[
            bits(p.x),
            bits(p.y),
            bits(p.z),
            bits(si.wo.x),
            bits(si.wo.y),
            bits(si.wo.z),
            u64::from(materials[0]),
            u64::from(materials[1]),
        ]);
        // The top 24 bits: a uniform number in [0, 1) exactly representable as f32.
        let u = (h >> 40) as f32 / 16_777_216.0;
        if amount < u {
            materials[0]
        } else {
            materials[1]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{hit, scaled};
    use super::super::MaterialDesc;
    use super::*;

    #[test]
    fn mix_amount_is_a_texture_evaluated_per_hit() {
        let si = hit();
        let ctx = TextureContext::at_point(&si);
        for (amount, expected) in [(scaled(1.0, 0.0), 3), (scaled(0.5, 2.0), 4)] {
            let m = MaterialDesc::Mix(MixMaterial {
                materials: [3, 4],
                amount,
            });
            assert!(m.is_textured());
            assert_eq!(m.mix_choice(&si, &ctx), Some(expected));
        }
    }

    #[test]
    fn out_of_range_materials_are_refused() {
        let m = MixMaterial {
            materials: [0, 2],
            amount: 0.5.into(),
        };
        assert!(m.validate(1, 3).is_ok());
        let e = m.validate(1, 2).unwrap_err();
        assert_eq!(e.what, "material 1");
        assert!(e.detail.contains("mixes material index 2"), "{e:?}");
    }
}
