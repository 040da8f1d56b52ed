//! `rockfall validate`: flags → [`Validate`] → `rockfall_validation::run::run_validation` →
//! the terminal tables and the files written.

use crate::Failure;
use crate::lab::print_files;
use crate::simulate;
use rockfall_validation::report;
use rockfall_validation::run::{QUICK_ROCKS, ROCKS, Validate, run_validation};
use std::path::Path;

/// The flags of `validate`.
pub struct ValidateFlags {
    /// Runs asked for (none: all).
    pub cases: Vec<String>,
    /// `--rocks`.
    pub rocks: Option<u64>,
    /// `--quick`.
    pub quick: bool,
    /// `--seed`.
    pub seed: Option<u64>,
    /// `--threads`.
    pub threads: Option<u64>,
}

impl ValidateFlags {
    /// Rocks per Vaujany run and per shape.
    fn rocks(&self) -> (u64, u64) {
        match (self.rocks, self.quick) {
            (Some(n), _) => (n, n),
            (None, true) => QUICK_ROCKS,
            (None, false) => ROCKS,
        }
    }

    /// What the flags ask to validate; an unknown case is bad input.
    fn settings(&self) -> Result<Validate, Failure> {
        let cases = Validate::select(&self.cases).map_err(|e| Failure::BadInput(e.into()))?;
        let (site_rocks, shape_rocks) = self.rocks();
        Ok(Validate {
            cases,
            site_rocks,
            shape_rocks,
            seed: self.seed.unwrap_or(1),
            threads: simulate::threads(self.threads),
            // lossy: a path that is not UTF-8 must not make the report panic
            command: std::iter::once("rockfall".to_string())
                .chain(
                    std::env::args_os()
                        .skip(1)
                        .map(|a| a.to_string_lossy().into_owned()),
                )
                .collect::<Vec<_>>()
                .join(" "),
        })
    }
}

/// `rockfall validate`.
pub fn validate(flags: &ValidateFlags, out: &Path) -> Result<(), Failure> {
    let settings = flags.settings()?;
    let v = run_validation(&settings, out, &simulate::Console::default())
        .map_err(|e| Failure::of(e.is_bad_input(), e))?;
    print!("{}", report::terminal(&v.cases));
    print!("{}", report::sensitivity_terminal(&v.meta.sensitivity));
    println!();
    print_files(out, &v.files);
    Ok(())
}
