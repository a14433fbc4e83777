//! Helpers shared by the integration tests.
#![allow(dead_code)]
use slither::model::Model;
use slither::problem;
use std::path::Path;

/// Model from inline TOML.
pub fn model(toml: &str) -> Model {
    let p = problem::parse(toml, Path::new("<inline>")).expect("valid inline problem");
    Model::new(&p)
}

/// Small deterministic generator (xorshift) for random test configurations.
pub struct Rng(pub u64);
impl Rng {
    /// Uniform in [-1, 1).
    pub fn sym(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}
