//! A validated sweep ([`Sweep`]) from its file, its plan for workers elsewhere, and one
//! sample's run.

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::time::Instant;

use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;
use scene::SceneError;
use serde::{Deserialize, Serialize};
use sim::RunError;
use sim::overrides::RunOverrides;

use crate::definition::{Input, Mode, Sampler};
use crate::error::{SampleError, SweepError};
use crate::life_columns::LifeColumns;
use crate::row::{FIXED_COLUMNS, Row, Status, number};
use crate::{path, spec};

/// The whole numbers an integer scene field holds: its Rust type's range (within TOML's `i64`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Whole {
    min: i64,
    max: i64,
}

impl Whole {
    /// `value` as the field's integer. Err: why not, for "`path = value: why`"; a fraction or
    /// an out-of-range value is refused, not rounded or saturated (a sweep of `run.cycles =
    /// 2.5` must not quietly run 3 cycles, nor `1e19` cells become `i64::MAX`).
    fn of(self, value: f64) -> Result<i64, String> {
        /// 2⁶³: the first float beyond `i64` (`i64::MAX as f64` rounds up to it).
        const LIMIT: f64 = 9_223_372_036_854_775_808.0;
        if value.fract() != 0.0 {
            return Err("must be a whole number".into());
        }
        if (-LIMIT..LIMIT).contains(&value) {
            // Exact: whole and inside i64.
            let n = value as i64;
            if (self.min..=self.max).contains(&n) {
                return Ok(n);
            }
        }
        Err(format!(
            "beyond the range of the integer field ({} to {})",
            self.min, self.max
        ))
    }
}

/// Whether the scene deserializes with `value` at `path` and the rest as in `base`.
fn accepts(base: &toml::Table, path: &str, value: toml::Value) -> bool {
    let mut table = base.clone();
    path::set(&mut table, path, value).is_ok()
        && toml::Value::Table(table).try_into::<scene::Scene>().is_ok()
}

/// The range of the integer scene field at `path`; `None` for a float (or not a number) field.
/// The scene's deserialization decides, not the base scene's TOML: a field left to its default
/// has no value to look at, and `inertia = 1` is a float field spelled as an integer. A field
/// is an integer one if it takes an integer but not the same value as a float (probing a few
/// values, as validation inside the deserialization may refuse one); its range is the widest
/// of the Rust integer types' it takes.
fn whole_range(base: &toml::Table, path: &str) -> Option<Whole> {
    use toml::Value::{Float, Integer};
    let taken = [1, 0, 2].into_iter().find_map(|v| {
        if accepts(base, path, Float(v as f64)) {
            Some(None)
        } else {
            accepts(base, path, Integer(v)).then_some(Some(v))
        }
    })??;
    let widest = |bounds: [i64; 6]| {
        bounds
            .into_iter()
            .find(|b| accepts(base, path, Integer(*b)))
            .unwrap_or(taken)
    };
    Some(Whole {
        min: widest([
            i64::MIN,
            i32::MIN.into(),
            i16::MIN.into(),
            i8::MIN.into(),
            0,
            1,
        ]),
        max: widest([
            i64::MAX,
            u32::MAX.into(),
            i32::MAX.into(),
            u16::MAX.into(),
            i16::MAX.into(),
            u8::MAX.into(),
        ]),
    })
}

/// Check input `k`'s values for its integer field `path` before any sample runs: every grid
/// value must be a whole number in range, and a distribution (whose draws are fractions) is
/// refused.
fn check_whole(k: usize, input: &Input, path: &str, w: Whole) -> Result<(), SweepError> {
    let draws = match &input.sampler {
        Sampler::Grid(values) => {
            for (j, v) in values.iter().enumerate() {
                w.of(*v).map_err(|why| SweepError::Field {
                    field: format!("vary[{k}].values[{j}]"),
                    value: number(*v),
                    reason: format!("{path} = {}: {why}", number(*v)),
                })?;
            }
            return Ok(());
        }
        Sampler::Uniform { .. } => "uniform",
        Sampler::Normal { .. } => "normal",
        Sampler::LogNormal { .. } => "log-normal",
    };
    Err(SweepError::Field {
        field: format!("vary[{k}].distribution"),
        value: format!("{draws:?}"),
        reason: format!(
            "{path} is an integer field ({} to {}) and a {draws} draw is not a whole number: \
             give its values as a grid",
            w.min, w.max
        ),
    })
}

/// Largest sweep file read, bytes (a grid of [`MAX_SAMPLES`] values fits twice over):
/// a longer one (a link to `/dev/zero`, a pipe that never ends) is refused, not read on.
pub const MAX_SWEEP_FILE_BYTES: u64 = 64 << 20;

/// The text of the sweep file at `path`, at most [`MAX_SWEEP_FILE_BYTES`] read (a pipe is
/// read too: `wearsim sweep <(…)`). Text that is not UTF-8 is refused naming its line.
fn read_text(path: &Path) -> Result<String, SweepError> {
    use std::io::Read;
    let io = |source| SweepError::Io {
        path: path.to_path_buf(),
        source,
    };
    let invalid = |why: String| io(std::io::Error::new(std::io::ErrorKind::InvalidData, why));
    let too_large = || {
        invalid(format!(
            "larger than {} MiB: not a sweep file",
            MAX_SWEEP_FILE_BYTES >> 20
        ))
    };
    let file = std::fs::File::open(path).map_err(io)?;
    if file.metadata().map_err(io)?.len() > MAX_SWEEP_FILE_BYTES {
        return Err(too_large());
    }
    let mut bytes = Vec::new();
    file.take(MAX_SWEEP_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > MAX_SWEEP_FILE_BYTES {
        return Err(too_large());
    }
    String::from_utf8(bytes).map_err(|e| {
        let (bytes, at) = (e.as_bytes(), e.utf8_error().valid_up_to());
        let line_start = bytes[..at]
            .iter()
            .rposition(|b| *b == b'\n')
            .map_or(0, |i| i + 1);
        let line = 1 + bytes[..at].iter().filter(|b| **b == b'\n').count();
        let column = 1 + at - line_start;
        invalid(format!("line {line}, column {column}: not UTF-8 text"))
    })
}

/// What a sweep's tasks need, with nothing read from disk: the file's text and the base scene
/// as a merged table in TOML, so a worker on another machine rebuilds the same [`Sweep`].
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Plan {
    name: String,
    text: String,
    scene_name: String,
    base: String,
}

/// A validated sweep.
#[derive(Debug, Clone)]
pub struct Sweep {
    /// Name (the file's stem): the default output folder `out/sweep/<name>`.
    pub name: String,
    /// Name the runs are filed under (the base scene's).
    pub scene_name: String,
    /// Varied inputs, in file order.
    pub inputs: Vec<Input>,
    /// Metric paths into `summary.json`.
    pub metrics: Vec<String>,
    /// Grid or random.
    pub mode: Mode,
    /// Run settings applied to every sample.
    pub overrides: RunOverrides,
    base: toml::Table,
    text: String,
    /// Each varied path's integer range (`None`: a float field), found when the sweep is built.
    wholes: HashMap<String, Option<Whole>>,
    /// With a clearance limit in the base scene: where the rows keep each wearing joint's
    /// cycles to it ([`crate::life`]).
    pub life: Option<LifeColumns>,
}

/// The `[run]` table against the base scene, with the scene's rules and the run's
/// ([`sim::scene_as_run`]), before any sample: a bad setting would fail every row. The
/// error names the table's field (`run.max_wall_time`) and the scene field it sets.
fn check_run_table(
    overrides: &RunOverrides,
    base: &toml::Table,
    scene_name: &str,
) -> Result<(), SweepError> {
    let scene = scene::from_table(base.clone(), scene_name)?;
    let origin = format!("{scene_name} with the sweep file's [run] table");
    let refused = match overrides.apply(scene, &origin) {
        Ok(scene) => match sim::scene_as_run(scene_name, &scene, &overrides.run_options()) {
            Ok(_) => return Ok(()),
            Err(RunError::Scene(e)) => e,
            Err(RunError::Trajectories {
                trajectories,
                cycles_per_stage,
            }) => {
                // K as the samples run it: the table's, else the run's default (not the
                // scene's, which sets only what a stage stands for).
                let k_from = if overrides.cycles_per_stage.is_some() {
                    "this table's run.cycles_per_stage"
                } else {
                    "the run's default; set run.cycles_per_stage in this table"
                };
                return Err(SweepError::Field {
                    field: "run.trajectories".into(),
                    value: trajectories.to_string(),
                    reason: format!(
                        "must divide the simulated cycles per wear stage K = {cycles_per_stage} \
                         ({k_from}): each trajectory simulates whole drive cycles"
                    ),
                });
            }
            Err(other) => {
                return Err(SweepError::Field {
                    field: "run".into(),
                    value: "[run]".into(),
                    reason: other.to_string(),
                });
            }
        },
        Err(e) => e,
    };
    // Name the table's field when the scene refuses what it set.
    if let SceneError::Invalid { issues, .. } = &refused {
        for issue in issues {
            let field = RunOverrides::SCENE_FIELDS
                .iter()
                .find(|(_, path)| *path == issue.path)
                .map(|(field, _)| *field);
            if let Some(field) = field {
                return Err(SweepError::Field {
                    field: format!("run.{field}"),
                    value: issue.value.clone(),
                    reason: format!("{} (it sets the scene's {})", issue.reason, issue.path),
                });
            }
        }
    }
    Err(refused.into())
}

/// Refuses an input whose path a run setting replaces in every sample
/// ([`RunOverrides::replaced_fields`]): the row would record the varied value beside results of
/// another one.
fn check_not_replaced(inputs: &[Input], overrides: &RunOverrides) -> Result<(), SweepError> {
    let replaced = overrides.replaced_fields();
    for (k, input) in inputs.iter().enumerate() {
        for p in &input.paths {
            let at = path::segments(p);
            let Some((field, scene_path)) = replaced
                .iter()
                .find(|(_, scene_path)| at == path::segments(scene_path))
            else {
                continue;
            };
            let by = if *field == "trajectories" && overrides.trajectories.is_none() {
                "the run's default trajectories (set run.cycles_per_stage in the [run] table to \
                 run the scene's)"
                    .to_string()
            } else {
                format!("the [run] table's {field}")
            };
            return Err(SweepError::Field {
                field: format!("vary[{k}].path"),
                value: format!("{p:?}"),
                reason: format!(
                    "{scene_path} is set by {by} in every sample, so the varied value would not \
                     run: vary it or set it, not both"
                ),
            });
        }
    }
    Ok(())
}

/// Top-level keys of `summary.json`: a metric must start with one.
const SUMMARY_KEYS: [&str; 9] = [
    "scene",
    "description",
    "response_body",
    "period_s",
    "transient_window_s",
    "reference",
    "response",
    "wear",
    "worn_response",
];

impl Sweep {
    /// Read and validate a sweep file; its base scene may be a file relative to it.
    pub fn from_path(path: &Path) -> Result<Sweep, SweepError> {
        let text = read_text(path)?;
        let name = path
            .file_stem()
            .map_or_else(|| "sweep".to_string(), |s| s.to_string_lossy().into_owned());
        let file = spec::parse(&text, &path.display().to_string())?;
        let (scene_name, base) = spec::base_scene(&file.scene, path.parent())?;
        Self::build(name, text, file, scene_name, base)
    }

    /// Parse and validate sweep text; its base scene must be built in.
    pub fn from_str(text: &str, name: &str) -> Result<Sweep, SweepError> {
        let file = spec::parse(text, name)?;
        let (scene_name, base) = spec::base_scene(&file.scene, None)?;
        Self::build(name.to_string(), text.to_string(), file, scene_name, base)
    }

    /// Rebuild a sweep from [`Sweep::plan`]'s text (on a worker: reads no file).
    pub fn from_plan(plan: &str) -> Result<Sweep, SweepError> {
        let plan: Plan = serde_json::from_str(plan)?;
        let file = spec::parse(&plan.text, &plan.name)?;
        let base: toml::Table = toml::from_str(&plan.base).map_err(|source| SweepError::Toml {
            origin: format!("{} (plan's base scene)", plan.name),
            source: Box::new(source),
        })?;
        Self::build(plan.name, plan.text, file, plan.scene_name, base)
    }

    /// Everything a task needs to rebuild this sweep, as text (see [`Sweep::from_plan`]).
    pub fn plan(&self) -> String {
        let plan = Plan {
            name: self.name.clone(),
            text: self.text.clone(),
            scene_name: self.scene_name.clone(),
            // A table of strings, numbers, booleans, arrays and tables always serializes.
            base: toml::to_string(&self.base).unwrap_or_default(),
        };
        serde_json::to_string(&plan).unwrap_or_default()
    }

    fn build(
        name: String,
        text: String,
        file: spec::File,
        scene_name: String,
        base: toml::Table,
    ) -> Result<Sweep, SweepError> {
        let overrides = file.run.overrides()?;
        check_run_table(&overrides, &base, &scene_name)?;
        let inputs = file
            .vary
            .iter()
            .enumerate()
            .map(|(k, v)| v.input(k))
            .collect::<Result<Vec<_>, _>>()?;
        let mode = spec::mode(&file, &inputs)?;
        if file.metrics.is_empty() {
            return Err(SweepError::Field {
                field: "metrics".into(),
                value: "[]".into(),
                reason: "give at least one summary.json path".into(),
            });
        }
        for (k, m) in file.metrics.iter().enumerate() {
            if m.chars().any(char::is_control) {
                return Err(SweepError::Field {
                    field: format!("metrics[{k}]"),
                    value: format!("{m:?}"),
                    reason: "must not contain control characters (it names a column)".into(),
                });
            }
            let first = path::segments(m).and_then(|s| s.into_iter().next());
            if !first.is_some_and(|f| SUMMARY_KEYS.contains(&f.as_str())) {
                return Err(SweepError::Field {
                    field: format!("metrics[{k}]"),
                    value: format!("{m:?}"),
                    reason: format!(
                        "not a summary.json path (it starts with one of {})",
                        SUMMARY_KEYS.join(", ")
                    ),
                });
            }
        }
        // With a clearance limit: each wearing joint's cycles to it and their noise too.
        let base_scene = scene::from_table(base.clone(), &scene_name)?;
        let mut metrics = file.metrics.clone();
        let life = LifeColumns::of(&base_scene, &mut metrics);
        let mut names: Vec<&str> = inputs.iter().map(|i| i.name.as_str()).collect();
        names.extend(metrics.iter().map(String::as_str));
        names.extend(FIXED_COLUMNS);
        for (k, n) in names.iter().enumerate() {
            if names[..k].contains(n) {
                return Err(SweepError::Field {
                    field: "vary.name / metrics".into(),
                    value: format!("{n:?}"),
                    reason: "two columns of the same name".into(),
                });
            }
        }
        check_not_replaced(&inputs, &overrides)?;
        let mut wholes = HashMap::new();
        for (k, input) in inputs.iter().enumerate() {
            for p in &input.paths {
                let whole = whole_range(&base, p);
                if let Some(w) = whole {
                    check_whole(k, input, p, w)?;
                }
                wholes.insert(p.clone(), whole);
            }
        }
        let sweep = Sweep {
            name,
            scene_name,
            inputs,
            metrics,
            mode,
            overrides,
            base,
            text,
            wholes,
            life,
        };
        // Every varied path must exist in the scene: set typical values and deserialize.
        for (k, input) in sweep.inputs.iter().enumerate() {
            let mut table = sweep.base.clone();
            sweep
                .edit(&mut table, input, input.sampler.typical())
                .map_err(|e| SweepError::Field {
                    field: format!("vary[{k}].path"),
                    value: format!("{:?}", input.paths),
                    reason: e.to_string(),
                })?;
            let checked: Result<scene::Scene, _> =
                serde_path_to_error::deserialize(toml::Value::Table(table));
            if let Err(e) = checked {
                let at = e.path().to_string();
                return Err(SweepError::Field {
                    field: format!("vary[{k}].path"),
                    value: format!("{:?}", input.paths),
                    reason: format!("in the scene, {at}: {}", e.into_inner()),
                });
            }
        }
        Ok(sweep)
    }

    /// What every sample runs with besides its inputs, as a fingerprint (16 hex digits): the
    /// base scene (merged with its `extends`) and the `[run]` settings. Each row of the rows
    /// file records it, so a resume whose base scene or `[run]` table changed is refused
    /// instead of keeping rows that ran with other settings ([`table::read_rows`]).
    ///
    /// [`table::read_rows`]: crate::table::read_rows
    pub fn settings_id(&self) -> String {
        // FNV-1a: stable across builds and platforms (std's hasher is not).
        let text = format!(
            "{}\n[run]\n{:?}",
            toml::to_string(&self.base).unwrap_or_default(),
            self.overrides
        );
        let hash = text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        });
        format!("{hash:016x}")
    }

    /// Number of samples.
    pub fn samples(&self) -> usize {
        match self.mode {
            Mode::Grid { samples } | Mode::Random { samples, .. } => samples,
        }
    }

    /// Input values of sample `index`, in input order; they depend on the file and `index`
    /// only. They are not rounded: a fraction drawn for an integer field fails its sample.
    pub fn input_values(&self, index: usize) -> Vec<f64> {
        match self.mode {
            Mode::Grid { .. } => {
                let mut rest = index;
                let mut values = vec![0.0; self.inputs.len()];
                for (slot, input) in values.iter_mut().zip(&self.inputs).rev() {
                    if let Sampler::Grid(v) = &input.sampler {
                        *slot = v[rest % v.len()];
                        rest /= v.len();
                    }
                }
                values
            }
            Mode::Random { seed, .. } => {
                let mut rng = ChaCha20Rng::seed_from_u64(seed);
                rng.set_stream(index as u64);
                self.inputs
                    .iter()
                    .map(|i| i.sampler.draw(&mut rng))
                    .collect()
            }
        }
    }

    /// The integer range of the field at `path`, or `None` for a float field. A path the sweep
    /// was not built with (the inputs are public, so a caller may change them) is probed now.
    fn whole(&self, path: &str) -> Option<Whole> {
        match self.wholes.get(path) {
            Some(w) => *w,
            None => whole_range(&self.base, path),
        }
    }

    /// Set `value` at every path of `input`: an integer field gets the integer it is (a
    /// fraction or an out-of-range value is refused, naming the field and the value).
    fn edit(&self, table: &mut toml::Table, input: &Input, value: f64) -> Result<(), SampleError> {
        for p in &input.paths {
            let refuse = |reason: String| SampleError::Value {
                path: p.clone(),
                value: number(value),
                reason,
            };
            if !value.is_finite() {
                return Err(refuse("must be finite".into()));
            }
            let v = match self.whole(p) {
                Some(w) => toml::Value::Integer(w.of(value).map_err(refuse)?),
                None => toml::Value::Float(value),
            };
            path::set(table, p, v).map_err(|reason| SampleError::Edit {
                path: p.clone(),
                reason,
            })?;
        }
        Ok(())
    }

    /// The scene of sample `index`, with the run settings applied and validated.
    pub fn scene(&self, index: usize) -> Result<scene::ValidScene, SampleError> {
        let mut table = self.base.clone();
        for (input, v) in self.inputs.iter().zip(self.input_values(index)) {
            self.edit(&mut table, input, v)?;
        }
        let origin = format!("{} sample {index}", self.name);
        let scene = scene::from_table(table, &origin)?;
        Ok(self.overrides.apply(
            scene,
            &format!("{origin} with the sweep file's [run] table"),
        )?)
    }

    /// Run sample `index` (the whole of a Dask task): never panics, never fails; a sample
    /// that cannot run is a row with status `failed` and the error.
    pub fn run_sample(&self, index: usize) -> Row {
        let started = Instant::now();
        let inputs = self.input_values(index);
        let result = catch_unwind(AssertUnwindSafe(|| self.metrics_of(index)));
        let (metrics, status, error) = match result {
            Ok(Ok(m)) => (m, Status::Ok, String::new()),
            Ok(Err(e)) => (
                vec![None; self.metrics.len()],
                Status::Failed,
                e.to_string(),
            ),
            Err(panic) => {
                let what = panic
                    .downcast_ref::<&str>()
                    .map(ToString::to_string)
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown".into());
                (
                    vec![None; self.metrics.len()],
                    Status::Failed,
                    format!("internal error (panic): {what}"),
                )
            }
        };
        Row {
            sample: index,
            inputs,
            metrics,
            status,
            error,
            wall_time_s: started.elapsed().as_secs_f64(),
        }
    }

    fn metrics_of(&self, index: usize) -> Result<Vec<Option<f64>>, SampleError> {
        let scene = self.scene(index)?;
        let outcome = sim::run_scene(
            &self.scene_name,
            &scene,
            &self.overrides.run_options(),
            &mut (),
        )?;
        self.metrics_of_summary(&outcome.summary)
    }

    /// The metrics of a run's `summary` (as in `summary.json`), in metric order; `None` where
    /// the summary holds no number (`null`). A NaN or infinity is an error naming the metric,
    /// so its sample is a failed row, never `ok` with a number that is none (`summary.json`
    /// writes it as `null`, read as "no value": [`path::summary_value`] keeps it).
    pub fn metrics_of_summary<T: Serialize + ?Sized>(
        &self,
        summary: &T,
    ) -> Result<Vec<Option<f64>>, SampleError> {
        let summary = path::summary_value(summary)?;
        self.metrics
            .iter()
            .map(|m| match path::number(&summary, m) {
                Ok(Some(value)) if !value.is_finite() => Err(SampleError::NotFinite {
                    path: m.clone(),
                    value,
                }),
                Ok(v) => Ok(v),
                Err(reason) => Err(SampleError::Metric {
                    path: m.clone(),
                    reason,
                }),
            })
            .collect()
    }

    /// Run sample `index`, checking it exists.
    pub fn try_run_sample(&self, index: usize) -> Result<Row, SweepError> {
        if index >= self.samples() {
            return Err(SweepError::NoSuchSample {
                index,
                samples: self.samples(),
            });
        }
        Ok(self.run_sample(index))
    }
}
