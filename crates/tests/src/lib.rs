//! Cross-crate tests live in `tests/`: they exercise `contact`, `wear`, `multibody` and `lgres`
//! together (for example a short landing-gear run checked against its kinematic analysis).
