//! `rockfall calibrate`: flags → `rockfall_calibrate::calibrate` with a progress bar → the
//! files written and the best values printed.

use std::cell::RefCell;
use std::path::{Path, PathBuf};

use indicatif::ProgressBar;
use rockfall_calibrate::{Options, Progress, Spec, report};

use crate::Failure;
use crate::lab::print_files;
use crate::simulate;

/// The flags of `calibrate`.
pub struct CalibrateFlags {
    /// Scenario file or Rockyfor3D folder.
    pub scenario: PathBuf,
    /// Targets file.
    pub targets: PathBuf,
    /// `--budget`.
    pub budget: usize,
    /// `--seed`.
    pub seed: Option<u64>,
    /// `--threads`.
    pub threads: Option<u64>,
}

/// A progress bar over the candidates, with the best objective so far.
struct Bar(RefCell<Option<ProgressBar>>, usize);

impl Progress for Bar {
    fn evaluated(&self, done: usize, budget: usize, best: f64) {
        let mut bar = self.0.borrow_mut();
        let b = bar.get_or_insert_with(|| {
            simulate::progress_bar(budget as u64, "calibrating", "candidates")
        });
        b.set_position(done as u64);
        b.set_message(format!("best {best:.3}"));
        if done >= self.1 {
            b.finish_and_clear();
        }
    }
}

/// `rockfall calibrate`.
pub fn calibrate(flags: &CalibrateFlags, out: &Path) -> Result<(), Failure> {
    let bad = |e: rockfall_calibrate::CalibrationError| Failure::of(e.is_bad_input(), e);
    let spec = Spec::read(&flags.targets).map_err(bad)?;
    let scenario = rockfall_io::load(&flags.scenario)?;
    let opts = Options {
        budget: flags.budget,
        seed: flags.seed,
        threads: simulate::threads(flags.threads),
    };
    let bar = Bar(RefCell::new(None), flags.budget);
    let c = rockfall_calibrate::calibrate(scenario.clone(), &spec, &opts, &bar).map_err(
        |e| match e {
            rockfall_calibrate::CalibrationError::Sim(s) => {
                simulate::sim_failure(s, &flags.scenario)
            }
            other => bad(other),
        },
    )?;
    if let Some(b) = bar.0.borrow().as_ref() {
        b.finish_and_clear();
    }
    // the input scenario with the best values: its own numbers of rocks, seed and outputs
    let best = rockfall_calibrate::run::candidate(&scenario, &c.parameters, &c.best().values)
        .map_err(bad)?;
    let files = report::write(&c, &best, Some(&flags.targets), out).map_err(bad)?;
    let b = c.best();
    println!(
        "{}: {} candidates of {} rocks in {:.1} s; best objective (mean z²) {:.3} at evaluation {}, \
         {} candidates fit every target within 2σ",
        c.scenario,
        c.evaluations.len(),
        c.rocks,
        c.wall_time_s,
        b.objective,
        b.index,
        c.fitting().count()
    );
    let ranges = c.fit_ranges();
    for (k, p) in c.parameters.iter().enumerate() {
        let fit = ranges[k].map_or("none fits".into(), |[lo, hi]| {
            format!("fits {lo:.4} – {hi:.4}")
        });
        println!("  {:<40} best {:.4}  ({fit})", p.label(), b.values[k]);
    }
    for r in &b.residuals {
        println!(
            "  target {:<38} observed {:.4}  simulated {}  z {:+.2}",
            r.path,
            r.observed,
            r.simulated.map_or("–".into(), |s| format!("{s:.4}")),
            r.z
        );
    }
    print_files(out, &files);
    Ok(())
}
