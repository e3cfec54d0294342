//! A small seeded random-number generator: the same stream on every machine and version.
//!
//! In: a 64-bit seed. Out: 64 random bits ([`SplitMix64::next_u64`]), uniform numbers in [0, 1)
//! ([`SplitMix64::uniform`]) and standard normal numbers ([`SplitMix64::normal`]), all
//! dimensionless.
//!
//! Method: SplitMix64 (Steele, Lea & Flood 2014; Vigna's `splitmix64.c`): the state advances by
//! the golden-ratio increment 0x9E3779B97F4A7C15 and each output is the state through a 64-bit
//! mixing function. The stream comes from the `rand_xoshiro` crate's `SplitMix64`, seeded
//! with the seed as its state; it equals the published reference values bit for bit (tested
//! below), so a seeded synthetic wall map is the same map everywhere. Uniform numbers take the
//! top 53 bits; normal numbers use Box–Muller (cosine branch), two uniforms each. The generator
//! is tiny and ample for smooth random fields and seeded test cases; it is not for cryptography.

use std::f64::consts::TAU;

use rand_xoshiro::rand_core::{RngCore, SeedableRng};

/// SplitMix64 (module doc): a tiny seeded generator, ample for smooth fields (and the seeded cases
/// of the input mutation test), the same stream on every machine and version.
pub struct SplitMix64(rand_xoshiro::SplitMix64);

impl SplitMix64 {
    /// The generator started at `seed` (the state before the first output).
    pub fn new(seed: u64) -> Self {
        Self(rand_xoshiro::SplitMix64::seed_from_u64(seed))
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in [0, 1), 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Standard normal (Box–Muller, cosine branch).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform();
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stream_matches_the_published_reference_values() {
        // Vigna's splitmix64.c started at x = 0: its first three outputs.
        let mut rng = SplitMix64::new(0);
        assert_eq!(rng.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(rng.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(rng.next_u64(), 0x06C4_5D18_8009_454F);
    }

    #[test]
    fn uniform_takes_the_top_53_bits() {
        // Seed 0's first output 0xE220A8397B1DCDAF: its top 53 bits over 2^53.
        let expected = (0xE220_A839_7B1D_CDAF_u64 >> 11) as f64 / (1u64 << 53) as f64;
        assert_eq!(SplitMix64::new(0).uniform().to_bits(), expected.to_bits());
        let mut rng = SplitMix64::new(7);
        assert!((0..10_000).all(|_| (0.0..1.0).contains(&rng.uniform())));
    }

    #[test]
    fn normal_has_unit_variance() {
        let mut rng = SplitMix64::new(1);
        let n = 200_000;
        let x: Vec<f64> = (0..n).map(|_| rng.normal()).collect();
        let mean = x.iter().sum::<f64>() / n as f64;
        let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64;
        // Standard errors: 1/√n ≈ 2.2e-3 for the mean, √(2/n) ≈ 3.2e-3 for the variance.
        assert!(mean.abs() < 0.01, "{mean}");
        assert!((var - 1.0).abs() < 0.015, "{var}");
    }
}
