//! Text for the terminal that never panics. `println!` panics when standard output is a closed
//! pipe (`wearsim scenes | head -1`), and a panic in a destructor while unwinding aborts the
//! process before the output folder is cleaned up. Every line the program writes goes through
//! [`write_out`] or [`write_err`] instead (by the `outln!`, `out!`, `errln!` and `err!`
//! macros): a failed write is remembered, never fatal, and the program finishes its work (an
//! output folder complete or untouched) and exits as a closed pipe asks ([`EXIT_CLOSED_PIPE`]).

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

/// Exit code when standard output was closed under the program: 128 + SIGPIPE, what shells
/// report for a program a closed pipe ended.
pub const EXIT_CLOSED_PIPE: u8 = 141;

/// Set once a write to standard output failed: later writes are skipped.
static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);

/// Writes to standard output; a failure (a closed pipe, a full disk) is remembered.
pub fn write_out(text: std::fmt::Arguments<'_>) {
    if STDOUT_CLOSED.load(Ordering::Relaxed) {
        return;
    }
    if std::io::stdout()
        .lock()
        .write_all(printable(text).as_bytes())
        .is_err()
    {
        STDOUT_CLOSED.store(true, Ordering::Relaxed);
    }
}

/// Writes to standard error; a failure is ignored (there is nowhere left to report it).
pub fn write_err(text: std::fmt::Arguments<'_>) {
    let _ = std::io::stderr()
        .lock()
        .write_all(printable(text).as_bytes());
}

/// `text` with every control character but line breaks and tabs escaped (`\u{1b}`): a file
/// name or a value printed in a message must not drive the terminal of whoever runs wearsim
/// (ESC sequences retitle or clear it).
fn printable(text: std::fmt::Arguments<'_>) -> String {
    let text = text.to_string();
    if !text.chars().any(is_unsafe) {
        return text;
    }
    text.chars()
        .map(|c| {
            if is_unsafe(c) {
                c.escape_unicode().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// A control character other than a line break or a tab.
fn is_unsafe(c: char) -> bool {
    c.is_control() && !matches!(c, '\n' | '\t')
}

/// Flushes standard output and tells whether any of it was lost to a closed pipe.
pub fn stdout_closed() -> bool {
    if std::io::stdout().lock().flush().is_err() {
        STDOUT_CLOSED.store(true, Ordering::Relaxed);
    }
    STDOUT_CLOSED.load(Ordering::Relaxed)
}

/// `println!` that never panics ([`write_out`]).
macro_rules! outln {
    () => { $crate::console::write_out(format_args!("\n")) };
    ($($arg:tt)*) => {
        $crate::console::write_out(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` that never panics ([`write_out`]).
macro_rules! out {
    ($($arg:tt)*) => { $crate::console::write_out(format_args!($($arg)*)) };
}

/// `eprintln!` that never panics ([`write_err`]).
macro_rules! errln {
    ($($arg:tt)*) => {
        $crate::console::write_err(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `eprint!` that never panics ([`write_err`]).
macro_rules! err {
    ($($arg:tt)*) => { $crate::console::write_err(format_args!($($arg)*)) };
}
