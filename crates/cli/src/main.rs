//! The `rockfall` binary: parses the command line, dispatches, maps failures to exit codes
//! (0 success, 2 bad input, 1 internal failure). All work happens in the library crates.

mod args;
mod calibrate;
mod commands;
mod hazard;
mod lab;
#[cfg(feature = "mpi")]
mod mpi_run;
#[cfg(feature = "mpi")]
mod mpi_tiles;
mod region_index;
mod regional;
mod schema;
mod simulate;
mod tiles;
mod validate;

use clap::Parser;
use std::process::ExitCode;

/// A failed command: bad input (exit 2) or anything else (exit 1).
pub enum Failure {
    /// The user's input is at fault; the message names the file, cell or key.
    BadInput(anyhow::Error),
    /// Our fault.
    Internal(anyhow::Error),
    /// An MPI rank other than 0 exits with this code; rank 0 printed what went wrong.
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    Rank(u8),
}

impl Failure {
    /// A library error that says whether the input is at fault (`bad_input`): exit 2 if so,
    /// 1 otherwise.
    pub fn of(bad_input: bool, e: impl Into<anyhow::Error>) -> Failure {
        if bad_input {
            Failure::BadInput(e.into())
        } else {
            Failure::Internal(e.into())
        }
    }
}

impl Failure {
    /// What went wrong, with its causes (as printed).
    pub fn text(&self) -> String {
        match self {
            Failure::BadInput(e) | Failure::Internal(e) => message(e),
            Failure::Rank(code) => format!("exit {code}"),
        }
    }
}

impl From<rockfall_io::InputError> for Failure {
    fn from(e: rockfall_io::InputError) -> Self {
        Failure::BadInput(e.into())
    }
}

fn main() -> ExitCode {
    std::panic::set_hook(Box::new(|info| {
        // a reader that closed our stdout early (`rockfall … | head`) is not a failure
        let text = info.payload_as_str().unwrap_or_default();
        if text.contains("failed printing to stdout") && text.contains("Broken pipe") {
            std::process::exit(0);
        }
        eprintln!("rockfall: internal error (a bug; please report it): {info}");
        std::process::exit(1);
    }));
    let cli = args::Cli::parse();
    match commands::dispatch(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::BadInput(e)) => {
            eprintln!("error: {}", message(&e));
            ExitCode::from(2)
        }
        Err(Failure::Internal(e)) => {
            eprintln!("rockfall: {}", message(&e));
            ExitCode::from(1)
        }
        Err(Failure::Rank(code)) => ExitCode::from(code),
    }
}

/// The error and its causes, joined by `: `. A cause whose text the previous message already
/// holds is left out: our errors print `path: cause` and also expose that cause as their
/// source, which `{:#}` would print twice.
fn message(e: &anyhow::Error) -> String {
    let mut out = e.to_string();
    let mut previous = out.clone();
    for cause in e.chain().skip(1) {
        let text = cause.to_string();
        if !previous.contains(&text) {
            out += ": ";
            out += &text;
        }
        previous = text;
    }
    out
}
