//! Scenario fingerprints: what a tally file records of the inputs, so that a merge refuses
//! the parts of different runs and a resumed run refuses a changed input.

use rockfall_results::Fnv1a;
use rockfall_scenario::Scenario;

/// A hash of everything in `scenario` that shapes its results: terrain, forest, nets, rock,
/// release, screens, engine settings, numbers of rocks, seed, outputs kept — but not where it
/// was read from (`sources`, `notes`), so that copies of one input on several machines agree.
/// FNV-1a over the `Debug` text of each part (exact for floats: `Debug` prints the shortest
/// text that reads back to the same bits), as 16 hex digits.
pub fn fingerprint(scenario: &Scenario) -> String {
    use std::fmt::Write;
    let s = scenario;
    let mut h = Fnv1a::default();
    // `write!` into the hash cannot fail
    let _ = write!(
        h,
        "{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}",
        s.name,
        s.engine,
        s.seed,
        s.terrain,
        s.forest,
        s.nets,
        s.rock,
        s.release,
        s.screens,
        s.lumped,
        s.rigid,
        s.contact,
        settled(&s.simulation),
        s.output,
    );
    format!("{:016x}", h.0)
}

/// The rock's settings with each per-cell raster replaced by a mark (its values are in the
/// files hashed beside it, and a tile holds only its window of them).
fn rock_without_grids(rock: &rockfall_scenario::RockSpec) -> String {
    use rockfall_raster::Field;
    let f = |f: &Field| match f {
        Field::Const(v) => format!("{v:?}"),
        Field::Grid(g) => format!("grid {:?}", g.geometry()),
    };
    let shape = match &rock.shape {
        rockfall_scenario::RockShape::PerCell(g) => f(g),
        other => format!("{other:?}"),
    };
    format!(
        "{shape}|{}|{}|{}|{}|{:?}|{:?}|{:?}",
        f(&rock.dims_m[0]),
        f(&rock.dims_m[1]),
        f(&rock.dims_m[2]),
        f(&rock.density_kg_m3),
        rock.volume_m3,
        rock.volume_variation_percent,
        rock.volume_distribution,
    )
}

/// The settings as simulated: whether a number of rocks was given or defaulted shapes
/// nothing once the caps are applied, and a run read back from its record has every number
/// given.
fn settled(s: &rockfall_scenario::SimulationSettings) -> rockfall_scenario::SimulationSettings {
    rockfall_scenario::SimulationSettings {
        rocks_per_cell_given: true,
        rocks_per_point_given: true,
        ..s.clone()
    }
}

/// The fingerprint of a region's run as its spatial tiles record it (`tiles-` and 16 hex
/// digits): the same for every tile and for the whole run, whose grids and release cells
/// differ from a tile's. FNV-1a over the parts of [`fingerprint`] other than the grids,
/// release cells and stands, the DEM's grid, and the [`input_digest`] of the files the
/// scenario was read from (`digest`; a tile index keeps it, see `rockfall_io::tile_index`).
pub fn tile_fingerprint(scenario: &Scenario, digest: u64) -> String {
    use std::fmt::Write;
    let s = scenario;
    let mut h = Fnv1a::default();
    let r = &s.release;
    let _ = write!(
        h,
        "{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}",
        s.name,
        s.engine,
        s.seed,
        s.terrain.dem.geometry(),
        rock_without_grids(&s.rock),
        r.cell_height_m,
        r.cell_velocity_ms,
        r.points,
        s.screens,
        s.lumped,
        s.rigid,
        s.contact,
        settled(&s.simulation),
        s.output,
        s.forest.is_some(),
        s.nets.is_some(),
    );
    h.bytes(&digest.to_le_bytes());
    format!("tiles-{:016x}", h.0)
}

/// FNV-1a over the key and the bytes of every file `scenario` was read from, in the order of
/// their keys.
pub fn input_digest(scenario: &Scenario) -> std::io::Result<u64> {
    use std::fmt::Write;
    use std::io::Read;
    let mut h = Fnv1a::default();
    let mut buf = vec![0u8; 1 << 20];
    for (key, path) in &scenario.sources {
        let _ = write!(h, "|{key}");
        let mut f = std::fs::File::open(path)?;
        loop {
            let n = f.read(&mut buf)?;
            if n == 0 {
                break;
            }
            h.bytes(&buf[..n]);
        }
    }
    Ok(h.0)
}
