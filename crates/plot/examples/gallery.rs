//! Draws one figure of each kind into a folder (default `target/plot-gallery`), to look at:
//! `cargo run -p rockfall-plot --example gallery -- DIR`.

use std::f64::consts::PI;
use std::path::PathBuf;

use rockfall_plot::{
    Axes, Bars, ColorScale, LinePanel, MapFigure, MapLine, Panel, PlotError, Polyline, Ramp,
    Series, colored_lines_panels, histogram, line_panels, raster_map, scatter_panels,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .map_or_else(|| PathBuf::from("target/plot-gallery"), PathBuf::from);
    std::fs::create_dir_all(&dir)?;
    lines(&dir.join("lines.png"))?;
    scatter(&dir.join("scatter.png"))?;
    map(&dir.join("map.png"))?;
    hist(&dir.join("histogram.png"))?;
    hazard_map(&dir.join("hazard_map.png"))?;
    site_map(&dir.join("site_map.png"))?;
    println!("wrote 6 figures to {}", dir.display());
    Ok(())
}

/// A small deterministic pseudo-random sequence in [0, 1).
fn noise(i: usize) -> f64 {
    let x = (i as f64 * 12.9898).sin() * 43758.5453;
    x - x.floor()
}

fn lines(path: &std::path::Path) -> Result<(), PlotError> {
    let curve = |label: &str, f: &dyn Fn(f64) -> f64| Series {
        label: label.into(),
        points: (0..200)
            .map(|i| i as f64 * 0.05)
            .map(|t| (t, f(t)))
            .collect(),
    };
    let panel = |title: &str, k: f64| Panel {
        title: title.into(),
        series: vec![
            curve("sphere", &|t| 20.0 * (1.0 - (-k * t).exp())),
            curve("cube", &|t| 15.0 * (1.0 - (-k * t).exp()) + (3.0 * t).sin()),
        ],
    };
    let axes = Axes::new("time (s)", "speed (m/s)");
    line_panels(
        path,
        "Speed along the slope",
        &axes,
        &[panel("soft soil", 0.3), panel("scree", 0.8)],
    )
}

fn scatter(path: &std::path::Path) -> Result<(), PlotError> {
    let cloud = |label: &str, shift: f64, seed: usize| Series {
        label: label.into(),
        points: (0..5000)
            .map(|i| {
                let (u, v) = (noise(seed + 2 * i), noise(seed + 2 * i + 1));
                let r = (-2.0 * (u + 1e-12).ln()).sqrt();
                (
                    shift + 80.0 * r * (2.0 * PI * v).cos(),
                    400.0 + 60.0 * r * (2.0 * PI * v).sin(),
                )
            })
            .collect(),
    };
    let panel = Panel {
        title: "runout vs energy".into(),
        series: vec![cloud("sphere", 0.0, 1), cloud("disc", 150.0, 99_999)],
    };
    let axes = Axes::new("runout (m)", "energy (kJ)");
    scatter_panels(path, "5000 rocks per shape", &axes, &[panel.clone(), panel])
}

fn map(path: &std::path::Path) -> Result<(), PlotError> {
    let panel = |title: &str, spread: f64| LinePanel {
        title: title.into(),
        lines: (0..60)
            .map(|k| {
                let x0 = 100.0 + 4.0 * k as f64;
                let points: Vec<[f64; 2]> = (0..100)
                    .map(|i| {
                        let s = i as f64 * 6.0;
                        [
                            x0 + spread * (k as f64 - 30.0) * s / 600.0 + 10.0 * (s / 80.0).sin(),
                            800.0 - s,
                        ]
                    })
                    .collect();
                let values = (0..100)
                    .map(|i| 1.0 + 3000.0 * (i as f64 / 99.0).powi(3))
                    .collect();
                Polyline { points, values }
            })
            .collect(),
    };
    let axes = Axes::new("x (m)", "y (m)");
    let scale = ColorScale {
        label: "total energy (kJ)".into(),
        min: 1.0,
        max: 3000.0,
        log: true,
        ..ColorScale::default()
    };
    colored_lines_panels(
        path,
        "Trajectories",
        &axes,
        &scale,
        &[panel("sphere", 1.0), panel("disc", 3.0)],
    )
}

fn hist(path: &std::path::Path) -> Result<(), PlotError> {
    let bins = |f: &dyn Fn(f64) -> f64| {
        (0..20)
            .map(|i| {
                (
                    i as f64 * 10.0,
                    i as f64 * 10.0 + 10.0,
                    f(i as f64 * 10.0 + 5.0),
                )
            })
            .collect()
    };
    let bars = [
        Bars {
            label: "observed".into(),
            bins: bins(&|x| 40.0 * (-((x - 80.0) / 40.0).powi(2)).exp()),
        },
        Bars {
            label: "simulated".into(),
            bins: bins(&|x| 36.0 * (-((x - 90.0) / 45.0).powi(2)).exp()),
        },
    ];
    histogram(
        path,
        "Runout distance",
        &Axes::new("runout (m)", "count"),
        &bars,
    )
}

/// A hazard map: energy on a log scale (magma) with screens, release cells and tree stems.
fn hazard_map(path: &std::path::Path) -> Result<(), PlotError> {
    let (x0, y0) = (939_300.0, 120_000.0);
    let scale = ColorScale {
        label: "max. kinetic energy (kJ)".into(),
        min: 1.0,
        max: 3000.0,
        log: true,
        ramp: Ramp::Magma,
    };
    let fill = |x: f64, y: f64| {
        let (u, v) = (x - x0, y - y0);
        if u > 140.0 - 0.05 * v || v < 20.0 + 0.1 * u {
            return None;
        }
        let energy_kj = 3000.0 * (-(355.0 - v) / 60.0).exp() * (-((u - 75.0) / 35.0).powi(2)).exp();
        (energy_kj >= 1.0).then(|| Ramp::Magma.at((energy_kj.log10()) / 3000f64.log10()))
    };
    let screen = |label: &str, v: f64| MapLine {
        label: label.into(),
        points_m: vec![[x0 + 5.0, y0 + v], [x0 + 145.0, y0 + v]],
    };
    let stems_m = (0..25 * 22)
        .map(|i| {
            let (a, b) = ((i % 25) as f64, (i / 25) as f64);
            let x = x0 + 3.0 + 6.0 * a + 3.0 * noise(2 * i);
            let y = y0 + 100.0 + 7.0 * b + 3.0 * noise(2 * i + 1);
            [x, y, 0.1 + 0.2 * noise(i + 7)]
        })
        .collect();
    let map = MapFigure {
        title: "Maximum kinetic energy, 10 000 rocks".into(),
        axes: Axes::new("easting (m)", "northing (m)"),
        extent_m: [x0, x0 + 150.0, y0, y0 + 355.0],
        fill: &fill,
        scale: Some(scale),
        lines: vec![screen("screen 185 m", 170.0), screen("screen 235 m", 120.0)],
        release_cells_m: (0..12)
            .map(|k| [x0 + 50.0 + 5.0 * f64::from(k), y0 + 345.0])
            .collect(),
        cell_size_m: 5.0,
        stems_m,
    };
    raster_map(path, &map).map(|_| ())
}

/// A wide site overview: shaded terrain without a colour bar; the stems are too dense to draw.
fn site_map(path: &std::path::Path) -> Result<(), PlotError> {
    let fill = |x: f64, y: f64| {
        let shade =
            0.5 + 0.5 * ((x - 2_600_000.0) / 700.0).sin() * ((y - 1_200_000.0) / 300.0).cos();
        let g = (150.0 + 80.0 * shade) as u8;
        Some((g - 30, g, g - 50))
    };
    let map = MapFigure {
        title: "Site overview".into(),
        axes: Axes::new("easting (m)", "northing (m)"),
        extent_m: [2_600_000.0, 2_610_000.0, 1_200_000.0, 1_200_500.0],
        fill: &fill,
        scale: None,
        lines: vec![MapLine {
            label: "road".into(),
            points_m: (0..50)
                .map(|i| {
                    [
                        2_599_900.0 + 210.0 * f64::from(i),
                        1_200_250.0 + 150.0 * (f64::from(i) / 5.0).sin(),
                    ]
                })
                .collect(),
        }],
        release_cells_m: vec![[2_603_000.0, 1_200_400.0], [2_603_020.0, 1_200_400.0]],
        cell_size_m: 20.0,
        stems_m: (0..200_000)
            .map(|i| [2_600_000.0 + 0.05 * i as f64, 1_200_100.0, 0.2])
            .collect(),
    };
    raster_map(path, &map).map(|_| ())
}
