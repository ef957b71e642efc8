//! The command's pieces: argument parsing (clap), what a sweep's options mean, running sweeps and
//! the main job, `check`, and the plots a sweep writes.

/// `println!` that ignores a closed stdout (`mechgen | head` must not panic).
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}

/// `print!` that ignores a closed stdout.
macro_rules! say_raw {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stdout(), $($t)*);
    }};
}

/// `eprintln!` that ignores a closed stderr (`mechgen check --file bad.toml 2>&1 | true` must
/// exit with the command's status, not a panic).
macro_rules! tell {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($t)*);
    }};
}

/// `eprint!` that ignores a closed stderr.
macro_rules! tell_raw {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stderr(), $($t)*);
    }};
}

/// Bytes buffered before a table or CSV is written out: large writes, few system calls.
pub(crate) const OUTPUT_BUFFER: usize = 1 << 20;

pub mod analysed;
pub mod args;
pub mod batch;
pub mod branches;
pub mod check;
pub mod design;
pub mod dynamics;
pub mod load;
pub mod metrics;
pub mod out;
pub mod plots;
pub mod run;
pub mod scene;
pub mod simulate;
