//! `wearsim study`: runs the paper's studies through [`analysis::study`] with progress bars and
//! prints the trend verdicts; the numbers and figures are in `<out>/report.html` (and the same
//! in `<out>/report.md`).

use std::path::PathBuf;

use clap::builder::{PossibleValue, PossibleValuesParser};

use analysis::study::judge;
use analysis::study::{self, StudyError, StudyOptions};

use crate::error::CliError;
use crate::overrides::Overrides;
use crate::progress::StudyBars;

/// Output folder when `--out` is not given.
const DEFAULT_OUT: &str = "out/study";

/// The names `wearsim study` takes, each with its summary as help: every name
/// [`study::resolve`] accepts.
pub fn name_parser() -> PossibleValuesParser {
    PossibleValuesParser::new(
        study::choices()
            .into_iter()
            .map(|c| PossibleValue::new(c.name).help(c.summary)),
    )
}

/// Runs study `name`, one of [`study::choices`].
/// `stage_cycles`: drive cycles one wear stage stands for, instead of the scenes' (a quick look).
pub fn run(name: &str, stage_cycles: Option<f64>, o: &Overrides) -> Result<(), CliError> {
    if let Some(s) = o.stages {
        // Each study fixes its stages (the wear-stage study is the comparison of 1 and 2).
        return Err(StudyError::BadOption {
            field: "--stages",
            value: s.to_string(),
            reason: "does not apply to a study; the studies fix their wear stages",
        }
        .into());
    }
    let studies = study::resolve(name)?;
    let out = o.out.clone().unwrap_or_else(|| PathBuf::from(DEFAULT_OUT));
    // Lock the folder at once; the scene runs and the report go to a staging folder that
    // replaces `out` whole at the end, so an interrupted study leaves the previous one intact.
    let mut options = StudyOptions::new(&out);
    if let Some(k) = o.cycles_per_stage {
        options.cycles_per_stage = k;
    }
    if let Some(c) = o.cycles {
        options.response_cycles = c;
    }
    options.rtol = o.rtol;
    options.cycles_represented = stage_cycles;
    if let Some(j) = o.jobs {
        options.jobs = j.get();
    }
    // Every option checked before the folder is touched.
    options.check()?;
    let staged = output::files::StagedDir::begin_study(&out)?;
    options.out = staged.path().to_path_buf();
    outln!(
        "study {name}: {} response cycles per scene, K = {} cycles per wear stage, {} run(s) at \
         a time",
        options.response_cycles,
        options.cycles_per_stage,
        options.jobs
    );
    let bars = StudyBars::new();
    let (results, staged_report) = study::run_studies(&studies, &options, &bars)?;
    drop(bars);
    let out = staged.commit()?;
    let path = staged_report
        .strip_prefix(&options.out)
        .map_or(staged_report.clone(), |relative| out.join(relative));
    for r in &results.runs {
        let s = &r.outcome.summary;
        let forces: Vec<String> = s
            .response
            .joints
            .iter()
            .map(|j| match &j.normal_force_after_transient {
                Some(p) => format!("{} median peak {:.1} kN", j.name, p.cycle_median * 1e-3),
                None => format!("{} median peak n/a", j.name),
            })
            .collect();
        let substeps = s.wear.as_ref().map_or(String::new(), |w| {
            format!("; wear sub-steps {:?}", w.substeps_per_stage)
        });
        outln!(
            "  {:<18} {:>6.1} s  {}{substeps}",
            r.key,
            s.wall_time_s,
            forces.join(", ")
        );
    }
    for (t, _, _) in judge::trends(&results) {
        outln!(
            "  {}: {} — {} ({} of {} quantities grew, {} shrank)",
            t.study,
            t.claim,
            t.verdict,
            t.grew,
            t.total,
            t.shrank
        );
    }
    outln!(
        "report: {} and {} ({:.0} s of runs)",
        path.with_extension("html").display(),
        path.display(),
        results.wall_time_s
    );
    Ok(())
}
