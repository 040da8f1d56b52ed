//! The scenario file's `[contact]` tables: the rigid engine's contact laws, ground model and
//! ground classes (`rockfall_scenario::ground`, docs/rigid-ground.md).

use super::keywords;
use rockfall_scenario::{ContactSettings, GroundModel};
use schemars::JsonSchema;
use serde::Deserialize;

/// `[contact]`: the rigid engine's contact laws (seed 001 §2: Newton impact law with
/// restitution ε_N, ε_T and Coulomb friction μ), its ground model and ground classes.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContactSec {
    /// Rock–ground contact: the hard law's μ and ε, and the ground model.
    pub ground: Option<GroundSec>,
    /// Rock–tree contact.
    pub tree: Option<ContactParamsSec>,
    /// RAMMS slippage friction on the hard ground (Leine et al. 2014), replacing
    /// `[contact.ground] mu`: μ(s) = μ_min + (2/π)(μ_max − μ_min) atan(κ s). Default: none.
    pub slippage: Option<SlippageSec>,
    /// Ground classes of the scenario's own, for the `[terrain] ground_class` map (a class
    /// replaces a built-in of the same id). Default: none (the built-ins lu2019-me10 = 3,
    /// medium = 4, lu2019-me20 = 5).
    pub ground_class: Option<Vec<GroundClassSec>>,
}

/// `[contact.ground]`: the hard law's μ and ε, the ground model, and the scarring ground's
/// default class and parameters. The parameters M_e … κ override those of `class` (Lu et al.
/// 2019); they are checked whenever the table is given.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GroundSec {
    /// Hard ground: Coulomb friction coefficient μ (replaced by `[contact.slippage]` if
    /// given). Default 0.3. ≥ 0.
    #[schemars(extend("default" = ContactSettings::default().ground.mu, "minimum" = 0.0))]
    pub mu: Option<f64>,
    /// Normal restitution ε_N on the ground (scarring: on its rebound plane). Default 0. In
    /// [0, 1].
    #[schemars(extend(
        "default" = ContactSettings::default().ground.eps_n,
        "minimum" = 0.0,
        "maximum" = 1.0
    ))]
    pub eps_n: Option<f64>,
    /// Tangential restitution ε_T on the ground. Default 0. In [0, 1].
    #[schemars(extend(
        "default" = ContactSettings::default().ground.eps_t,
        "minimum" = 0.0,
        "maximum" = 1.0
    ))]
    pub eps_t: Option<f64>,
    /// The rock–ground law: `hard` (the DEM surface, Leine et al. 2014) or `scarring` (a
    /// soft scarring layer over a hard rebound plane, RAMMS::ROCKFALL, Lu et al. 2019); any
    /// letter case. Default hard.
    #[schemars(
        transform = keywords::ground_model,
        extend("default" = GroundModel::default().name())
    )]
    pub model: Option<String>,
    /// Scarring: the class used where no `[terrain] ground_class` map gives one: a built-in
    /// (lu2019-me10, medium, lu2019-me20) or a `[[contact.ground_class]]` name, any letter
    /// case. Default medium.
    #[schemars(transform = keywords::class_examples, extend("default" = "medium"))]
    pub class: Option<String>,
    /// Scarring: soil mechanical strength M_e, MN/m². Default: the class's (medium: 15). > 0.
    #[schemars(extend("x-unit" = "MN/m²", "exclusiveMinimum" = 0.0))]
    pub me_mn_m2: Option<f64>,
    /// Scarring: scar drag coefficient of soil compaction C_s. Default: the class's (medium:
    /// 1.5). ≥ 0.
    #[schemars(extend("minimum" = 0.0))]
    pub c_s: Option<f64>,
    /// Scarring: scar drag coefficient of the soil's fluid behaviour C_f. Default: the
    /// class's (medium: 1). ≥ 0.
    #[schemars(extend("minimum" = 0.0))]
    pub c_f: Option<f64>,
    /// Scarring: soil density ρ_Σ, kg/m³. Default: the class's (medium: 1700). ≥ 0.
    #[schemars(extend("x-unit" = "kg/m³", "minimum" = 0.0))]
    pub rho_kg_m3: Option<f64>,
    /// Scarring: friction on the rebound plane at zero slippage μ_min. Default: the class's
    /// (medium: 0.55). ≥ 0.
    #[schemars(extend("minimum" = 0.0))]
    pub mu_min: Option<f64>,
    /// Scarring: friction approached at large slippage μ_max. Default: the class's (medium:
    /// 2). At least `mu_min`.
    #[schemars(extend("minimum" = 0.0))]
    pub mu_max: Option<f64>,
    /// Scarring: slippage softening β off the rebound plane, 1/s. Default: the class's
    /// (medium: 185). ≥ 0.
    #[schemars(extend("x-unit" = "1/s", "minimum" = 0.0))]
    pub beta_per_s: Option<f64>,
    /// Scarring: slippage hardening κ, 1/m. Default: the class's (medium: 3). ≥ 0.
    #[schemars(extend("x-unit" = "1/m", "minimum" = 0.0))]
    pub kappa_per_m: Option<f64>,
}

/// The scarring ground's parameters as a file gives them, each optional (the class's value
/// stands in): the keys of `[contact.ground]` and `[[contact.ground_class]]`.
#[derive(Debug, Default, Clone, Copy)]
pub struct ScarringKeys {
    pub me_mn_m2: Option<f64>,
    pub c_s: Option<f64>,
    pub c_f: Option<f64>,
    pub rho_kg_m3: Option<f64>,
    pub mu_min: Option<f64>,
    pub mu_max: Option<f64>,
    pub beta_per_s: Option<f64>,
    pub kappa_per_m: Option<f64>,
}

macro_rules! scarring_keys {
    ($t:ty) => {
        impl $t {
            /// The scarring ground's keys of this table.
            pub fn scarring_keys(&self) -> ScarringKeys {
                ScarringKeys {
                    me_mn_m2: self.me_mn_m2,
                    c_s: self.c_s,
                    c_f: self.c_f,
                    rho_kg_m3: self.rho_kg_m3,
                    mu_min: self.mu_min,
                    mu_max: self.mu_max,
                    beta_per_s: self.beta_per_s,
                    kappa_per_m: self.kappa_per_m,
                }
            }
        }
    };
}
scarring_keys!(GroundSec);
scarring_keys!(GroundClassSec);

/// `[[contact.ground_class]]`: a ground class of the scenario's own for the scarring ground,
/// numbered for the `[terrain] ground_class` map; its unset parameters are its `base`'s.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GroundClassSec {
    /// The class's number in the `ground_class` map (replaces a built-in of that number).
    /// Required. In [1, 255].
    #[schemars(extend("minimum" = 1, "maximum" = 255))]
    pub id: i64,
    /// The class's name, for `[contact.ground] class`. Required.
    pub name: String,
    /// The built-in class its unset parameters come from (lu2019-me10, medium,
    /// lu2019-me20), any letter case. Default medium.
    #[schemars(transform = keywords::builtin_class, extend("default" = "medium"))]
    pub base: Option<String>,
    /// Where its numbers come from (shown in the outputs). Default "the scenario file".
    #[schemars(extend("default" = "the scenario file"))]
    pub source: Option<String>,
    /// Soil mechanical strength M_e, MN/m². Default: the base's (medium: 15). > 0.
    #[schemars(extend("x-unit" = "MN/m²", "exclusiveMinimum" = 0.0))]
    pub me_mn_m2: Option<f64>,
    /// Scar drag coefficient of soil compaction C_s. Default: the base's (medium: 1.5). ≥ 0.
    #[schemars(extend("minimum" = 0.0))]
    pub c_s: Option<f64>,
    /// Scar drag coefficient of the soil's fluid behaviour C_f. Default: the base's (medium:
    /// 1). ≥ 0.
    #[schemars(extend("minimum" = 0.0))]
    pub c_f: Option<f64>,
    /// Soil density ρ_Σ, kg/m³. Default: the base's (medium: 1700). ≥ 0.
    #[schemars(extend("x-unit" = "kg/m³", "minimum" = 0.0))]
    pub rho_kg_m3: Option<f64>,
    /// Friction on the rebound plane at zero slippage μ_min. Default: the base's (medium:
    /// 0.55). ≥ 0.
    #[schemars(extend("minimum" = 0.0))]
    pub mu_min: Option<f64>,
    /// Friction approached at large slippage μ_max. Default: the base's (medium: 2). At
    /// least `mu_min`.
    #[schemars(extend("minimum" = 0.0))]
    pub mu_max: Option<f64>,
    /// Slippage softening β off the rebound plane, 1/s. Default: the base's (medium: 185).
    /// ≥ 0.
    #[schemars(extend("x-unit" = "1/s", "minimum" = 0.0))]
    pub beta_per_s: Option<f64>,
    /// Slippage hardening κ, 1/m. Default: the base's (medium: 3). ≥ 0.
    #[schemars(extend("x-unit" = "1/m", "minimum" = 0.0))]
    pub kappa_per_m: Option<f64>,
}

/// `[contact.tree]`: rock–tree contact (seed 001 §2, table 1).
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContactParamsSec {
    /// Coulomb friction coefficient μ. Default 0.6. ≥ 0.
    #[schemars(extend("default" = ContactSettings::default().tree.mu, "minimum" = 0.0))]
    pub mu: Option<f64>,
    /// Normal restitution ε_N. Default 0. In [0, 1].
    #[schemars(extend(
        "default" = ContactSettings::default().tree.eps_n,
        "minimum" = 0.0,
        "maximum" = 1.0
    ))]
    pub eps_n: Option<f64>,
    /// Tangential restitution ε_T. Default 0. In [0, 1].
    #[schemars(extend(
        "default" = ContactSettings::default().tree.eps_t,
        "minimum" = 0.0,
        "maximum" = 1.0
    ))]
    pub eps_t: Option<f64>,
}

/// `[contact.slippage]`: RAMMS slippage friction on the hard ground, μ(s) = μ_min + (2/π)
/// (μ_max − μ_min) atan(κ s), with ṡ = |v| in contact and ṡ = −β s in flight. All four keys
/// are required.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SlippageSec {
    /// μ at zero slippage. Required. ≥ 0.
    #[schemars(extend("minimum" = 0.0))]
    pub mu_min: f64,
    /// μ approached at large slippage. Required. At least `mu_min`.
    #[schemars(extend("minimum" = 0.0))]
    pub mu_max: f64,
    /// Decay rate of the slippage in flight β, 1/s. Required. ≥ 0.
    #[schemars(extend("x-unit" = "1/s", "minimum" = 0.0))]
    pub beta_per_s: f64,
    /// Slippage scale κ, 1/m. Required. > 0.
    #[schemars(extend("x-unit" = "1/m", "exclusiveMinimum" = 0.0))]
    pub kappa_per_m: f64,
}
