//! `wearsim stress`: the stress battery ([`analysis::stress`]) with a line per case.

use std::path::Path;

use crate::error::CliError;
use crate::overrides::Overrides;

/// `wearsim stress`: runs [`analysis::stress`], prints each case as it ends, writes the tables.
pub fn run(quick: bool, o: &Overrides) -> Result<(), CliError> {
    let out = o
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join("stress"));
    let _lock = output::files::FolderLock::take(&out)?;
    let options = analysis::stress::StressOptions {
        quick,
        ..Default::default()
    };
    let started = std::time::Instant::now();
    let results = analysis::stress::run_battery(&options, &mut |case, result| match result {
        None => err!("{:<24} ", case.name),
        Some(r) => errln!(
            "{} ({:.1} s) {}",
            r.outcome.label(),
            r.wall_time_s,
            r.outcome.detail()
        ),
    })
    .map_err(|e| match e {
        analysis::stress::StressError::Scene(e) => CliError::Scene(e),
        analysis::stress::StressError::Output(e) => CliError::Output(e),
    })?;
    let files = analysis::stress::write_report(&results, &out)?;
    out!("{}", analysis::stress::markdown(&results));
    let failed = results
        .iter()
        .filter(|r| r.outcome.label() == "FAILED")
        .count();
    outln!(
        "{} case(s), {failed} failed; wrote {} files to {} in {:.1} s",
        results.len(),
        files.len(),
        out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
