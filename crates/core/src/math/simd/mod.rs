//! The CPU's vector instruction sets: which ones this CPU has, found at run time, and the
//! few steps written in their intrinsics. The one module of the workspace with `unsafe`
//! code; every block carries a `SAFETY:` comment and the tests run every path this CPU can.
//!
//! The binary stays portable: it is built for baseline x86-64 (SSE2) or any other target,
//! and code using AVX2 or AVX-512 runs only after the CPU said it has them. That proof is
//! a value: an [`Avx2`] or [`Avx512`] can only be made by asking the CPU, so a function
//! taking one needs no `unsafe` at its call sites. Those are:
//! - [`Avx2::run`] and [`Avx512::run`]: run a closure inside a function compiled with the
//!   instruction set (`#[target_feature]`). The closure is inlined there, so plain
//!   fixed-size lane loops in it (the BVH's traversal and triangle kernels) are vectorised
//!   with 256-bit AVX2 and fused multiply-adds (AVX-512: also its mask registers and its
//!   32 vector registers). Rust never contracts a separate multiply and add, and a fused
//!   multiply-add is exactly rounded on whichever unit runs it, so every build gives the
//!   same bits.
//! - [`slab`]: the 8-wide slab test of a BVH node's boxes, in AVX2 and AVX-512 intrinsics.
//! - [`prefetch`], [`truncate_lanes`] and the ray offset's step to the next float, which
//!   need only the SSE and SSE2 every x86-64 CPU has.
//!
//! On targets other than x86-64 only [`Isa::Portable`] exists at run time and the tokens
//! cannot be made.

#![allow(unsafe_code)]

pub mod slab;
#[cfg(target_arch = "x86_64")]
pub(super) mod sse2;

/// An instruction set the BVH queries can run with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Isa {
    /// Any CPU: baseline instructions (SSE2 on x86-64).
    #[default]
    Portable,
    /// x86-64 with AVX2 and FMA.
    Avx2,
    /// x86-64 with AVX-512 F and VL, besides AVX2 and FMA.
    Avx512,
}

impl Isa {
    /// Every instruction set, supported here or not.
    pub const ALL: [Self; 3] = [Self::Portable, Self::Avx2, Self::Avx512];

    /// True when this CPU runs `self`.
    #[must_use]
    pub fn is_supported(self) -> bool {
        Supported::new(self).is_some()
    }

    /// The fastest one this CPU runs.
    #[must_use]
    pub fn best() -> Self {
        Supported::best().isa()
    }

    /// Lower-case name (`portable`, `avx2`, `avx512`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Portable => "portable",
            Self::Avx2 => "avx2",
            Self::Avx512 => "avx512",
        }
    }
}

/// An instruction set this CPU was found to have, holding the proof.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Supported {
    /// Baseline instructions.
    #[default]
    Portable,
    /// AVX2 and FMA.
    Avx2(Avx2),
    /// AVX-512 F and VL, AVX2 and FMA.
    Avx512(Avx512),
}

impl Supported {
    /// `isa`, if this CPU has it.
    #[must_use]
    pub fn new(isa: Isa) -> Option<Self> {
        match isa {
            Isa::Portable => Some(Self::Portable),
            Isa::Avx2 => Avx2::detect().map(Self::Avx2),
            Isa::Avx512 => Avx512::detect().map(Self::Avx512),
        }
    }

    /// The fastest instruction set this CPU has.
    #[must_use]
    pub fn best() -> Self {
        Self::new(Isa::Avx512)
            .or_else(|| Self::new(Isa::Avx2))
            .unwrap_or(Self::Portable)
    }

    /// Which instruction set it is.
    #[must_use]
    pub fn isa(self) -> Isa {
        match self {
            Self::Portable => Isa::Portable,
            Self::Avx2(_) => Isa::Avx2,
            Self::Avx512(_) => Isa::Avx512,
        }
    }
}

/// Proof that this CPU has AVX2 and FMA: made only by [`Avx2::detect`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Avx2(());

impl Avx2 {
    /// The proof, if this CPU has AVX2 and FMA.
    #[must_use]
    pub fn detect() -> Option<Self> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
            return Some(Self(()));
        }
        None
    }

    /// `f()`, compiled with AVX2 and FMA (see the module's documentation). Pass a closure
    /// written at the call and given to no other function: one whose code is called from
    /// several places is not inlined, and runs without the features (the same results, at
    /// portable speed; packet queries fell from 6.1 to 3.9 M rays/s when the dispatcher
    /// gave one closure to both `run`s).
    #[inline(always)]
    pub fn run<R>(self, f: impl FnOnce() -> R) -> R {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: an `Avx2` exists only once `detect` found AVX2 and FMA on this CPU,
            // all that `run_avx2` requires.
            unsafe { run_avx2(f) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        f()
    }
}

/// Proof that this CPU has AVX-512 F and VL, AVX2 and FMA: made only by
/// [`Avx512::detect`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Avx512(());

impl Avx512 {
    /// The proof, if this CPU has AVX-512 F and VL, AVX2 and FMA.
    #[must_use]
    pub fn detect() -> Option<Self> {
        #[cfg(target_arch = "x86_64")]
        if Avx2::detect().is_some()
            && std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl")
        {
            return Some(Self(()));
        }
        None
    }

    /// `f()`, compiled with AVX-512 F and VL, AVX2 and FMA (see the module's documentation
    /// and [`Avx2::run`] on the closure).
    #[inline(always)]
    pub fn run<R>(self, f: impl FnOnce() -> R) -> R {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: an `Avx512` exists only once `detect` found these features on this
            // CPU, all that `run_avx512` requires.
            unsafe { run_avx512(f) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        f()
    }
}

// The closures' code is inlined into these (a closure has one call site), and so compiled
// with their features; LLVM never inlines them into a caller without the features.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn run_avx2<R>(f: impl FnOnce() -> R) -> R {
    f()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx2,fma")]
fn run_avx512<R>(f: impl FnOnce() -> R) -> R {
    f()
}

/// Ask the CPU to start loading the cache lines of `value` (a hint: no effect on results).
#[inline(always)]
pub fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let start = std::ptr::from_ref(value).cast::<i8>();
        for line in (0..std::mem::size_of::<T>()).step_by(64) {
            // SAFETY: `prefetch` is SSE, which every x86-64 CPU has; it reads nothing and
            // cannot fault, and `start + line` stays inside `value`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(start.add(line)) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

/// The first three lanes of `v`, each in `0..2^31`, truncated to integers: one SSE2
/// conversion on x86-64 (`cvttps2dq`), where a lane-by-lane `as` saturates each lane with
/// compares and branches (the BVH build's binning converts three lanes per primitive per
/// level).
#[inline(always)]
#[must_use]
pub fn truncate_lanes(v: glam::Vec3A) -> [u32; 3] {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{__m128, __m128i, _mm_cvttps_epi32};
        let v: __m128 = v.into();
        // SAFETY: `cvttps2dq` is SSE2, which every x86-64 CPU has; it only converts lanes.
        // The transmute reinterprets 16 bytes of integers as four `u32`, which any bits are.
        let lanes: [u32; 4] = unsafe { std::mem::transmute::<__m128i, [u32; 4]>(_mm_cvttps_epi32(v)) };
        [lanes[0], lanes[1], lanes[2]]
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        [v.x as u32, v.y as u32, v.z as u32]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The SSE2 truncation gives `as u32`'s integers on every float in `0..=2^22` near the
    /// integers below 64, on a dense sample of the BVH build's bucket range `0..=12` and a
    /// sparse one above, so the conversion behind the `unsafe` block is the one the build's
    /// binning assumes.
    #[test]
    fn truncate_lanes_matches_as() {
        let mut checked = 0;
        let mut x = 0.0f32;
        while x <= 4_194_304.0 {
            let v = glam::Vec3A::new(x, x * 0.37, f32::from_bits(x.to_bits().saturating_sub(1)));
            assert_eq!(truncate_lanes(v), [v.x as u32, v.y as u32, v.z as u32], "{v:?}");
            let step = if x >= 0.5 && (x - x.round()).abs() < 1e-3 && x < 64.0 {
                1
            } else if x <= 12.0 {
                4096
            } else {
                65_536
            };
            x = f32::from_bits(x.to_bits() + step);
            checked += 1;
        }
        assert!(checked > 10_000, "{checked}");
        assert_eq!(
            truncate_lanes(glam::Vec3A::new(0.0, 11.0, 4_194_304.0)),
            [0, 11, 4_194_304]
        );
    }

    /// Runs the prefetch loop over no cache line, part of one and several, so every path of
    /// its `unsafe` block runs in the tests (the hint itself cannot fail: an out-of-bounds
    /// pointer would show under Miri), and the value is left as it was.
    #[test]
    fn prefetch_any_size() {
        prefetch(&());
        prefetch(&7u8);
        let big = [3u64; 100];
        prefetch(&big);
        assert_eq!(big, [3u64; 100]);
    }

    /// Detection agrees with itself, the best set is supported, and `run` returns its
    /// closure's value (and runs code needing the features: a fused multiply-add) in every
    /// set this CPU has.
    #[test]
    fn detection_and_run() {
        assert!(Isa::Portable.is_supported());
        assert!(Isa::best().is_supported());
        for isa in Isa::ALL {
            assert_eq!(
                Supported::new(isa).map(Supported::isa),
                isa.is_supported().then_some(isa)
            );
        }
        let fma = || 3.0f32.mul_add(5.0, -1.0);
        match Avx2::detect() {
            Some(cpu) => assert_eq!(cpu.run(fma), 14.0),
            None => eprintln!("NOT TESTED: this CPU has no AVX2 and FMA; only the portable kernels ran"),
        }
        match Avx512::detect() {
            Some(cpu) => {
                assert_eq!(cpu.run(fma), 14.0);
                assert!(Isa::Avx2.is_supported());
                assert_eq!(Isa::best(), Isa::Avx512);
            }
            None => eprintln!("NOT TESTED: this CPU has no AVX-512 F and VL; its kernels did not run"),
        }
    }
}
