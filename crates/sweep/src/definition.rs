//! What a sweep varies: its inputs, how their values are chosen, and grid or random.

use rand::Rng;
use rand_chacha::ChaCha20Rng;

/// How an input's values are chosen.
#[derive(Debug, Clone, PartialEq)]
pub enum Sampler {
    /// Grid values.
    Grid(Vec<f64>),
    /// Uniform on `[low, high)`.
    Uniform {
        /// Lower bound.
        low: f64,
        /// Upper bound.
        high: f64,
    },
    /// Normal.
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation.
        sd: f64,
    },
    /// Log-normal: `median · exp(sigma · z)`, `z` standard normal.
    LogNormal {
        /// Median (`exp μ`).
        median: f64,
        /// Standard deviation of `ln x`.
        sigma: f64,
    },
}

impl Sampler {
    /// A value typical of the input: for checking that its paths exist.
    pub(crate) fn typical(&self) -> f64 {
        match self {
            Sampler::Grid(v) => v.first().copied().unwrap_or(0.0),
            Sampler::Uniform { low, high } => 0.5 * (low + high),
            Sampler::Normal { mean, .. } => *mean,
            Sampler::LogNormal { median, .. } => *median,
        }
    }

    /// The largest standard normal [`Sampler::draw`] makes, in magnitude: its uniform `u1`
    /// is at least 2⁻⁵³, so `|z| ≤ √(−2 ln 2⁻⁵³) ≈ 8.57` (computed as the draw computes it).
    /// Validation uses it to refuse a distribution whose draws could overflow to infinity.
    pub(crate) fn largest_z() -> f64 {
        (-2.0 * (f64::EPSILON / 2.0).ln()).sqrt()
    }

    /// Draw a value from `rng` (one standard normal from two uniforms: Box–Muller).
    pub(crate) fn draw(&self, rng: &mut ChaCha20Rng) -> f64 {
        let mut normal = || {
            let u1 = 1.0 - rng.random::<f64>(); // (0, 1]: ln is finite
            let u2 = rng.random::<f64>();
            (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
        };
        match self {
            Sampler::Grid(v) => v.first().copied().unwrap_or(0.0),
            Sampler::Uniform { low, high } => low + (high - low) * rng.random::<f64>(),
            Sampler::Normal { mean, sd } => mean + sd * normal(),
            Sampler::LogNormal { median, sigma } => median * (sigma * normal()).exp(),
        }
    }
}

/// One varied input: a column of the rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Input {
    /// Column name (`name`, else the paths joined by `+`).
    pub name: String,
    /// Scene field paths set to the value.
    pub paths: Vec<String>,
    /// How values are chosen.
    pub sampler: Sampler,
}

/// Grid or random.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    /// Every combination of the inputs' values.
    Grid {
        /// Product of the value counts.
        samples: usize,
    },
    /// Independent draws.
    Random {
        /// Sample count.
        samples: usize,
        /// Seed.
        seed: u64,
    },
}
