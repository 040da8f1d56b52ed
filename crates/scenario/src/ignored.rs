//! What a run ignores: the parameters of a scenario that its engine does not read, so that
//! `check` and `run` can name them instead of leaving the user to think they matter.

use crate::{Engine, GroundModel, Scenario};

impl Scenario {
    /// The parameters this scenario gives that its engine ignores, each as `key: why`.
    pub fn ignored_parameters(&self) -> Vec<String> {
        let s = &self.terrain.surface;
        let mut out = Vec::new();
        match self.engine {
            Engine::Rigid => {
                let mut surface = vec!["soiltype", "rg70", "rg20", "rg10"];
                if s.r_n.is_some() {
                    surface.push("r_n");
                }
                if s.rolling_friction.is_some() {
                    surface.push("rolling_friction");
                }
                out.push(format!(
                    "{}: the lumped engine's ground; the rigid engine's is [contact.ground] \
                     (model {}{})",
                    surface.join(", "),
                    self.contact.model,
                    match self.contact.model {
                        GroundModel::Scarring => " with terrain.ground_class",
                        GroundModel::Hard => "",
                    }
                ));
                match self.contact.model {
                    GroundModel::Scarring => {
                        out.push(
                            "contact.ground.mu: the scarring ground's friction is the \
                             slippage friction of its ground class (mu_min … mu_max)"
                                .into(),
                        );
                        if self.contact.slippage.is_some() {
                            out.push(
                                "contact.slippage: the hard ground's slippage friction; the \
                                 scarring ground has its own"
                                    .into(),
                            );
                        }
                    }
                    GroundModel::Hard if s.ground_class.is_some() => out.push(
                        "terrain.ground_class: read by the scarring ground only \
                         ([contact.ground] model = \"scarring\")"
                            .into(),
                    ),
                    GroundModel::Hard => {}
                }
            }
            Engine::Lumped => {
                if s.ground_class.is_some() {
                    out.push("terrain.ground_class: the rigid engine's ground classes".into());
                }
            }
        }
        out
    }
}
