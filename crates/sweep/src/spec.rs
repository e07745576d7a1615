//! The sweep file (TOML) and its validation: every problem names its field.

use std::path::Path;

use serde::Deserialize;
use sim::overrides::RunOverrides;

use crate::{Input, Mode, Sampler, SweepError};

/// Most samples one sweep may have (a guard against a grid's product exploding).
pub const MAX_SAMPLES: usize = 1_000_000;

/// The file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct File {
    pub scene: String,
    #[serde(default)]
    pub samples: Option<usize>,
    #[serde(default)]
    pub seed: Option<u64>,
    pub metrics: Vec<String>,
    #[serde(default)]
    pub run: RunSection,
    pub vary: Vec<VaryFile>,
}

/// `[run]`: the settings `wearsim run` takes as flags.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RunSection {
    pub cycles: Option<u32>,
    pub stages: Option<u32>,
    pub rtol: Option<f64>,
    pub cycles_per_stage: Option<u32>,
    pub trajectories: Option<u32>,
    pub wear_tolerance: Option<f64>,
    pub max_steps: Option<usize>,
    pub max_wall_time: Option<f64>,
}

/// One path or several set to the same value.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub(crate) enum Paths {
    One(String),
    Many(Vec<String>),
}

/// `[[vary]]` as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct VaryFile {
    pub path: Paths,
    pub name: Option<String>,
    pub values: Option<Vec<f64>>,
    pub distribution: Option<String>,
    pub low: Option<f64>,
    pub high: Option<f64>,
    pub mean: Option<f64>,
    pub sd: Option<f64>,
    pub median: Option<f64>,
    pub sigma: Option<f64>,
}

fn bad(
    field: impl Into<String>,
    value: impl std::fmt::Debug,
    reason: impl Into<String>,
) -> SweepError {
    SweepError::Field {
        field: field.into(),
        value: format!("{value:?}"),
        reason: reason.into(),
    }
}

/// Parse the file text (`origin` names it in errors).
pub(crate) fn parse(text: &str, origin: &str) -> Result<File, SweepError> {
    let de = toml::Deserializer::parse(text).map_err(|source| SweepError::Toml {
        origin: origin.to_string(),
        source: Box::new(source),
    })?;
    serde_path_to_error::deserialize(de).map_err(|e| SweepError::Type {
        origin: origin.to_string(),
        field: e.path().to_string(),
        source: Box::new(e.into_inner()),
    })
}

impl RunSection {
    /// The run settings of every sample (only the stage count is checked here).
    pub(crate) fn overrides(&self) -> Result<RunOverrides, SweepError> {
        // Every value is checked with the scene's rules once the base scene is known
        // (`check_run_table`). The scene refuses more, but only once a sample is built, and the scene's validation
        // of an enormous count itself takes forever (it lists every stage's file names): so
        // here, up front, by this field.
        let most = scene::limits::MAX_WEAR_STAGES;
        if let Some(n) = self.stages.filter(|n| *n > most) {
            return Err(bad("run.stages", n, format!("at most {most}")));
        }
        Ok(RunOverrides {
            cycles: self.cycles,
            stages: self.stages,
            rtol: self.rtol,
            cycles_per_stage: self.cycles_per_stage,
            trajectories: self.trajectories,
            wear_tolerance: self.wear_tolerance,
            // The samples already run on the machine's cores: one thread each.
            threads: Some(1),
            max_steps: self.max_steps,
            max_wall_time: self.max_wall_time,
        })
    }
}

fn positive_finite(field: String, v: Option<f64>, what: &str) -> Result<f64, SweepError> {
    match v {
        None => Err(bad(field, "missing", format!("{what} is required"))),
        Some(x) if x.is_finite() && x > 0.0 => Ok(x),
        Some(x) => Err(bad(field, x, "must be a finite positive number")),
    }
}

fn finite(field: String, v: Option<f64>, what: &str) -> Result<f64, SweepError> {
    match v {
        None => Err(bad(field, "missing", format!("{what} is required"))),
        Some(x) if x.is_finite() => Ok(x),
        Some(x) => Err(bad(field, x, "must be finite")),
    }
}

impl VaryFile {
    /// The validated input `k`.
    pub(crate) fn input(&self, k: usize) -> Result<Input, SweepError> {
        let f = |key: &str| format!("vary[{k}].{key}");
        let paths = match &self.path {
            Paths::One(p) => vec![p.clone()],
            Paths::Many(p) => p.clone(),
        };
        if paths.is_empty() {
            return Err(bad(f("path"), "[]", "give at least one field path"));
        }
        for p in &paths {
            if crate::path::segments(p).is_none() {
                return Err(bad(
                    f("path"),
                    p,
                    "not a dotted field path (e.g. clearance_joints.A.clearance)",
                ));
            }
        }
        let name = self.name.clone().unwrap_or_else(|| paths.join("+"));
        if name.is_empty() || name.contains(['\n', '\r']) {
            return Err(bad(f("name"), &name, "must be a non-empty single line"));
        }
        if name.chars().any(char::is_control) {
            return Err(bad(
                f("name"),
                &name,
                "must not contain control characters (it names a column of samples.csv and the \
                 page)",
            ));
        }
        let given: Vec<&str> = [
            ("low", self.low),
            ("high", self.high),
            ("mean", self.mean),
            ("sd", self.sd),
            ("median", self.median),
            ("sigma", self.sigma),
        ]
        .iter()
        .filter(|(_, v)| v.is_some())
        .map(|(n, _)| *n)
        .collect();
        let allow = |keys: &[&str]| -> Result<(), SweepError> {
            match given.iter().find(|g| !keys.contains(g)) {
                Some(g) => Err(bad(
                    f(g),
                    "given",
                    format!(
                        "does not apply here (allowed: {})",
                        if keys.is_empty() {
                            "none".to_string()
                        } else {
                            keys.join(", ")
                        }
                    ),
                )),
                None => Ok(()),
            }
        };
        let sampler = match (&self.values, self.distribution.as_deref()) {
            (Some(_), Some(d)) => {
                return Err(bad(
                    f("distribution"),
                    d,
                    "give either values (a grid) or a distribution, not both",
                ));
            }
            (None, None) => {
                return Err(bad(
                    f("values"),
                    "missing",
                    "give values (a grid) or a distribution (uniform, normal, log-normal)",
                ));
            }
            (Some(values), None) => {
                allow(&[])?;
                if values.is_empty() {
                    return Err(bad(f("values"), "[]", "give at least one value"));
                }
                if let Some(v) = values.iter().find(|v| !v.is_finite()) {
                    return Err(bad(f("values"), v, "values must be finite"));
                }
                Sampler::Grid(values.clone())
            }
            (None, Some("uniform")) => {
                allow(&["low", "high"])?;
                let low = finite(f("low"), self.low, "low")?;
                let high = finite(f("high"), self.high, "high")?;
                if high <= low {
                    return Err(bad(f("high"), high, format!("must exceed low = {low}")));
                }
                Sampler::Uniform { low, high }
            }
            (None, Some("normal")) => {
                allow(&["mean", "sd"])?;
                Sampler::Normal {
                    mean: finite(f("mean"), self.mean, "mean")?,
                    sd: positive_finite(f("sd"), self.sd, "sd")?,
                }
            }
            (None, Some("log-normal")) => {
                allow(&["median", "sigma"])?;
                Sampler::LogNormal {
                    median: positive_finite(f("median"), self.median, "median")?,
                    sigma: positive_finite(f("sigma"), self.sigma, "sigma (of ln x)")?,
                }
            }
            (None, Some(other)) => {
                return Err(bad(
                    f("distribution"),
                    other,
                    "unknown; use uniform, normal or log-normal",
                ));
            }
        };
        if let Some((key, value, reason)) = unbounded_draws(&sampler) {
            return Err(bad(f(key), value, reason));
        }
        Ok(Input {
            name,
            paths,
            sampler,
        })
    }
}

/// Where `sampler`'s draws can be infinite (uniform: `high − low` overflows; normal and
/// log-normal: draws reach [`Sampler::largest_z`] deviations): the field that makes them so,
/// its value and why.
fn unbounded_draws(sampler: &Sampler) -> Option<(&'static str, f64, String)> {
    let z = Sampler::largest_z();
    match *sampler {
        Sampler::Uniform { low, high } if !(high - low).is_finite() => Some((
            "high",
            high,
            format!("high − low overflows (low = {low}): draws would be infinite"),
        )),
        Sampler::Normal { mean, sd } if !(mean.abs() + sd * z).is_finite() => Some((
            "sd",
            sd,
            format!("draws reach mean ± {z:.2}·sd (mean = {mean}), beyond the largest number"),
        )),
        Sampler::LogNormal { median, sigma } if !(median * (sigma * z).exp()).is_finite() => {
            Some((
                "sigma",
                sigma,
                format!(
                    "draws reach median·exp({z:.2}·sigma) (median = {median}), beyond the largest number"
                ),
            ))
        }
        _ => None,
    }
}

/// The sampling mode of validated inputs: all grids (full factorial) or all distributions.
pub(crate) fn mode(file: &File, inputs: &[Input]) -> Result<Mode, SweepError> {
    if inputs.is_empty() {
        return Err(bad("vary", "[]", "give at least one [[vary]] field"));
    }
    let grids = inputs
        .iter()
        .filter(|i| matches!(i.sampler, Sampler::Grid(_)))
        .count();
    if grids == inputs.len() {
        if let Some(n) = file.samples {
            return Err(bad(
                "samples",
                n,
                "a grid sweep runs every combination of its values; samples is for distributions",
            ));
        }
        if let Some(s) = file.seed {
            return Err(bad(
                "seed",
                s,
                "a grid sweep draws nothing; seed is for distributions",
            ));
        }
        let mut total: usize = 1;
        for (k, i) in inputs.iter().enumerate() {
            if let Sampler::Grid(v) = &i.sampler {
                total = total
                    .checked_mul(v.len())
                    .filter(|t| *t <= MAX_SAMPLES)
                    .ok_or_else(|| {
                        bad(
                            format!("vary[{k}].values"),
                            v.len(),
                            format!("the grid exceeds {MAX_SAMPLES} samples"),
                        )
                    })?;
            }
        }
        return Ok(Mode::Grid { samples: total });
    }
    if grids > 0 {
        let k = inputs
            .iter()
            .position(|i| matches!(i.sampler, Sampler::Grid(_)))
            .unwrap_or(0);
        return Err(bad(
            format!("vary[{k}].values"),
            "grid",
            "a sweep is either a grid (every input has values) or random (every input has a distribution)",
        ));
    }
    let samples = match file.samples {
        None => {
            return Err(bad(
                "samples",
                "missing",
                "a random sweep needs a sample count",
            ));
        }
        Some(n) if n == 0 || n > MAX_SAMPLES => {
            return Err(bad("samples", n, format!("must be 1 to {MAX_SAMPLES}")));
        }
        Some(n) => n,
    };
    let seed = file.seed.ok_or_else(|| {
        bad(
            "seed",
            "missing",
            "a random sweep needs a seed (its rows depend on it only)",
        )
    })?;
    Ok(Mode::Random { samples, seed })
}

/// The base scene: a built-in name or a file relative to the sweep file's folder, as a merged
/// table, and the name runs are filed under.
pub(crate) fn base_scene(
    spec: &str,
    dir: Option<&Path>,
) -> Result<(String, toml::Table), SweepError> {
    scene::load_named(spec, dir, lgres::scenes::BUILTINS).map_err(|e| match e {
        scene::LoadError::NotFound(_) => bad(
            "scene",
            spec,
            "no built-in scene and no file of this name (relative to the sweep file)",
        ),
        scene::LoadError::Scene(e) => e.into(),
    })
}
