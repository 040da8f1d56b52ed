//! The rigid engine's ground laws and ground classes (`[contact.ground]`,
//! `[[contact.ground_class]]`, `[terrain] ground_class`).
//!
//! - **`hard`**: the rock touches the DEM surface itself, with the Newton–Coulomb law of
//!   `[contact.ground]` (μ, ε_N, ε_T), optionally with `[contact.slippage]` friction.
//! - **`scarring`** (RAMMS::ROCKFALL's production ground; Lu et al. 2019, "Modelling rockfall
//!   impact with scarring in compactable soils", *Landslides* 16:2353, eqs. 9–14): a soft
//!   scarring layer over a hard rebound plane. The parameters of a ground class are those of
//!   [`ScarringGround`]; a per-cell map of class numbers selects one per impact.

use crate::ScenarioError;
use rockfall_raster::Field;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Which rock–ground law the rigid engine uses (`[contact.ground] model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GroundModel {
    /// Hard contact with the DEM surface (Leine et al. 2014; `[contact.ground]` μ, ε).
    #[default]
    Hard,
    /// The scarring layer over a hard rebound plane of Lu et al. 2019.
    Scarring,
}

impl GroundModel {
    /// The scenario file's name.
    pub fn name(self) -> &'static str {
        match self {
            GroundModel::Hard => "hard",
            GroundModel::Scarring => "scarring",
        }
    }
}

impl fmt::Display for GroundModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for GroundModel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "hard" => Ok(GroundModel::Hard),
            "scarring" => Ok(GroundModel::Scarring),
            other => Err(format!(
                "unknown ground model '{other}' (expected 'hard' or 'scarring')"
            )),
        }
    }
}

impl Serialize for GroundModel {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for GroundModel {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        String::deserialize(d)?
            .parse()
            .map_err(serde::de::Error::custom)
    }
}

/// The parameters of a scarring ground, under the symbols of Lu et al. 2019 (table 1).
/// Serialised with the keys of the scenario file.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ScarringGround {
    /// Soil mechanical strength M_e^Σ, MN/m² (eq. 11 takes it in kN/m²: Lu et al. 2019 list
    /// their values in MN/m² "only for the purpose of simple expression").
    pub me_mn_m2: f64,
    /// Scar drag coefficient of soil compaction C_s^I, dimensionless (eq. 12).
    pub c_s: f64,
    /// Scar drag coefficient of the soil's fluid behaviour C_f^I, dimensionless (eq. 12).
    pub c_f: f64,
    /// Soil density ρ_Σ, kg/m³ (eq. 9).
    pub rho_kg_m3: f64,
    /// Friction coefficient on the rebound plane at zero slippage μ_min^Λ (eq. 13).
    pub mu_min: f64,
    /// Friction coefficient approached at large slippage μ_max^Λ (eq. 13).
    pub mu_max: f64,
    /// Slippage softening β_Λ, 1/s: ṡ = −β s off the rebound plane (eq. 14).
    pub beta_per_s: f64,
    /// Slippage hardening κ_Λ, 1/m (eq. 13).
    pub kappa_per_m: f64,
}

impl ScarringGround {
    /// Lu et al. 2019's whole-trajectory set at Chant Sura ("Rockfall energy dissipation on a
    /// complete trajectory level"): M_e 15 MN/m², C_s 1.5, with C_f 1.0 ("assumed to be a
    /// constant value 1.0"), ρ_Σ 1700 kg/m³ ("a typical, constant value", after Dorren 2016)
    /// and the rebound plane's fixed set μ_min 0.55, μ_max 2.0, β 185 s⁻¹, κ 3 m⁻¹ ("Bartelt
    /// et al. 2016"). It is the `medium` ground class.
    pub const LU_2019: ScarringGround = ScarringGround {
        me_mn_m2: 15.0,
        c_s: 1.5,
        c_f: 1.0,
        rho_kg_m3: 1700.0,
        mu_min: 0.55,
        mu_max: 2.0,
        beta_per_s: 185.0,
        kappa_per_m: 3.0,
    };

    /// The rebound plane's slippage friction (eqs. 13–14).
    pub fn slippage(&self) -> crate::Slippage {
        crate::Slippage {
            mu_min: self.mu_min,
            mu_max: self.mu_max,
            beta_per_s: self.beta_per_s,
            kappa_per_m: self.kappa_per_m,
        }
    }

    /// The scar drag coefficient C_d^I = C_f^I + C_s^I (eq. 12).
    pub fn drag_coefficient(&self) -> f64 {
        self.c_f + self.c_s
    }

    /// The first key whose value is out of range, with the range expected.
    pub fn out_of_range(&self) -> Option<(&'static str, f64, &'static str)> {
        let checks = [
            ("me_mn_m2", self.me_mn_m2, self.me_mn_m2 > 0.0, "> 0"),
            ("c_s", self.c_s, self.c_s >= 0.0, "≥ 0"),
            ("c_f", self.c_f, self.c_f >= 0.0, "≥ 0"),
            ("rho_kg_m3", self.rho_kg_m3, self.rho_kg_m3 >= 0.0, "≥ 0"),
            ("mu_min", self.mu_min, self.mu_min >= 0.0, "≥ 0"),
            (
                "mu_max",
                self.mu_max,
                self.mu_max >= self.mu_min,
                "≥ mu_min",
            ),
            ("beta_per_s", self.beta_per_s, self.beta_per_s >= 0.0, "≥ 0"),
            (
                "kappa_per_m",
                self.kappa_per_m,
                self.kappa_per_m >= 0.0,
                "≥ 0",
            ),
        ];
        checks
            .into_iter()
            .find(|(_, v, ok, _)| !(*ok && v.is_finite()))
            .map(|(k, v, _, want)| (k, v, want))
    }
}

impl Default for ScarringGround {
    fn default() -> Self {
        ScarringGround::LU_2019
    }
}

/// A named ground class: a number for the per-cell map and a parameter set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GroundClass {
    /// The class number used in the `ground_class` map (1–255).
    pub id: u8,
    /// Its name (`medium`, or the user's).
    pub name: String,
    /// Its parameters.
    #[serde(flatten)]
    pub params: ScarringGround,
    /// Where its numbers come from.
    pub source: String,
}

/// The built-in ground classes, each with its source.
///
/// - `medium` (4): Lu et al. 2019's whole-trajectory set ([`ScarringGround::LU_2019`]);
/// - `lu2019-me10` (3) and `lu2019-me20` (5): the same with M_e 10 and 20 MN/m², the range of
///   their sensitivity study (table 5), a softer and a firmer soil.
///
/// RAMMS::ROCKFALL's named terrain categories (extra soft … extra hard) are not shipped: their
/// numbers were not in reach (the manual's table), and none is guessed.
pub fn builtin_ground_classes() -> Vec<GroundClass> {
    let lu = "Lu et al. 2019 (Landslides 16:2353)";
    let with_me = |id: u8, me_mn_m2: f64| GroundClass {
        id,
        name: format!("lu2019-me{me_mn_m2}"),
        params: ScarringGround {
            me_mn_m2,
            ..ScarringGround::LU_2019
        },
        source: format!("{lu}, table 5: the sensitivity study's M_e = {me_mn_m2} MN/m²"),
    };
    vec![
        with_me(3, 10.0),
        GroundClass {
            id: MEDIUM_CLASS_ID,
            name: "medium".into(),
            params: ScarringGround::LU_2019,
            source: format!(
                "{lu}, the whole-trajectory set at Chant Sura (M_e 15 MN/m², C_s 1.5, C_f 1.0, \
                 ρ_Σ 1700 kg/m³); rebound plane μ 0.55–2.0, β 185 s⁻¹, κ 3 m⁻¹ after Bartelt \
                 et al. 2016"
            ),
        },
        with_me(5, 20.0),
    ]
}

/// The number of the built-in `medium` class (Lu et al. 2019's whole-trajectory set).
pub const MEDIUM_CLASS_ID: u8 = 4;

/// The class named `name` among the built-ins (case-insensitive).
pub fn builtin_ground_class(name: &str) -> Option<GroundClass> {
    builtin_ground_classes()
        .into_iter()
        .find(|c| c.name.eq_ignore_ascii_case(name))
}

/// The scarring ground of a run: the class used where the map gives none (or everywhere,
/// without a map), and every class the map may name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScarringSettings {
    /// The ground where no `ground_class` map is given: the class `[contact.ground] class`
    /// names (default `medium`), with any parameter `[contact.ground]` sets.
    pub default: GroundClass,
    /// The classes a `ground_class` map may use: the built-ins and the scenario's own
    /// `[[contact.ground_class]]` (which replace a built-in of the same number).
    pub classes: Vec<GroundClass>,
}

impl Default for ScarringSettings {
    fn default() -> Self {
        let classes = builtin_ground_classes();
        let default = builtin_ground_class("medium").unwrap_or_else(|| classes[0].clone());
        ScarringSettings { default, classes }
    }
}

impl ScarringSettings {
    /// The class numbered `id`.
    pub fn class(&self, id: u8) -> Option<&GroundClass> {
        self.classes.iter().find(|c| c.id == id)
    }
}

impl ScarringSettings {
    /// Checks every class's parameters and that every cell of the `ground_class` map `map`
    /// names a class (0: the default one); errors name the key, or the cell.
    pub fn check(&self, map: Option<&Field>) -> Result<(), ScenarioError> {
        let classes = std::iter::once(("contact.ground".to_string(), &self.default)).chain(
            (self.classes.iter())
                .map(|c| (format!("contact.ground_class {} ({})", c.id, c.name), c)),
        );
        for (key, class) in classes {
            if let Some((k, v, want)) = class.params.out_of_range() {
                return Err(ScenarioError::OutOfRange {
                    parameter: format!("{key}.{k}"),
                    cell: None,
                    value: v,
                    expected: want.into(),
                });
            }
        }
        let Some(map) = map else { return Ok(()) };
        let known = |v: f64| v == 0.0 || self.classes.iter().any(|c| f64::from(c.id) == v);
        if let Some((row, col, value)) = map.find(|v| !known(v)) {
            let ids: Vec<String> = self.classes.iter().map(|c| c.id.to_string()).collect();
            return Err(ScenarioError::OutOfRange {
                parameter: "terrain.ground_class".into(),
                cell: Some((row, col)),
                value,
                expected: format!(
                    "0 (the default class) or a defined class: {} ([[contact.ground_class]] \
                     defines more)",
                    ids.join(", ")
                ),
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The built-in classes, their numbers and their M_e; `medium` is Lu et al. 2019's set.
    #[test]
    fn builtin_classes_are_the_sourced_sets() {
        let ids: Vec<(u8, String, f64)> = builtin_ground_classes()
            .into_iter()
            .map(|c| (c.id, c.name, c.params.me_mn_m2))
            .collect();
        assert_eq!(
            ids,
            [
                (3, "lu2019-me10".to_string(), 10.0),
                (4, "medium".to_string(), 15.0),
                (5, "lu2019-me20".to_string(), 20.0)
            ]
        );
        let m = builtin_ground_class("MEDIUM").unwrap().params;
        assert_eq!(m, ScarringGround::LU_2019);
        assert_eq!(
            (
                m.c_s,
                m.c_f,
                m.rho_kg_m3,
                m.mu_min,
                m.mu_max,
                m.beta_per_s,
                m.kappa_per_m
            ),
            (1.5, 1.0, 1700.0, 0.55, 2.0, 185.0, 3.0)
        );
        assert!((m.drag_coefficient() - 2.5).abs() < 1e-15);
        assert!(builtin_ground_class("loam").is_none());
    }

    /// Each key out of its range is named, with its value and the range.
    #[test]
    fn every_parameter_is_range_checked() {
        let base = ScarringGround::LU_2019;
        assert_eq!(base.out_of_range(), None);
        let cases: [(&str, ScarringGround); 9] = [
            (
                "me_mn_m2",
                ScarringGround {
                    me_mn_m2: 0.0,
                    ..base
                },
            ),
            ("c_s", ScarringGround { c_s: -1.0, ..base }),
            ("c_f", ScarringGround { c_f: -1.0, ..base }),
            (
                "rho_kg_m3",
                ScarringGround {
                    rho_kg_m3: -1.0,
                    ..base
                },
            ),
            (
                "mu_min",
                ScarringGround {
                    mu_min: -0.1,
                    ..base
                },
            ),
            (
                "mu_max",
                ScarringGround {
                    mu_max: 0.5,
                    ..base
                },
            ),
            (
                "beta_per_s",
                ScarringGround {
                    beta_per_s: -1.0,
                    ..base
                },
            ),
            (
                "kappa_per_m",
                ScarringGround {
                    kappa_per_m: -1.0,
                    ..base
                },
            ),
            (
                "me_mn_m2",
                ScarringGround {
                    me_mn_m2: f64::NAN,
                    ..base
                },
            ),
        ];
        for (key, g) in cases {
            let (k, _, _) = g.out_of_range().unwrap_or_else(|| panic!("{key} passed"));
            assert_eq!(k, key);
        }
    }

    /// `check` covers the default class as well as the map's classes.
    #[test]
    fn check_covers_the_default_class() {
        let mut s = ScarringSettings::default();
        s.check(None).unwrap();
        s.default.params.me_mn_m2 = 0.0;
        let e = s.check(None).unwrap_err().to_string();
        assert!(e.contains("contact.ground.me_mn_m2"), "{e}");
        let mut s = ScarringSettings::default();
        s.classes[0].params.c_f = -2.0;
        let e = s.check(None).unwrap_err().to_string();
        assert!(e.contains("lu2019-me10") && e.contains("c_f"), "{e}");
    }
}
