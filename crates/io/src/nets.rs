//! Nets as screens (`[nets] screens = true`): one evaluation screen per net, named
//! `net_<id>`, with the net's energy capacity and height as the screen's barrier limits, so
//! that a net's load is read as any screen's (`summary.json` `screens`,
//! `screen_crossings.csv`, the report's screen plots).

use std::collections::BTreeMap;

use rockfall_raster::Field;
use rockfall_scenario::{Nets, Screen};

use crate::vector::inputs::NetLine;

/// The screen of net `id` with capacity `energy_kj` and height `height_m` (limits ≤ 0 are
/// left out: a net without them) along `points_m`.
fn screen(id: u32, points_m: Vec<[f64; 2]>, energy_kj: f64, height_m: f64) -> Screen {
    let limit = |v: f64| (v.is_finite() && v > 0.0).then_some(v);
    Screen {
        name: format!("net_{id}"),
        points_m,
        capacity_kj: limit(energy_kj),
        height_m: limit(height_m),
        net: Some(id),
    }
}

/// One screen per net id of `lines`, drawn along the first part of the first line with that
/// id, in order of id.
pub(crate) fn line_screens(lines: &[NetLine]) -> Vec<Screen> {
    let mut first: BTreeMap<u32, &NetLine> = BTreeMap::new();
    for l in lines {
        first.entry(l.id).or_insert(l);
    }
    (first.into_values())
        .map(|l| {
            let points = l.points_m.first().cloned().unwrap_or_default();
            screen(l.id, points, l.energy_kj, l.height_m)
        })
        .collect()
}

/// One screen per net id (> 0) of the `net_number` raster, in order of id, with the capacity
/// and height of the net's first cell (row-major); without a line to draw.
pub(crate) fn raster_screens(nets: &Nets) -> Vec<Screen> {
    // a constant id covers every cell: its first cell is (0, 0)
    let (nrows, ncols) = match &nets.number {
        Field::Grid(g) => (g.geometry().nrows, g.geometry().ncols),
        Field::Const(_) => (1, 1),
    };
    let mut first: BTreeMap<u32, (f64, f64)> = BTreeMap::new();
    for row in 0..nrows {
        for col in 0..ncols {
            let id = nets.number.at(row, col).unwrap_or(0.0);
            // validated later: ids are whole numbers in u32's range
            if id >= 1.0 && id <= f64::from(u32::MAX) && id.fract() == 0.0 {
                first.entry(id as u32).or_insert_with(|| {
                    let at = |f: &Field| f.at(row, col).unwrap_or(0.0);
                    (at(&nets.energy_kj), at(&nets.height_m))
                });
            }
        }
    }
    (first.into_iter())
        .map(|(id, (e, h))| screen(id, Vec::new(), e, h))
        .collect()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use rockfall_raster::{Grid, GridGeometry};

    #[test]
    fn one_screen_per_net_id_with_its_limits() {
        let g = GridGeometry {
            ncols: 3,
            nrows: 2,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        };
        let number = Grid::from_fn(g, |row, col| {
            Some([[0.0, 4.0, 4.0], [2.0, 0.0, 4.0]][row][col])
        });
        let energy = Grid::from_fn(g, |row, col| {
            Some([[0.0, 500.0, 9.0], [100.0, 0.0, 9.0]][row][col])
        });
        let nets = Nets {
            number: Field::Grid(number),
            energy_kj: Field::Grid(energy),
            height_m: Field::Const(3.0),
        };
        let s = raster_screens(&nets);
        let summary: Vec<_> = (s.iter())
            .map(|s| {
                (
                    s.name.as_str(),
                    s.net,
                    s.capacity_kj,
                    s.height_m,
                    s.points_m.len(),
                )
            })
            .collect();
        assert_eq!(
            summary,
            [
                ("net_2", Some(2), Some(100.0), Some(3.0), 0),
                ("net_4", Some(4), Some(500.0), Some(3.0), 0),
            ]
        );
        let lines = [
            NetLine {
                id: 7,
                points_m: vec![vec![[0.0, 1.0], [5.0, 1.0]]],
                energy_kj: 1000.0,
                height_m: 0.0,
                cells: vec![],
            },
            NetLine {
                id: 3,
                points_m: vec![vec![[0.0, 2.0], [5.0, 2.0]], vec![[9.0, 9.0], [9.0, 8.0]]],
                energy_kj: 250.0,
                height_m: 4.0,
                cells: vec![],
            },
        ];
        let s = line_screens(&lines);
        assert_eq!(s[0].name, "net_3");
        assert_eq!(s[0].points_m, [[0.0, 2.0], [5.0, 2.0]]);
        assert_eq!((s[0].capacity_kj, s[0].height_m), (Some(250.0), Some(4.0)));
        assert_eq!((s[1].net, s[1].height_m), (Some(7), None));
    }
}
