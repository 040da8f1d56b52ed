//! The observed figures of seed 000 (Dorren et al. 2006), tables 2 and 3, typed in with
//! RockyFor's simulated values and errors beside them.
//!
//! Observed: 100 rocks on site 1, 102 analysed rocks on site 2 (§2.1); RockyFor: 10 000
//! simulated rocks per site (table 2).

/// One observed quantity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantity {
    /// Key the simulated value is looked up by (see [`crate::measure`]).
    pub key: &'static str,
    /// What it is, as the paper names it.
    pub label: &'static str,
    /// Unit.
    pub unit: &'static str,
    /// Group of rows the paper gives one RMSE for.
    pub group: &'static str,
    /// Observed value O.
    pub observed: f64,
    /// RockyFor's simulated value C in the paper.
    pub rockyfor: f64,
    /// The paper's error E for RockyFor, %.
    pub rockyfor_error_pct: f64,
}

/// A group of rows and the RMSE the paper gives for RockyFor on it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Group {
    /// Group name (`table 2`, `mean`, `max`).
    pub name: &'static str,
    /// The paper's RMSE, %.
    pub rockyfor_rmse_pct: f64,
}

/// One published comparison: a site's table 2 column or one screen of table 3.
#[derive(Debug, Clone, PartialEq)]
pub struct Published {
    /// Case name in `validation.json`.
    pub name: &'static str,
    /// The built-in site the case runs.
    pub site: &'static str,
    /// What it is.
    pub title: &'static str,
    /// Where the figures are from.
    pub source: &'static str,
    /// Rocks observed on the site (the paper gives no count per screen).
    pub observed_rocks: Option<u32>,
    /// Screen the quantities are measured at (table 3), by its name in the site's scenario.
    pub screen: Option<&'static str>,
    /// The observed quantities.
    pub quantities: Vec<Quantity>,
    /// The paper's RMSE groups.
    pub groups: Vec<Group>,
}

const fn q(
    key: &'static str,
    label: &'static str,
    unit: &'static str,
    group: &'static str,
    [observed, rockyfor, rockyfor_error_pct]: [f64; 3],
) -> Quantity {
    Quantity {
        key,
        label,
        unit,
        group,
        observed,
        rockyfor,
        rockyfor_error_pct,
    }
}

const T2: &str = "table 2";

/// Table 2's column of site 1 or, `forested`, of site 2: [O, C, E] of each row.
fn table2(forested: bool) -> Vec<Quantity> {
    let rows: [(&str, &str, &str, [[f64; 3]; 2]); 5] = [
        (
            "mean_max_velocity_ms",
            "Average maximum translation velocity of all the rocks",
            "m/s",
            [[15.4, 17.3, 12.3], [11.7, 12.8, 9.4]],
        ),
        (
            "max_velocity_ms",
            "Maximum translation velocity",
            "m/s",
            [[30.6, 30.4, -0.7], [24.2, 22.3, -7.9]],
        ),
        (
            "stopped_within_223_5m_pct",
            "Rocks stopped within the first 223.5 m",
            "%",
            [[5.0, 4.0, -20.0], [66.0, 74.0, 12.1]],
        ),
        (
            "passed_lower_road_pct",
            "Rocks that passed the lower forest road",
            "%",
            [[74.0, 95.0, 28.4], [21.0, 25.0, 19.0]],
        ),
        (
            "max_rebound_height_m",
            "Maximal height of rebound",
            "m",
            [[8.0, 7.6, -5.0], [2.0, 2.1, 5.0]],
        ),
    ];
    let mut v: Vec<Quantity> = rows
        .iter()
        .map(|&(key, label, unit, sites)| q(key, label, unit, T2, sites[usize::from(forested)]))
        .collect();
    if forested {
        // on the unforested site 1 the paper has "n.a."
        let trees = q(
            "tree_impacts_per_rock",
            "Mean number of tree impacts per falling rock",
            "–",
            T2,
            [2.8, 2.3, -17.9],
        );
        v.insert(4, trees);
    }
    v
}

/// Table 3 at one screen: [O, C, E] of v, RH, E_kin, each as mean then max.
fn table3(rows: [[f64; 3]; 6]) -> Vec<Quantity> {
    let what = [
        (
            "mean_velocity_ms",
            "Mean translation velocity",
            "m/s",
            "mean",
        ),
        (
            "mean_rebound_height_m",
            "Mean vertical rebound height",
            "m",
            "mean",
        ),
        ("mean_energy_kj", "Mean kinetic energy", "kJ", "mean"),
        (
            "max_velocity_ms",
            "Maximum translation velocity",
            "m/s",
            "max",
        ),
        (
            "max_rebound_height_m",
            "Maximum vertical rebound height",
            "m",
            "max",
        ),
        ("max_energy_kj", "Maximum kinetic energy", "kJ", "max"),
    ];
    what.iter()
        .zip(rows)
        .map(|(&(key, label, unit, group), r)| q(key, label, unit, group, r))
        .collect()
}

/// Every published comparison of seed 000: table 2 for each site, table 3 at each screen.
pub fn published() -> Vec<Published> {
    let groups = |mean: f64, max: f64| {
        vec![
            Group {
                name: "mean",
                rockyfor_rmse_pct: mean,
            },
            Group {
                name: "max",
                rockyfor_rmse_pct: max,
            },
        ]
    };
    vec![
        Published {
            name: "vaujany-site1",
            site: "vaujany-site1",
            title: "Site 1 (unforested avalanche track), slope scale",
            source: "Dorren et al. 2006 (seed 000), table 2; observed n = 100",
            observed_rocks: Some(100),
            screen: None,
            quantities: table2(false),
            groups: vec![Group {
                name: T2,
                rockyfor_rmse_pct: 17.0,
            }],
        },
        Published {
            name: "vaujany-site1/screen-185m",
            site: "vaujany-site1",
            title: "Site 1, evaluation screen 1 (185 m along the slope)",
            source: "Dorren et al. 2006 (seed 000), table 3",
            observed_rocks: None,
            screen: Some("screen_185m"),
            quantities: table3([
                [12.5, 17.1, 36.8],
                [1.4, 0.9, -36.5],
                [204.9, 346.7, 69.2],
                [28.1, 24.1, -14.2],
                [5.0, 4.2, -15.7],
                [786.4, 781.9, -0.6],
            ]),
            groups: groups(50.0, 12.0),
        },
        Published {
            name: "vaujany-site1/screen-235m",
            site: "vaujany-site1",
            title: "Site 1, evaluation screen 2 (235 m along the slope)",
            source: "Dorren et al. 2006 (seed 000), table 3",
            observed_rocks: None,
            screen: Some("screen_235m"),
            quantities: table3([
                [13.8, 17.3, 25.4],
                [1.6, 1.2, -27.8],
                [244.5, 406.9, 66.4],
                [28.9, 26.5, -8.2],
                [6.2, 5.5, -11.1],
                [958.3, 943.8, -1.5],
            ]),
            groups: groups(44.0, 8.0),
        },
        Published {
            name: "vaujany-site2",
            site: "vaujany-site2",
            title: "Site 2 (forested), slope scale",
            source: "Dorren et al. 2006 (seed 000), table 2; observed n = 102",
            observed_rocks: Some(102),
            screen: None,
            quantities: table2(true),
            groups: vec![Group {
                name: T2,
                rockyfor_rmse_pct: 13.0,
            }],
        },
    ]
}
