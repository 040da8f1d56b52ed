//! The scenario file's `[contact]` tables: the rigid engine's contact laws, its ground model and
//! ground classes (`rockfall_scenario::ground`).

use crate::schema::{self, ScarringKeys};
use rockfall_scenario::ground::{builtin_ground_class, builtin_ground_classes};
use rockfall_scenario::{
    ContactParams, ContactSettings, GroundClass, GroundModel, ScarringGround, ScarringSettings,
    Slippage,
};

/// The contact settings of `c` (the defaults without it); `Err` holds the key at fault and what
/// is wrong with it.
pub(crate) fn contact(c: Option<schema::ContactSec>) -> Result<ContactSettings, (String, String)> {
    let d = ContactSettings::default();
    let Some(c) = c else { return Ok(d) };
    let tree = match c.tree {
        None => d.tree,
        Some(p) => ContactParams {
            mu: p.mu.unwrap_or(d.tree.mu),
            eps_n: p.eps_n.unwrap_or(d.tree.eps_n),
            eps_t: p.eps_t.unwrap_or(d.tree.eps_t),
        },
    };
    let (ground, model, scarring) = ground(c.ground.as_ref(), c.ground_class.as_deref(), &d)?;
    Ok(ContactSettings {
        ground,
        tree,
        slippage: c.slippage.map(|s| Slippage {
            mu_min: s.mu_min,
            mu_max: s.mu_max,
            beta_per_s: s.beta_per_s,
            kappa_per_m: s.kappa_per_m,
        }),
        model,
        scarring,
    })
}

type Ground = (ContactParams, GroundModel, ScarringSettings);

/// `[contact.ground]` and `[[contact.ground_class]]`.
fn ground(
    g: Option<&schema::GroundSec>,
    own: Option<&[schema::GroundClassSec]>,
    d: &ContactSettings,
) -> Result<Ground, (String, String)> {
    let err = |k: &str, m: String| (k.to_string(), m);
    let mut classes = builtin_ground_classes();
    for (k, c) in own.unwrap_or_default().iter().enumerate() {
        let key = format!("contact.ground_class[{}]", k + 1);
        let id = u8::try_from(c.id)
            .ok()
            .filter(|&id| id >= 1)
            .ok_or_else(|| err(&format!("{key}.id"), format!("{} is not in 1–255", c.id)))?;
        let base = match &c.base {
            None => ScarringGround::LU_2019,
            Some(b) => named(b).map_err(|m| err(&format!("{key}.base"), m))?.params,
        };
        let class = GroundClass {
            id,
            name: c.name.clone(),
            params: apply(base, &c.scarring_keys()),
            source: c
                .source
                .clone()
                .unwrap_or_else(|| "the scenario file".into()),
        };
        if let Some((k, v, want)) = class.params.out_of_range() {
            return Err(err(
                &format!("{key}.{k}"),
                format!("value {v} is out of range ({want})"),
            ));
        }
        match classes.iter_mut().find(|x| x.id == id) {
            Some(slot) => *slot = class,
            None => classes.push(class),
        }
    }
    classes.sort_by_key(|c| c.id);
    let Some(g) = g else {
        let default = ScarringSettings::default().default;
        return Ok((d.ground, d.model, ScarringSettings { default, classes }));
    };
    let model = match &g.model {
        None => d.model,
        Some(m) => m.parse().map_err(|m| err("contact.ground.model", m))?,
    };
    let mut default = match &g.class {
        None => named("medium").map_err(|m| err("contact.ground.class", m))?,
        Some(name) => (classes.iter())
            .find(|c| c.name.eq_ignore_ascii_case(name))
            .cloned()
            .map_or_else(|| named(name), Ok)
            .map_err(|m| err("contact.ground.class", m))?,
    };
    let keys = g.scarring_keys();
    default.params = apply(default.params, &keys);
    if let Some((k, v, want)) = default.params.out_of_range() {
        return Err(err(
            &format!("contact.ground.{k}"),
            format!("value {v} is out of range ({want})"),
        ));
    }
    let ground = ContactParams {
        mu: g.mu.unwrap_or(d.ground.mu),
        eps_n: g.eps_n.unwrap_or(d.ground.eps_n),
        eps_t: g.eps_t.unwrap_or(d.ground.eps_t),
    };
    Ok((ground, model, ScarringSettings { default, classes }))
}

/// The built-in class `name`, or what the names are.
fn named(name: &str) -> Result<GroundClass, String> {
    builtin_ground_class(name).ok_or_else(|| {
        let names: Vec<String> = builtin_ground_classes()
            .into_iter()
            .map(|c| c.name)
            .collect();
        format!(
            "unknown ground class '{name}' (built-in: {}; or a [[contact.ground_class]] name)",
            names.join(", ")
        )
    })
}

/// `base` with the keys the file gives.
fn apply(base: ScarringGround, k: &ScarringKeys) -> ScarringGround {
    ScarringGround {
        me_mn_m2: k.me_mn_m2.unwrap_or(base.me_mn_m2),
        c_s: k.c_s.unwrap_or(base.c_s),
        c_f: k.c_f.unwrap_or(base.c_f),
        rho_kg_m3: k.rho_kg_m3.unwrap_or(base.rho_kg_m3),
        mu_min: k.mu_min.unwrap_or(base.mu_min),
        mu_max: k.mu_max.unwrap_or(base.mu_max),
        beta_per_s: k.beta_per_s.unwrap_or(base.beta_per_s),
        kappa_per_m: k.kappa_per_m.unwrap_or(base.kappa_per_m),
    }
}
