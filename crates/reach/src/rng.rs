//! The crate's one pseudo-random generator, for reproducible restarts and sampling.

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny, fast, well-mixed deterministic generator.
/// The same seed always gives the same sequence, so numeric IK starts and planner samples
/// are reproducible.
#[derive(Debug, Clone)]
pub(crate) struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)` (53 random bits; both conversions are exact).
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_f64() * n as f64) as usize).min(n - 1)
    }

    /// Standard normal (mean 0, variance 1), by the Box–Muller transform of two uniforms
    /// (`1 − u` keeps the logarithm's argument in `(0, 1]`).
    #[cfg_attr(not(test), allow(dead_code, reason = "used by the sensing tests' simulated noise"))]
    pub fn normal(&mut self) -> f64 {
        let (u, v) = (1.0 - self.next_f64(), self.next_f64());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}
