//! # A seeded pseudo-random generator
//!
//! hompm's only randomness: data layouts that the seeds describe as "random"
//! (TLS paper §5.3) and property-test-like sweeps in the report. SplitMix64
//! (Steele, Lea & Flood 2014) is tiny, fast and fully determined by its seed,
//! so the same seed gives bit-identical layouts on every machine.

/// SplitMix64.
#[derive(Debug, Clone)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator with the given seed.
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform number in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniform number in (a, b), never equal to either end.
    pub fn open_interval(&mut self, a: f64, b: f64) -> f64 {
        loop {
            let x = a + (b - a) * self.uniform();
            if x > a && x < b {
                return x;
            }
        }
    }
}
