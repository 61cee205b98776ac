//! Shared pieces of the fuzz targets (`tests/fuzz.rs`, `tests/fuzz_surfaces.rs`): a seeded
//! generator and the values numbers are replaced with.

/// A small deterministic generator (xorshift64*), so a seed reproduces a failure.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Values a number or a word of a scenario is replaced with.
pub const EXTREMES: &[&str] = &[
    "0",
    "0.0",
    "-0.0",
    "-1.0",
    "1",
    "1e300",
    "-1e300",
    "1e-300",
    "1e19",
    "1e12",
    "1e-12",
    "3.4e38",
    "1e17",
    "-1e17",
    "nan",
    "inf",
    "-inf",
    "\"x\"",
    "true",
    "[]",
    "[1.0]",
    "[1.0, 2.0, 3.0, 4.0]",
    "{}",
    "99999999999999999999",
    "\"locked\"",
    "\"free\"",
    "\"assembled\"",
    "6.5",
    "720.0",
    "1e5",
    "2e-16",
    "\"generalized-alpha\"",
];
