//! `mpirun -np N rockfall run …` (cargo feature `mpi`): the ranks share the rocks as the N
//! partitions of `--partition`, and rank 0 gathers their exact tallies, merges them and
//! writes the run folder, identical to a one-process run's (timings aside).
//!
//! Every rank reads the input. Two collective steps follow, each entered by every rank
//! whatever happened before it, so that a failing rank never leaves the others waiting:
//! after reading, every rank reports ok or its error to rank 0, which broadcasts the verdict;
//! after simulating, every rank sends its status and its tally file's bytes to rank 0. Errors
//! are printed by rank 0 alone, naming the rank; the other ranks then exit 0, so that
//! `mpirun` never aborts rank 0 before it has printed, and returns rank 0's code.

use crate::Failure;
use crate::commands::load_simulation;
use crate::regional::{recorded_input, write_run_folder};
use crate::simulate::Console;
use anyhow::anyhow;
use mpi::Count;
use mpi::datatype::PartitionMut;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use rockfall_results::{decode_tally, encode_tally};
use rockfall_sim::{Finished, Observer, Overrides, Partition, Quiet, RunRecord, share};
use std::path::{Path, PathBuf};

/// True when this process was started by `mpirun` (Open MPI, MPICH or a PMIx launcher):
/// checked before MPI is initialised, since a singleton initialisation sets these itself.
pub fn launched() -> bool {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"]
        .iter()
        .any(|v| std::env::var_os(v).is_some())
}

/// Status codes exchanged between ranks: 0 ok, 1 internal failure, 2 bad input.
pub(crate) fn code(f: &Failure) -> i32 {
    match f {
        Failure::BadInput(_) => 2,
        Failure::Internal(_) | Failure::Rank(_) => 1,
    }
}

/// Runs `input` with `overrides` over the ranks of `mpirun`; rank 0 writes into `out`.
pub fn run(input: &Path, overrides: &Overrides, out: &Path, ascii: bool) -> Result<(), Failure> {
    let universe = mpi::initialize()
        .ok_or_else(|| Failure::Internal(anyhow!("MPI cannot be initialised twice")))?;
    let world = universe.world();
    let (rank, size) = (world.rank(), world.size());
    let loaded = load_simulation(input, overrides).and_then(|sim| {
        match sim.scenario().simulation.until_stable_pct {
            Some(_) => Err(Failure::BadInput(anyhow!(
                "{}: until_stable_pct: under mpirun the ranks share a fixed set of rocks; run \
                 convergence over tiles (--tiles N) or in one process",
                input.display()
            ))),
            None => Ok(sim),
        }
    });
    agree(&world, loaded.as_ref().err())?;
    let sim = loaded?;
    let share = Partition {
        index: rank as u64 + 1,
        count: size as u64,
    };
    let record = RunRecord::new(sim.scenario(), &recorded_input(input)).with_partition(share);
    let console = Console::default();
    let observer: &dyn Observer = if rank == 0 { &console } else { &Quiet };
    let label = format!("{size} ranks, rank 0");
    let bytes = sim
        .run_batches(record, None, &label, observer, &mut |_, _, _| Ok(()))
        .map_err(|e| crate::simulate::sim_failure(e, input))
        .and_then(|f| {
            encode_tally(&f.tally, &f.info, &f.record).map_err(|e| Failure::Internal(e.into()))
        });
    let status = bytes.as_ref().map_or_else(code, |_| 0);
    let message = bytes.as_ref().err().map(Failure::text).unwrap_or_default();
    let mine = bytes.unwrap_or_default();
    let gathered = gather(&world, status, message.as_bytes(), &mine);
    let Some(ranks) = gathered else {
        // the other ranks are done: rank 0 reports for everyone and exits with the code
        return match status {
            0 => Ok(()),
            _ => Err(Failure::Rank(QUIET_EXIT)),
        };
    };
    let mut parts = Vec::with_capacity(ranks.len());
    for (r, (status, message, bytes)) in ranks.into_iter().enumerate() {
        let e = anyhow!("rank {r}: {}", String::from_utf8_lossy(&message));
        match status {
            0 => {}
            2 => return Err(Failure::BadInput(e)),
            _ => return Err(Failure::Internal(e)),
        }
        let name = PathBuf::from(format!("rank {r}"));
        let saved = decode_tally(&bytes, &name).map_err(|e| Failure::Internal(e.into()))?;
        parts.push((name, saved));
    }
    let merged = share::merge(parts).map_err(|e| Failure::Internal(e.into()))?;
    let finished = Finished {
        tally: merged.tally,
        info: merged.info,
        record: merged.record,
        convergence: None,
    };
    println!(
        "{size} MPI ranks, {} rocks in all",
        finished.record.rocks_total
    );
    write_run_folder(&sim, input, out, ascii, finished)
        .map_err(|e| Failure::Internal(anyhow!("rank 0 cannot write the output: {}", e.text())))
}

/// The exit code of a rank other than 0 once rank 0 knows of a failure: 0, quietly. Were it
/// non-zero, `mpirun` could abort rank 0 before rank 0 printed the message; rank 0 exits
/// with the failure's code, which `mpirun` returns.
const QUIET_EXIT: u8 = 0;

/// Every rank says whether it failed (`failure`); rank 0 prints the failures and broadcasts
/// the verdict. Returns the failure to exit with: rank 0's own or the first rank's, printed
/// once by rank 0 (other ranks exit quietly, [`QUIET_EXIT`]).
pub(crate) fn agree(world: &SimpleCommunicator, failure: Option<&Failure>) -> Result<(), Failure> {
    let status = failure.map_or(0, code);
    let message = failure.map(Failure::text).unwrap_or_default();
    let ranks = gather(world, status, message.as_bytes(), &[]);
    let root = world.process_at_rank(0);
    let mut verdict = ranks
        .as_ref()
        .and_then(|v| v.iter().map(|(s, _, _)| *s).find(|&s| s != 0))
        .unwrap_or(0);
    root.broadcast_into(&mut verdict);
    match (verdict, ranks) {
        (0, _) => Ok(()),
        (c, Some(ranks)) => {
            let (r, m) = (ranks.iter().enumerate())
                .find(|(_, (s, _, _))| *s != 0)
                .map_or((0, String::new()), |(r, x)| {
                    (r, String::from_utf8_lossy(&x.1).into_owned())
                });
            let e = anyhow!("rank {r}: {m}");
            Err(if c == 2 {
                Failure::BadInput(e)
            } else {
                Failure::Internal(e)
            })
        }
        (_, None) => Err(Failure::Rank(QUIET_EXIT)),
    }
}

/// What one rank sends: status, message, tally bytes.
type Sent = (i32, Vec<u8>, Vec<u8>);

/// Collective: every rank sends its status, message and bytes; rank 0 gets them in rank
/// order, the others `None`.
fn gather(
    world: &SimpleCommunicator,
    status: i32,
    message: &[u8],
    bytes: &[u8],
) -> Option<Vec<Sent>> {
    let root = world.process_at_rank(0);
    let statuses = if world.rank() == 0 {
        let mut v = vec![0i32; world.size() as usize];
        root.gather_into_root(&status, &mut v[..]);
        Some(v)
    } else {
        root.gather_into(&status);
        None
    };
    let messages = gather_bytes(world, message);
    let tallies = gather_bytes(world, bytes);
    match (statuses, messages, tallies) {
        (Some(s), Some(m), Some(t)) => Some(
            s.into_iter()
                .zip(m)
                .zip(t)
                .map(|((s, m), t)| (s, m, t))
                .collect(),
        ),
        _ => None,
    }
}

/// Largest piece of a rank's bytes sent in one MPI call (MPI counts are 32-bit).
const PIECE: u64 = 1 << 30;

/// Collective: every rank's bytes, in rank order, on rank 0: the lengths first, then the
/// bytes in rounds of at most [`PIECE`] bytes per rank, so tallies beyond 2 GiB pass too.
fn gather_bytes(world: &SimpleCommunicator, mine: &[u8]) -> Option<Vec<Vec<u8>>> {
    let root = world.process_at_rank(0);
    let len = mine.len() as u64;
    let lens = if world.rank() == 0 {
        let mut v = vec![0u64; world.size() as usize];
        root.gather_into_root(&len, &mut v[..]);
        Some(v)
    } else {
        root.gather_into(&len);
        None
    };
    let mut rounds = lens
        .as_ref()
        .map_or(0, |v| v.iter().max().copied().unwrap_or(0).div_ceil(PIECE));
    root.broadcast_into(&mut rounds);
    let mut out: Option<Vec<Vec<u8>>> = lens
        .as_ref()
        .map(|v| v.iter().map(|&n| Vec::with_capacity(n as usize)).collect());
    for k in 0..rounds {
        let piece = |n: u64| (k * PIECE).min(n)..((k + 1) * PIECE).min(n);
        let r = piece(len);
        let got = gather_piece(world, &mine[r.start as usize..r.end as usize]);
        if let (Some(out), Some(got)) = (out.as_mut(), got) {
            for (o, g) in out.iter_mut().zip(got) {
                o.extend_from_slice(&g);
            }
        }
    }
    out
}

/// One round of [`gather_bytes`]: at most [`PIECE`] bytes per rank.
fn gather_piece(world: &SimpleCommunicator, mine: &[u8]) -> Option<Vec<Vec<u8>>> {
    let root = world.process_at_rank(0);
    // at most PIECE = 2^30 bytes: fits a Count
    let len = mine.len() as Count;
    // an empty slice's dangling pointer is MPI_IN_PLACE to Open MPI: send from a real address
    let dummy = [0u8; 1];
    let mine = if mine.is_empty() { &dummy[..0] } else { mine };
    if world.rank() != 0 {
        root.gather_into(&len);
        root.gather_varcount_into(mine);
        return None;
    }
    let mut counts = vec![0 as Count; world.size() as usize];
    root.gather_into_root(&len, &mut counts[..]);
    let displs: Vec<Count> = (counts.iter())
        .scan(0, |at, &c| {
            let d = *at;
            *at += c;
            Some(d)
        })
        .collect();
    let total: Count = counts.iter().sum();
    let mut buf = vec![0u8; total as usize + 1]; // never an empty (MPI_IN_PLACE) buffer
    {
        let mut part = PartitionMut::new(&mut buf[..], &counts[..], &displs[..]);
        root.gather_varcount_into_root(mine, &mut part);
    }
    Some(
        counts
            .iter()
            .zip(&displs)
            .map(|(&c, &d)| buf[d as usize..(d + c) as usize].to_vec())
            .collect(),
    )
}
