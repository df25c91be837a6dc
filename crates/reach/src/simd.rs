//! Run-time choice of the vector instructions the batch kernels are compiled for.
//!
//! The kernels (lanes of configurations, candidates or rows processed side by side) are
//! written once, in plain Rust over fixed-size arrays, and compiled for several instruction
//! levels; [`run`] calls the widest one the processor offers. On x86-64 the levels are the
//! baseline (SSE2, two `f64` per instruction), AVX2 with FMA (four) and AVX-512 (eight).
//!
//! **Results do not depend on the level, bit for bit:** Rust never contracts `a * b + c`
//! into a fused multiply–add, and every other operation the kernels use (`+ − × ÷ √`,
//! comparisons, `min`/`max`, explicit [`f64::mul_add`]) is correctly rounded at every level;
//! the levels differ only in how many lanes one instruction takes. The tests run each kernel
//! at every level the machine has and compare the bits ([`levels`], [`run_at`]).
//!
//! The environment variable `REACH_SIMD` (`baseline`, `avx2` or `avx512`) caps the level,
//! for measuring the levels against each other; it is read once.

use std::sync::OnceLock;

/// A vector-instruction level the kernels are compiled for, narrowest first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    /// The target's baseline (x86-64: SSE2).
    Baseline,
    /// x86-64 AVX2 with FMA (four `f64` lanes).
    Avx2,
    /// x86-64 AVX-512 (F, VL, DQ, BW; eight `f64` lanes).
    Avx512,
}

impl Level {
    /// The level's name as `REACH_SIMD` spells it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Level::Baseline => "baseline",
            Level::Avx2 => "avx2",
            Level::Avx512 => "avx512",
        }
    }

    fn parse(name: &str) -> Option<Level> {
        [Level::Baseline, Level::Avx2, Level::Avx512].into_iter().find(|l| l.name() == name.trim())
    }
}

/// The widest level this processor supports (not capped by `REACH_SIMD`), probed once.
fn detected() -> Level {
    static DETECTED: OnceLock<Level> = OnceLock::new();
    *DETECTED.get_or_init(probe)
}

/// The processor's features, read.
fn probe() -> Level {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::is_x86_feature_detected as has;
        if has!("avx512f") && has!("avx512vl") && has!("avx512dq") && has!("avx512bw") && has!("avx2") && has!("fma") {
            return Level::Avx512;
        }
        if has!("avx2") && has!("fma") {
            return Level::Avx2;
        }
    }
    Level::Baseline
}

/// The level [`run`] uses: the widest the processor supports, capped by `REACH_SIMD` when it
/// names a level (an unknown value is ignored).
#[must_use]
pub fn level() -> Level {
    static LEVEL: OnceLock<Level> = OnceLock::new();
    *LEVEL.get_or_init(|| {
        let cap = std::env::var("REACH_SIMD").ok().and_then(|v| Level::parse(&v)).unwrap_or(Level::Avx512);
        detected().min(cap)
    })
}

/// Every level this processor supports, narrowest first (for tests that compare them).
#[must_use]
pub fn levels() -> Vec<Level> {
    [Level::Baseline, Level::Avx2, Level::Avx512].into_iter().filter(|l| *l <= detected()).collect()
}

/// A kernel: work [`run`] compiles for each level.
///
/// Implement it on a small struct holding the kernel's arguments, with `run` marked
/// `#[inline(always)]` (and the kernel's inner functions `#[inline(always)]`, or small and
/// generic): only code inlined into the level's entry point is compiled for that level;
/// anything called out of line runs at the baseline — still correct, only not widened.
/// (A closure cannot be forced inline on stable Rust, hence the trait.)
pub trait Kernel {
    /// What the kernel returns.
    type Output;
    /// The work.
    fn run(self) -> Self::Output;
}

/// Runs `kernel` compiled for [`level`].
#[inline(always)]
pub fn run<K: Kernel>(kernel: K) -> K::Output {
    run_at(level(), kernel)
}

/// Runs `kernel` compiled for `level`, or for the widest supported level below it.
#[inline(always)]
pub fn run_at<K: Kernel>(level: Level, kernel: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    {
        let level = level.min(detected());
        if level == Level::Avx512 {
            // SAFETY: `detected` found every feature `avx512` enables on this processor.
            return unsafe { x86::avx512(kernel) };
        }
        if level == Level::Avx2 {
            // SAFETY: `detected` found every feature `avx2` enables on this processor.
            return unsafe { x86::avx2(kernel) };
        }
    }
    let _ = level;
    kernel.run()
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::Kernel;

    /// `kernel` compiled with AVX2 and FMA.
    #[target_feature(enable = "avx,avx2,fma")]
    pub(super) fn avx2<K: Kernel>(kernel: K) -> K::Output {
        kernel.run()
    }

    /// `kernel` compiled with AVX-512 (and AVX2, FMA).
    #[target_feature(enable = "avx,avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")]
    pub(super) fn avx512<K: Kernel>(kernel: K) -> K::Output {
        kernel.run()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_parse_by_name_and_are_ordered() {
        for l in [Level::Baseline, Level::Avx2, Level::Avx512] {
            assert_eq!(Level::parse(l.name()), Some(l));
        }
        assert_eq!(Level::parse("sse9"), None);
        assert!(Level::Baseline < Level::Avx2 && Level::Avx2 < Level::Avx512);
        assert_eq!(levels()[0], Level::Baseline);
        assert!(level() <= detected());
    }

    /// The operations the module docs promise are exact at every level, over lanes.
    struct Sample<'a>(&'a [f64]);

    impl Kernel for Sample<'_> {
        type Output = Vec<u64>;
        #[inline(always)]
        fn run(self) -> Vec<u64> {
            self.0
                .iter()
                .map(|v| {
                    let s = (v * v + 1.0).sqrt() / (v.abs() + 0.5) - v * 1e-3;
                    s.mul_add(*v, 0.25).max(-1e6).to_bits() ^ (s < 1e6) as u64
                })
                .collect()
        }
    }

    #[test]
    fn a_lane_kernel_gives_the_same_bits_at_every_level() {
        let x: Vec<f64> = (0..1024).map(|i| (i as f64 * 0.7310585786).sin() * 1e3).collect();
        let baseline = run_at(Level::Baseline, Sample(&x));
        for l in levels() {
            assert_eq!(run_at(l, Sample(&x)), baseline, "level {}", l.name());
        }
    }
}
