//! `mpirun -np P rockfall run INPUT --tiles N` (cargo feature `mpi`): rank r runs tiles
//! r + 1, r + 1 + P, … of the region, folds them into one part, and the parts are merged up
//! a reduction tree — in round k, rank r with r mod 2^(k+1) = 2^k sends its part to rank
//! r − 2^k, which merges it into its own — so that no rank but the last receives more than
//! ⌈log₂ P⌉ parts and rank 0 never gathers every rank's tally at once. Rank 0 then checks
//! that every rock is there and writes the region's run folder, byte for byte the one-process
//! run's (timings aside).
//!
//! A failure travels up the tree with its rank, instead of a part: rank 0 prints the first
//! (lowest rank) and exits with its code; the other ranks exit 0 (see `mpi_run`).

use crate::Failure;
use crate::mpi_run::{agree, code};
use crate::simulate::Console;
use crate::tiles::{TiledRun, own_tiles};
use anyhow::anyhow;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use rockfall_results::{decode_tally, encode_tally};
use rockfall_sim::reduce::{Part, combine};

use rockfall_sim::tile::TileSpec;
use rockfall_sim::{Observer, Overrides, Quiet, RunRecord};
use std::path::{Path, PathBuf};

/// What a rank holds on its way up the tree: its part (none when it had no tile), or the
/// first failure below it, with its rank and exit code.
type Held = Result<Option<Part>, (i32, String)>;

/// Runs the `spec.count` tiles of `input` over the ranks; rank 0 writes into `out`.
pub fn run(
    input: &Path,
    overrides: &Overrides,
    spec: &TileSpec,
    index: &crate::region_index::RegionIndex,
    out: &Path,
    ascii: bool,
) -> Result<(), Failure> {
    let universe = mpi::initialize()
        .ok_or_else(|| Failure::Internal(anyhow!("MPI cannot be initialised twice")))?;
    let world = universe.world();
    let (rank, size) = (world.rank(), world.size());
    // every rank checks the tiling before any runs: a bad flag is reported once
    let checked = rockfall_io::region_geometry(input)
        .map_err(Failure::from)
        .and_then(|g| {
            spec.core(&g)
                .map(|_| ())
                .map_err(|e| Failure::BadInput(anyhow!("{}: {e}", input.display())))
        });
    agree(&world, checked.as_ref().err())?;
    let console = Console::default();
    let observer: &dyn Observer = if rank == 0 { &console } else { &Quiet };
    let tiles: Vec<u64> = (rank as u64 + 1..=spec.count)
        .step_by(size.max(1) as usize)
        .collect();
    // rank 0 keeps the run and decides after every batch; the others follow its verdict
    let mut run = TiledRun::default();
    let mut range = run.next_batch();
    while let Some(r) = range {
        let mine = own_tiles(input, overrides, spec, &tiles, r, index, observer)
            .map_err(|f| (code(&f), format!("rank {rank}: {}", f.text())));
        // 0: next batch from .. to; 1: over; 2: failed (rank 0 reports)
        let mut verdict: [u64; 3] = [1, 0, 0];
        let mut failure = None;
        if let Some(held) = reduce(&world, mine) {
            verdict = match held {
                Ok(Some(batch)) => match run.add(batch) {
                    Ok(false) => run.next_batch().map_or([1, 0, 0], |(a, b)| [0, a, b]),
                    Ok(true) => [1, 0, 0],
                    Err(f) => {
                        failure = Some(f);
                        [2, 0, 0]
                    }
                },
                Ok(None) => [1, 0, 0],
                Err((c, message)) => {
                    failure = Some(match c {
                        2 => Failure::BadInput(anyhow!(message)),
                        _ => Failure::Internal(anyhow!(message)),
                    });
                    [2, 0, 0]
                }
            };
        }
        world.process_at_rank(0).broadcast_into(&mut verdict[..]);
        match verdict[0] {
            0 => range = Some((verdict[1], verdict[2])),
            _ => {
                if let Some(f) = failure {
                    return Err(f);
                }
                range = None;
            }
        }
    }
    if rank != 0 {
        // a failure is rank 0's to report, so this rank exits 0
        return Ok(());
    }
    println!("{size} MPI ranks, {} tiles", spec.count);
    run.write(input, overrides, out, ascii)
}

/// Collective: the ranks' holdings merged up the reduction tree; rank 0 gets the result, the
/// others `None` (after sending theirs, or failing quietly).
fn reduce(world: &SimpleCommunicator, mut held: Held) -> Option<Held> {
    let (rank, size) = (world.rank(), world.size());
    let mut stride = 1;
    while stride < size {
        if rank % (2 * stride) == stride {
            send(world, rank - stride, &held);
            return None;
        }
        if rank + stride < size {
            let theirs = receive(world, rank + stride);
            held = merge(held, theirs);
        }
        stride *= 2;
    }
    Some(held)
}

/// Two holdings as one: the first failure (lower rank first), else the parts combined.
fn merge(mine: Held, theirs: Held) -> Held {
    match (mine, theirs) {
        (Err(e), _) | (Ok(_), Err(e)) => Err(e),
        (Ok(None), Ok(p)) | (Ok(p), Ok(None)) => Ok(p),
        (Ok(Some(a)), Ok(Some(b))) => combine(a, b).map(Some).map_err(|e| (1, e.to_string())),
    }
}

/// Sends a holding: a status (0 part, 3 nothing, else the failure's code), then the message
/// or the tally bytes.
fn send(world: &SimpleCommunicator, to: i32, held: &Held) {
    let (status, bytes) = match held {
        Ok(None) => (3, Vec::new()),
        Ok(Some((_, s))) => match encode_tally(&s.tally, &s.info, &s.run) {
            Ok(b) => (0, b),
            Err(e) => (1, format!("rank {}: {e}", world.rank()).into_bytes()),
        },
        Err((c, m)) => (*c, m.clone().into_bytes()),
    };
    let peer = world.process_at_rank(to);
    peer.send(&status);
    send_bytes(&peer, &bytes);
}

fn receive(world: &SimpleCommunicator, from: i32) -> Held {
    let peer = world.process_at_rank(from);
    let (status, _) = peer.receive::<i32>();
    let bytes = receive_bytes(&peer);
    match status {
        3 => Ok(None),
        0 => {
            let name = PathBuf::from(format!("rank {from}"));
            decode_tally::<RunRecord>(&bytes, &name)
                .map(|s| Some((name, s)))
                .map_err(|e| (1, format!("rank {from}: {e}")))
        }
        c => Err((c, String::from_utf8_lossy(&bytes).into_owned())),
    }
}

/// Largest piece sent in one MPI call (MPI counts are 32-bit).
const PIECE: usize = 1 << 30;

fn send_bytes(peer: &mpi::topology::Process<'_>, bytes: &[u8]) {
    peer.send(&(bytes.len() as u64));
    for piece in bytes.chunks(PIECE) {
        peer.send(piece);
    }
}

fn receive_bytes(peer: &mpi::topology::Process<'_>) -> Vec<u8> {
    let (len, _) = peer.receive::<u64>();
    let mut out = Vec::with_capacity(len as usize);
    while (out.len() as u64) < len {
        let (piece, _) = peer.receive_vec::<u8>();
        out.extend_from_slice(&piece);
    }
    out
}
