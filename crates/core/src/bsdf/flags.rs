//! Flags describing a lobe or a sampled event: reflection / transmission and
//! diffuse / glossy / specular.

use std::ops::BitOr;

/// A set of scattering kinds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BxdfFlags(u8);

impl BxdfFlags {
    /// Nothing: a black lobe.
    pub const NONE: Self = Self(0);
    /// Scatters to the side of `wo`.
    pub const REFLECTION: Self = Self(1);
    /// Scatters to the other side.
    pub const TRANSMISSION: Self = Self(2);
    /// Spread over the hemisphere.
    pub const DIFFUSE: Self = Self(4);
    /// Concentrated around a direction.
    pub const GLOSSY: Self = Self(8);
    /// A Dirac delta.
    pub const SPECULAR: Self = Self(16);
    /// Diffuse reflection.
    pub const DIFFUSE_REFLECTION: Self = Self(1 | 4);

    /// True when no flag is set.
    #[must_use]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// True when all flags of `o` are set.
    #[must_use]
    pub fn contains(self, o: Self) -> bool {
        self.0 & o.0 == o.0
    }

    /// True for a Dirac-delta lobe or event.
    #[must_use]
    pub fn is_specular(self) -> bool {
        self.contains(Self::SPECULAR)
    }

    /// True when some part is not specular, so light sampling can help.
    #[must_use]
    pub fn is_non_specular(self) -> bool {
        self.0 & (Self::DIFFUSE.0 | Self::GLOSSY.0) != 0
    }
}

impl BitOr for BxdfFlags {
    type Output = Self;
    fn bitor(self, o: Self) -> Self {
        Self(self.0 | o.0)
    }
}
