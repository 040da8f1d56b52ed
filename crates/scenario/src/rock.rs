//! The rock: shape, dimensions, density.

use crate::VolumeDistribution;
use rockfall_raster::Field;
use std::f64::consts::PI;
use std::path::PathBuf;

/// Block shapes of Rockyfor3D (`blshape` codes 1–4; 0 means "no block").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BlockShape {
    /// 1: rectangular block (a box d1 × d2 × d3).
    Rectangular,
    /// 2: ellipsoid with axes d1, d2, d3.
    Ellipsoidal,
    /// 3: sphere (diameter = mean of d1, d2, d3).
    Spherical,
    /// 4: disc (elliptic cylinder of thickness d1 and diameters d2, d3).
    Disc,
}

impl BlockShape {
    /// The shape of a `blshape` code; `None` for 0 and anything outside 1–4.
    pub fn from_code(code: f64) -> Option<Self> {
        match code {
            1.0 => Some(BlockShape::Rectangular),
            2.0 => Some(BlockShape::Ellipsoidal),
            3.0 => Some(BlockShape::Spherical),
            4.0 => Some(BlockShape::Disc),
            _ => None,
        }
    }

    /// The `blshape` code.
    pub fn code(self) -> u8 {
        match self {
            BlockShape::Rectangular => 1,
            BlockShape::Ellipsoidal => 2,
            BlockShape::Spherical => 3,
            BlockShape::Disc => 4,
        }
    }

    /// Name as used in scenario files.
    pub fn name(self) -> &'static str {
        match self {
            BlockShape::Rectangular => "box",
            BlockShape::Ellipsoidal => "ellipsoid",
            BlockShape::Spherical => "sphere",
            BlockShape::Disc => "disc",
        }
    }

    /// Volume of the block with dimensions d1, d2, d3 (m), m³: box d1·d2·d3; ellipsoid
    /// π/6·d1·d2·d3; sphere π/6·d³ with d the mean dimension; disc π/4·d1·d2·d3.
    pub fn volume_m3(self, d_m: [f64; 3]) -> f64 {
        let [a, b, c] = d_m;
        match self {
            BlockShape::Rectangular => a * b * c,
            BlockShape::Ellipsoidal => PI / 6.0 * a * b * c,
            BlockShape::Spherical => {
                let d = (a + b + c) / 3.0;
                PI / 6.0 * d * d * d
            }
            BlockShape::Disc => PI / 4.0 * a * b * c,
        }
    }
}

/// Named rock shapes and their extents (x, y, z) before scaling to a volume, m: the natural
/// rocks of seed 001 (table 2) and the EOTA test blocks of EAD 340059-00-0106 (at 1 m³).
pub const NAMED_SHAPES: [(&str, [f64; 3]); 5] = [
    ("cubic1.2", [0.38, 0.36, 0.31]),
    ("flat2.2", [0.48, 0.42, 0.22]),
    ("long2.2", [0.55, 0.31, 0.25]),
    ("eota111", [EOTA111_EDGE_M, EOTA111_EDGE_M, EOTA111_EDGE_M]),
    (
        "eota221",
        [
            2.0 * EOTA221_SHORT_M,
            2.0 * EOTA221_SHORT_M,
            EOTA221_SHORT_M,
        ],
    ),
];

/// Edge of the bounding cube of the 1 m³ EOTA₁₁₁ block, m: (24/17)^(1/3), since the block
/// fills 17/24 of its cube (see `rockfall_rigid::shape::named::eota_points`). The Chant Sura
/// shape file `1m3_EOTA_111_cube.pts` (Caviezel et al. 2020, EnviDat,
/// doi:10.16904/envidat.174) spans 1.122 m, this edge rounded to the millimetre.
pub const EOTA111_EDGE_M: f64 = 1.121_813_787_760_367;

/// Short side of the bounding box (2:2:1) of the 1 m³ EOTA₂₂₁ block, m: (24/68)^(1/3). The
/// Chant Sura file `1m3_EOTA_221_plate.pts` spans 1.4136 × 1.4136 × 0.7068 m: the same box
/// volume as its 1.122 m cube, i.e. the EOTA₁₁₁ block stretched 2:2:1.
pub const EOTA221_SHORT_M: f64 = 0.706_698_402_630_793_1;

/// Volume of the EOTA blocks as the Chant Sura shape files give them, m³: the default for
/// `eota111` and `eota221` (scale them with `volume_m3` or `mass_kg`).
pub const EOTA_VOLUME_M3: f64 = 1.0;

/// The volume a named shape takes when the scenario gives none, m³: 1 m³ for the EOTA
/// blocks, seed 001's 0.02 m³ for its rocks and the rough rocks.
pub fn default_volume_m3(name: &str) -> f64 {
    if name.starts_with("eota") {
        EOTA_VOLUME_M3
    } else {
        SEED_001_VOLUME_M3
    }
}

/// Volume of the seed 001 rocks (table 1), m³: the default for named shapes.
pub const SEED_001_VOLUME_M3: f64 = 0.02;

/// What the rock looks like.
#[derive(Debug, Clone, PartialEq)]
pub enum RockShape {
    /// One block shape everywhere.
    Block(BlockShape),
    /// A Rockyfor3D `blshape` raster: a code 1–4 per source cell.
    PerCell(Field),
    /// A named natural shape of seed 001 (`cubic1.2`, `flat2.2`, `long2.2`; rigid engine).
    Named(String),
    /// A point cloud or mesh file whose convex hull is the rock (rigid engine), not read yet:
    /// what [`RockShape::parse`] gives for a path. Readers turn it into [`RockShape::Cloud`]
    /// (`rockfall_io::shape::read_shape`); the engines take only points and refuse it.
    File(PathBuf),
    /// The points of a point cloud or mesh file, read: the rock is their convex hull (rigid
    /// engine).
    Cloud {
        /// The file the points were read from, as named (resolved against the scenario's
        /// folder for scenario files); for descriptions and written scenarios.
        source: PathBuf,
        /// The points, m, in the file's own coordinates.
        points_m: Vec<[f64; 3]>,
    },
}

impl RockShape {
    /// Parses a scenario `shape` value: `sphere`, `box` (or `rectangular`), `ellipsoid`,
    /// `disc`, a named seed 001 shape, or else a file path (anything with an extension).
    pub fn parse(s: &str) -> Result<RockShape, String> {
        let lower = s.to_ascii_lowercase();
        let block = match lower.as_str() {
            "sphere" | "spherical" => Some(BlockShape::Spherical),
            "box" | "rectangular" | "cuboid" => Some(BlockShape::Rectangular),
            "ellipsoid" | "ellipsoidal" => Some(BlockShape::Ellipsoidal),
            "disc" | "disk" => Some(BlockShape::Disc),
            _ => None,
        };
        if let Some(b) = block {
            return Ok(RockShape::Block(b));
        }
        if NAMED_SHAPES.iter().any(|(n, _)| *n == lower) || RoughRock::parse(&lower).is_some() {
            return Ok(RockShape::Named(lower));
        }
        let ext = std::path::Path::new(s)
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("xyz" | "csv" | "txt" | "obj" | "ply" | "stl") => Ok(RockShape::File(s.into())),
            _ => Err(format!(
                "unknown shape `{s}` (expected sphere, box, ellipsoid, disc, cubic1.2, flat2.2, \
                 long2.2, eota111, eota221, a rough rock such as rough-flat2.2-7, or a \
                 .xyz/.csv/.obj/.ply/.stl file)"
            )),
        }
    }

    /// Short description.
    pub fn describe(&self) -> String {
        match self {
            RockShape::Block(b) => b.name().into(),
            RockShape::PerCell(_) => "per cell (blshape raster)".into(),
            RockShape::Named(n) => n.clone(),
            RockShape::File(p) | RockShape::Cloud { source: p, .. } => {
                format!("hull of {}", p.display())
            }
        }
    }
}

/// The rock released from every source.
#[derive(Debug, Clone, PartialEq)]
pub struct RockSpec {
    /// Shape.
    pub shape: RockShape,
    /// Dimensions d1, d2, d3, m (Rockyfor3D: height, width, length); for a sphere all three
    /// equal the diameter. Ignored for named, file and point-cloud shapes, which carry their
    /// own.
    pub dims_m: [Field; 3],
    /// When set, the shape is rescaled to this volume, m³.
    pub volume_m3: Option<f64>,
    /// Rock density, kg/m³.
    pub density_kg_m3: Field,
    /// Each rock's volume is drawn uniformly within ± this share of the volume the other keys
    /// give, %, in [0, 100) (default 0: every rock alike). Rockyfor3D's "additional variation
    /// of the block volume" (Dorren 2016 §2.5).
    pub volume_variation_percent: f64,
    /// When set, each rock's volume is drawn from this distribution, m³, replacing the volume
    /// the other keys give (their shape and density kept); excludes
    /// `volume_variation_percent`. See [`VolumeDistribution`].
    pub volume_distribution: Option<VolumeDistribution>,
}

impl RockSpec {
    /// A sphere of `diameter_m` and `density_kg_m3`.
    pub fn sphere(diameter_m: f64, density_kg_m3: f64) -> Self {
        RockSpec {
            shape: RockShape::Block(BlockShape::Spherical),
            dims_m: [
                Field::Const(diameter_m),
                Field::Const(diameter_m),
                Field::Const(diameter_m),
            ],
            volume_m3: None,
            density_kg_m3: Field::Const(density_kg_m3),
            volume_variation_percent: 0.0,
            volume_distribution: None,
        }
    }

    /// A named shape (`cubic1.2`, …, `eota111`, `eota221`) or rough rock (`rough-flat2.2-7`,
    /// see [`RoughRock`]) of `volume_m3` (default [`default_volume_m3`]).
    pub fn named(name: &str, volume_m3: Option<f64>, density_kg_m3: f64) -> Option<Self> {
        let dims = named_dims(name)?;
        Some(RockSpec {
            shape: RockShape::Named(name.into()),
            dims_m: dims.map(Field::Const),
            volume_m3: Some(volume_m3.unwrap_or_else(|| default_volume_m3(name))),
            density_kg_m3: Field::Const(density_kg_m3),
            volume_variation_percent: 0.0,
            volume_distribution: None,
        })
    }

    /// Block shape and dimensions at cell (row, col), for the lumped engine; `None` where the
    /// shape is not a block or a value is missing.
    pub fn block_at(&self, row: usize, col: usize) -> Option<(BlockShape, [f64; 3])> {
        let shape = match &self.shape {
            RockShape::Block(b) => *b,
            RockShape::PerCell(f) => BlockShape::from_code(f.at(row, col)?)?,
            _ => return None,
        };
        let d = [
            self.dims_m[0].at(row, col)?,
            self.dims_m[1].at(row, col)?,
            self.dims_m[2].at(row, col)?,
        ];
        let d = match self.volume_m3 {
            Some(v) => {
                let s = (v / shape.volume_m3(d)).cbrt();
                d.map(|x| x * s)
            }
            None => d,
        };
        Some((shape, d))
    }
}

/// Dimensions (x, y, z) of a named seed 001 shape as listed in its table 2, m.
pub fn named_dims(name: &str) -> Option<[f64; 3]> {
    (NAMED_SHAPES.iter())
        .find(|(n, _)| *n == name)
        .map(|(_, d)| *d)
        .or_else(|| RoughRock::parse(name).map(|r| r.dims_m()))
}

/// A member of a seeded ensemble of rough rocks, named `rough-<class><Π>-<member>`
/// (`rough-flat2.2-7`): a class (`cubic`, `flat`, `long`), an aspect ratio Π = l_max/l_min
/// (1 ≤ Π ≤ 10; ≤ 1.2 for cubic, > 1.2 otherwise) and a member number. The rigid engine
/// builds it as the convex hull of random points with surface roughness
/// (`rockfall_rigid::shape::rough_points`); its bulk proportions are those of seed 001's
/// rock of the class (table 2), stretched to Π.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughRock {
    /// `cubic`, `flat` or `long`.
    pub class: &'static str,
    /// Aspect ratio Π = l_max / l_min.
    pub aspect_ratio: f64,
    /// Ensemble member (seeds its points).
    pub member: u64,
}

impl RoughRock {
    /// The rock named `name`, when it is a well-formed rough-rock name.
    pub fn parse(name: &str) -> Option<RoughRock> {
        let rest = name.strip_prefix("rough-")?;
        let (shape, member) = rest.rsplit_once('-')?;
        let member: u64 = member.parse().ok()?;
        let class = ["cubic", "flat", "long"]
            .into_iter()
            .find(|c| shape.starts_with(c))?;
        let aspect_ratio: f64 = shape[class.len()..].parse().ok()?;
        let cubic = (aspect_ratio * 10.0).round() <= 12.0;
        let ok = aspect_ratio.is_finite()
            && (1.0..=10.0).contains(&aspect_ratio)
            && (cubic == (class == "cubic"));
        ok.then_some(RoughRock {
            class,
            aspect_ratio,
            member,
        })
    }

    /// The principal lengths, m, before volume scaling: l_min = 0.25 m, l_max = Π l_min and
    /// l_mid placed between them as in seed 001's rock of the class (table 2: cubic1.2
    /// 0.38/0.36/0.31 → 0.71 of the way from l_min to l_max, flat2.2 0.48/0.42/0.22 → 0.77,
    /// long2.2 0.55/0.31/0.25 → 0.20), so the class comes out as named.
    pub fn dims_m(&self) -> [f64; 3] {
        let l_min = 0.25;
        let l_max = self.aspect_ratio * l_min;
        let share = match self.class {
            "cubic" => 0.71,
            "flat" => 0.77,
            _ => 0.20,
        };
        [l_max, l_min + share * (l_max - l_min), l_min]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_parse_and_volumes() {
        assert_eq!(
            RockShape::parse("Sphere"),
            Ok(RockShape::Block(BlockShape::Spherical))
        );
        assert_eq!(
            RockShape::parse("flat2.2"),
            Ok(RockShape::Named("flat2.2".into()))
        );
        assert_eq!(
            RockShape::parse("rocks/r1.obj"),
            Ok(RockShape::File("rocks/r1.obj".into()))
        );
        // read or not, a file's rock is described by its path (summary.json's `rock_shape`)
        let cloud = RockShape::Cloud {
            source: "rocks/r1.obj".into(),
            points_m: vec![[0.0; 3]; 4],
        };
        assert_eq!(cloud.describe(), "hull of rocks/r1.obj");
        assert_eq!(
            RockShape::File("rocks/r1.obj".into()).describe(),
            cloud.describe()
        );
        assert!(
            RockShape::parse("pyramid")
                .unwrap_err()
                .contains("unknown shape")
        );
        // seed 000: 0.95 m spheres have ≈ 0.45 m³ (the paper's mean volume is 0.49 m³)
        let v = BlockShape::Spherical.volume_m3([0.95; 3]);
        assert!((v - 0.4489).abs() < 1e-3, "{v}");
        assert_eq!(BlockShape::Rectangular.volume_m3([1.0, 2.0, 3.0]), 6.0);
        for code in 1..=4 {
            assert_eq!(
                BlockShape::from_code(code as f64).map(BlockShape::code),
                Some(code)
            );
        }
        assert_eq!(BlockShape::from_code(0.0), None);
    }

    #[test]
    fn volume_rescales_block_dimensions() {
        let mut r = RockSpec::sphere(1.0, 2700.0);
        r.volume_m3 = Some(0.02);
        let (shape, d) = r.block_at(0, 0).unwrap();
        assert!((shape.volume_m3(d) - 0.02).abs() < 1e-12);
        assert!(
            (d[0] / 2.0 - 0.168).abs() < 1e-3,
            "seed 001: sphere radius 0.168 m"
        );
    }
}
