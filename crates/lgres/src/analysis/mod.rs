//! The analyses beyond one run, each engine apart from its rendering: the paper's studies and
//! their report ([`study`]), the work–precision sweep of the integrators ([`precision`]) and the
//! stress battery ([`stress`]).

pub mod precision;
pub mod stress;
pub mod study;
