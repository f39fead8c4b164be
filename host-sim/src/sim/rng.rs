//! The one pseudo-random generator of host-sim's campaigns (SplitMix64, Steele, Lea & Flood 2014):
//! seeded, so the noisy experiments (state chatter, sensor noise in the fault campaign) give the
//! same numbers on every run, without a dependency.

/// SplitMix64 state.
#[derive(Clone, Copy, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator started at `seed`.
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [−1, 1).
    pub fn uniform_pm1(&mut self) -> f64 {
        2.0 * self.uniform() - 1.0
    }

    /// Uniform integer in [−k, k] (`k` ≥ 0; the modulo bias is below 2⁻⁶⁰ for small `k`).
    pub fn symmetric(&mut self, k: u32) -> i64 {
        let span = 2 * u64::from(k) + 1;
        (self.next_u64() % span) as i64 - i64::from(k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The published first output for seed 0 (reference implementation by Vigna) and the mean and
    /// range of 1e5 uniforms on [−1, 1) (σ = 1/√3, so the mean is within 4·0.577/√1e5 ≈ 0.0073).
    /// The seed is fixed: measured mean 5.7e-4. The bound stays the 4σ statistical one (a
    /// statement about the generator, not about this seed's draw).
    #[test]
    fn matches_the_reference_and_is_uniform() {
        assert_eq!(SplitMix64::new(0).next_u64(), 0xe220_a839_7b1d_cdaf);
        let mut r = SplitMix64::new(7);
        let n = 100_000;
        let xs: Vec<f64> = (0..n).map(|_| r.uniform_pm1()).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.008, "{mean}");
        assert!(xs.iter().all(|x| (-1.0..1.0).contains(x)));
    }
}
