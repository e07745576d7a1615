//! The analyses beyond one run, each engine apart from its rendering: the paper's studies and
//! their report ([`study`]: the runner, the trend verdicts, the report; the studies themselves
//! and the paper's numbers are the LGRES model's, in crate `lgres`), the work–precision sweep of
//! the integrators ([`precision`]) and the stress battery ([`stress`]). Every simulation they make
//! runs through `sim` (`sim::run_scene`, `sim::integrate`): no system is built here.
//!
//! ```no_run
//! use analysis::study::{self, StudyOptions};
//!
//! // The paper's wear-stages study on tiny runs: every scene's files under `out/study/<scene>/`
//! // and the report `out/study/report.md`.
//! let kinds = study::resolve(lgres::studies::WEAR_STAGES.name)?;
//! let options = StudyOptions {
//!     response_cycles: 1,
//!     cycles_per_stage: 1,
//!     ..StudyOptions::new("out/study")
//! };
//! let (_results, report) = study::run_studies(&kinds, &options, &())?;
//! println!("{}", report.display());
//! # Ok::<(), analysis::study::StudyError>(())
//! ```

#![warn(missing_docs)]

pub mod precision;
pub mod stress;
pub mod study;
