//! `wearsim`: the command line of the worn-clearance-joint toolkit.
//!
//! It will run scenes (`run`), the paper's studies (`study`) and scene checks (`check`); until
//! the `lgres` crate holds the scenes it only prints what it will do.

fn main() {
    println!(
        "wearsim {}: the scene runner is not built yet; see README.md for what runs today.",
        env!("CARGO_PKG_VERSION")
    );
}
