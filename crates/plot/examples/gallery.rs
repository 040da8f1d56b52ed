//! Draws one figure of each kind into a folder (default `target/plot-gallery`), to look at:
//! `cargo run -p rockfall-plot --example gallery -- DIR`.

use std::f64::consts::PI;
use std::path::PathBuf;

use rockfall_plot::{
    Axes, Bars, ColorScale, LinePanel, Panel, PlotError, Polyline, Series, colored_lines_panels,
    histogram, line_panels, scatter_panels,
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
    println!("wrote 4 figures to {}", dir.display());
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
