//! Trees as rigid truncated cones and their contacts with the rock (seed 001 §2, fig. 1).
//!
//! A stem is a truncated cone standing on the terrain with its axis vertical: base radius r0
//! at the ground height of its axis, top radius r1 at height h above it, taper
//! `κ = (r1 − r0)/h` (seed 001 fig. 1c). Seed 001 finds contacts with an axis-aligned
//! bounding-box test followed by a separating-axis test; here the broad phase is the stem
//! index (axis within the rock's circumradius plus the stem radius, horizontally) and an
//! overlap of the vertical extents, and the narrow phase is GJK with EPA for penetration
//! (`parry3d-f64`) between the hull and the cone, both given by their support functions —
//! exact for the convex shapes, where a separating-axis test over a faceted cone would not
//! be.
//!
//! Stems of a forest carry a DBH and a height only. Their cone takes the taper of seed 001's
//! laboratory stem, d0 = 0.55 m to d1 = 0.45 m over h = 10 m: the diameter shrinks by
//! 0.01 m per metre of height ([`DIAMETER_TAPER_M_PER_M`]; the paper's κ = −0.01 is this
//! diameter taper: the radius taper of its definition is −0.005). The cone has the DBH at
//! breast height, 1.3 m; its top radius is kept at least 30 % of its base radius so that
//! thin tall stems do not end in a point.

use crate::math::{Quat, V3};
use crate::shape::RockGeometry;
use parry3d_f64::math::Pose;
use parry3d_f64::query::contact::contact_support_map_support_map;
use parry3d_f64::shape::SupportMap;
use rockfall_forest::{BREAST_HEIGHT_M, Stem, StemIndex};

/// Diameter lost per metre of height, m/m (seed 001 §2: (0.55 − 0.45) m over 10 m).
pub const DIAMETER_TAPER_M_PER_M: f64 = 0.01;

/// Smallest top radius as a share of the base radius.
const MIN_TOP_SHARE: f64 = 0.3;

/// A vertical truncated cone, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cone {
    /// Centre of the base (on the axis, at the ground), world frame, m.
    pub base_m: V3,
    /// Base radius r0, m.
    pub r0_m: f64,
    /// Top radius r1, m.
    pub r1_m: f64,
    /// Height h, m.
    pub h_m: f64,
}

impl Cone {
    /// The cone of a forest stem whose axis meets the ground at height `ground_z_m`.
    pub fn of_stem(stem: &Stem, ground_z_m: f64) -> Cone {
        let taper_r = 0.5 * DIAMETER_TAPER_M_PER_M;
        let r0 = stem.radius_m() + taper_r * BREAST_HEIGHT_M;
        let r1 = (r0 - taper_r * stem.height_m).max(MIN_TOP_SHARE * r0);
        Cone {
            base_m: V3::new(stem.x_m, stem.y_m, ground_z_m),
            r0_m: r0,
            r1_m: r1,
            h_m: stem.height_m,
        }
    }

    /// Radius at height `z_m` above the base (clamped to the cone), m.
    pub fn radius_at_m(&self, z_m: f64) -> f64 {
        let s = (z_m / self.h_m).clamp(0.0, 1.0);
        self.r0_m + (self.r1_m - self.r0_m) * s
    }
}

impl SupportMap for Cone {
    /// Support point in the cone's frame (origin at the base centre, z up): the farthest
    /// point of the base or the top circle in direction `dir`.
    fn local_support_point(&self, dir: V3) -> V3 {
        let lateral = dir.x.hypot(dir.y);
        let (ex, ey) = if lateral > 0.0 {
            (dir.x / lateral, dir.y / lateral)
        } else {
            (0.0, 0.0)
        };
        let bottom = V3::new(ex * self.r0_m, ey * self.r0_m, 0.0);
        let top = V3::new(ex * self.r1_m, ey * self.r1_m, self.h_m);
        if top.dot(dir) > bottom.dot(dir) {
            top
        } else {
            bottom
        }
    }
}

/// The hull as a support map, in the body frame.
struct Hull<'a>(&'a RockGeometry);

impl SupportMap for Hull<'_> {
    fn local_support_point(&self, dir: V3) -> V3 {
        self.0.support(dir)
    }
}

/// A rock–stem contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StemContact {
    /// Which stem (index in the forest's stem list).
    pub stem: usize,
    /// Contact point on the rock, world frame, m.
    pub point_m: V3,
    /// Unit normal pointing from the stem into the rock.
    pub normal: V3,
    /// Normal gap, m (≤ 0).
    pub gap_m: f64,
    /// Height of the contact above the stem's base, m.
    pub height_m: f64,
}

/// The contact of the rock at (`c`, `q`) with `cone`, if they touch or overlap.
pub fn cone_contact(geom: &RockGeometry, c: V3, q: Quat, cone: &Cone) -> Option<(V3, V3, f64)> {
    let rock = Pose::from_parts(c, q);
    let stem = Pose::from_translation(cone.base_m);
    let pos12 = rock.inv_mul(&stem);
    let contact = contact_support_map_support_map(&pos12, &Hull(geom), cone, 0.0)?;
    if contact.dist.is_nan() || contact.dist > 0.0 {
        return None;
    }
    let point = c + q * contact.point1;
    let normal = -(q * contact.normal1);
    Some((point, normal, contact.dist))
}

/// `true` when a vertical plane separates the rock at (`c`, `q`) from `cone`: the plane
/// facing the rock across the horizontal line from the cone's axis to the rock's centre. The
/// rock reaches towards the axis no farther than its support point in that direction, and
/// the cone no farther from its axis than its largest radius; when these leave a gap the two
/// are apart and GJK need not run (a separating-axis test, as in seed 001's narrow phase).
fn apart(geom: &RockGeometry, c: V3, q: Quat, cone: &Cone) -> bool {
    let (dx, dy) = (c.x - cone.base_m.x, c.y - cone.base_m.y);
    let distance_m = dx.hypot(dy);
    if distance_m <= 0.0 {
        return false;
    }
    let toward_axis = V3::new(-dx / distance_m, -dy / distance_m, 0.0);
    let toward_axis_body = q.inverse() * toward_axis;
    let reach_m = geom.support(toward_axis_body).dot(toward_axis_body);
    distance_m - reach_m > cone.r0_m.max(cone.r1_m)
}

/// The forest as cones, with the stem index for the broad phase.
#[derive(Debug, Clone)]
pub struct Stand<'f> {
    index: &'f StemIndex,
    cones: Vec<Cone>,
}

impl<'f> Stand<'f> {
    /// Cones of `stems` standing on the ground heights `ground_z_m` (one per stem; a stem
    /// off the terrain gets NaN and is never touched).
    pub fn new(stems: &[Stem], index: &'f StemIndex, ground_z_m: impl Fn(f64, f64) -> f64) -> Self {
        let cones = stems
            .iter()
            .map(|s| Cone::of_stem(s, ground_z_m(s.x_m, s.y_m)))
            .collect();
        Stand { index, cones }
    }

    /// Stems given as cones, one per stem of `index` (same order), for stems whose shape is
    /// known directly (the impact laboratory's stem of seed 001 §2).
    pub fn from_cones(cones: Vec<Cone>, index: &'f StemIndex) -> Self {
        debug_assert_eq!(cones.len(), index.len(), "one cone per indexed stem");
        Stand { index, cones }
    }

    /// Number of stems.
    pub fn len(&self) -> usize {
        self.cones.len()
    }

    /// `true` without stems.
    pub fn is_empty(&self) -> bool {
        self.cones.is_empty()
    }

    /// The cone of stem `k`.
    pub fn cone(&self, k: usize) -> &Cone {
        &self.cones[k]
    }

    /// Appends the contacts of the rock at (`c`, `q`) with the stems.
    pub fn contacts(&self, geom: &RockGeometry, c: V3, q: Quat, out: &mut Vec<StemContact>) {
        let radius = geom.circumradius_m;
        self.index
            .for_each_near_point(c.x, c.y, radius + 0.02, |hit| {
                let cone = &self.cones[hit.index];
                let z0 = cone.base_m.z;
                if !(c.z - radius <= z0 + cone.h_m && c.z + radius >= z0) || apart(geom, c, q, cone)
                {
                    return;
                }
                if let Some((point, normal, gap)) = cone_contact(geom, c, q, cone) {
                    out.push(StemContact {
                        stem: hit.index,
                        point_m: point,
                        normal,
                        gap_m: gap,
                        height_m: point.z - z0,
                    });
                }
            });
    }
}
