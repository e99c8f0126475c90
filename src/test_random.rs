//! Tests: a small deterministic generator (xorshift64), so that a test's
//! made-up inputs are the same on every run and machine.

/// Numbers from a seed, the same on every run.
pub struct Random(u64);

impl Random {
    pub fn new(seed: u64) -> Random {
        // Xorshift never leaves zero.
        Random(seed | 1)
    }

    /// The next 64 bits.
    pub fn bits(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// A number below `n` (not 0).
    pub fn below(&mut self, n: u64) -> u64 {
        self.bits() % n
    }
}
