//! `wearsim precision`: the work–precision sweep ([`analysis::precision`]) with a line per
//! run.

use std::path::Path;

use crate::error::CliError;
use crate::load::{Loaded, load};
use crate::overrides::Overrides;

/// Settings of `wearsim precision` beyond the scene.
pub struct PrecisionArgs<'a> {
    /// Integrators to sweep (empty: all).
    pub methods: &'a [scene::Integrator],
    /// Relative tolerances (empty: the default decades).
    pub rtols: &'a [f64],
    /// Timed repeats per run and variant.
    pub repeats: usize,
    /// Simulated time, s (`None`: one drive period).
    pub duration: Option<f64>,
    /// End of the start-up window of error (a), s.
    pub start_up: f64,
    /// Accepted-step budget per run.
    pub max_steps: usize,
}

/// `wearsim precision`: runs [`analysis::precision`], one line per run, writes the report.
pub fn run(spec: &str, args: &PrecisionArgs<'_>, o: &Overrides) -> Result<(), CliError> {
    let Loaded { name, scene } = load(spec, o)?;
    let out = o
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join("precision"));
    let _lock = output::files::FolderLock::take(&out)?;
    let mut options = analysis::precision::PrecisionOptions {
        repeats: args.repeats,
        duration: args.duration,
        start_up: args.start_up,
        max_steps: args.max_steps,
        ..Default::default()
    };
    if !args.methods.is_empty() {
        options.methods = args.methods.to_vec();
    }
    if !args.rtols.is_empty() {
        options.rtols = args.rtols.to_vec();
    }
    let started = std::time::Instant::now();
    let report =
        analysis::precision::run_sweep(&name, &scene, &options, &mut |event| match event {
            analysis::precision::Event::Start(method, rtol, what) => {
                errln!(
                    "[{:>6.0} s] {method:<9} rtol {rtol:.0e}: {what}",
                    started.elapsed().as_secs_f64()
                );
            }
            analysis::precision::Event::Row(row) => match row.errors() {
                Some(e) => errln!(
                    "           {} steps, {:.3} s; start-up error {:.2e} m, cycle error {:.2e}",
                    row.steps,
                    row.wall_s,
                    e.start_up_m(),
                    e.cycle_max()
                ),
                None => errln!("           {:?}", row.outcome),
            },
        })?;
    let files = report.write(&out)?;
    outln!("{}", report.markdown(None));
    outln!(
        "wrote {} files to {} in {:.1} s",
        files.len(),
        out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
