//! Tree species, as far as rockfall modelling distinguishes them.
//!
//! Species matter to a rockfall model through the energy a stem can absorb before it breaks:
//! Dorren & Berger (2006) express it as a fracture-energy ratio relative to *Abies alba*. Those
//! ratios belong to the engine that uses them and are deliberately **not** defined here; this
//! module only names species and reads them from the many ways inventories write them.
//!
//! The named species are the six that dominate Alpine protection forests. Stands described only
//! by a conifer share expand to [`Species::OtherConifer`] and [`Species::OtherBroadleaf`];
//! [`Species::Unknown`] is for tree lists whose species column is empty or unrecognised by the
//! caller's choice.
//!
//! ```
//! use rockfall_forest::Species;
//! assert_eq!(Species::parse("Picea_abies"), Some(Species::PiceaAbies));
//! assert_eq!(Species::parse("Norway spruce"), Some(Species::PiceaAbies));
//! assert_eq!(Species::parse("fasy"), Some(Species::FagusSylvatica));
//! assert_eq!(Species::parse("broadleaved"), Some(Species::OtherBroadleaf));
//! assert_eq!(Species::LarixDecidua.is_conifer(), Some(true));
//! ```

use std::fmt;

/// A tree species or species group.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Species {
    /// Silver fir, *Abies alba* Mill. (code `abal`); the reference species of the
    /// fracture-energy ratios.
    AbiesAlba,
    /// Norway spruce, *Picea abies* (L.) H. Karst. (code `piab`).
    PiceaAbies,
    /// European beech, *Fagus sylvatica* L. (code `fasy`).
    FagusSylvatica,
    /// Sycamore maple, *Acer pseudoplatanus* L. (code `acps`).
    AcerPseudoplatanus,
    /// European larch, *Larix decidua* Mill. (code `lade`); a conifer that sheds its needles.
    LarixDecidua,
    /// Scots pine, *Pinus sylvestris* L. (code `pisy`).
    PinusSylvestris,
    /// A conifer of another or unspecified species.
    OtherConifer,
    /// A broadleaved tree of another or unspecified species.
    OtherBroadleaf,
    /// Species not known, not even whether conifer or broadleaf.
    Unknown,
}

impl Species {
    /// Every variant, in declaration order.
    pub const ALL: [Species; 9] = [
        Species::AbiesAlba,
        Species::PiceaAbies,
        Species::FagusSylvatica,
        Species::AcerPseudoplatanus,
        Species::LarixDecidua,
        Species::PinusSylvestris,
        Species::OtherConifer,
        Species::OtherBroadleaf,
        Species::Unknown,
    ];

    /// Whether the species is a conifer (`Some(true)`), a broadleaf (`Some(false)`), or not
    /// known (`None`, for [`Species::Unknown`]).
    pub fn is_conifer(self) -> Option<bool> {
        match self {
            Species::AbiesAlba
            | Species::PiceaAbies
            | Species::LarixDecidua
            | Species::PinusSylvestris
            | Species::OtherConifer => Some(true),
            Species::FagusSylvatica | Species::AcerPseudoplatanus | Species::OtherBroadleaf => {
                Some(false)
            }
            Species::Unknown => None,
        }
    }

    /// The Latin binomial ("Abies alba"), or for the groups a plain description
    /// ("other conifer", "other broadleaf", "unknown"). [`Species::parse`] reads every name
    /// back.
    pub fn name(self) -> &'static str {
        match self {
            Species::AbiesAlba => "Abies alba",
            Species::PiceaAbies => "Picea abies",
            Species::FagusSylvatica => "Fagus sylvatica",
            Species::AcerPseudoplatanus => "Acer pseudoplatanus",
            Species::LarixDecidua => "Larix decidua",
            Species::PinusSylvestris => "Pinus sylvestris",
            Species::OtherConifer => "other conifer",
            Species::OtherBroadleaf => "other broadleaf",
            Species::Unknown => "unknown",
        }
    }

    /// The four-letter inventory code (first two letters of genus and species, `"piab"`), for
    /// the six named species only.
    pub fn code(self) -> Option<&'static str> {
        match self {
            Species::AbiesAlba => Some("abal"),
            Species::PiceaAbies => Some("piab"),
            Species::FagusSylvatica => Some("fasy"),
            Species::AcerPseudoplatanus => Some("acps"),
            Species::LarixDecidua => Some("lade"),
            Species::PinusSylvestris => Some("pisy"),
            _ => None,
        }
    }

    /// Reads a species from a Latin name ("Abies alba", "abies_alba"), an English common name
    /// ("silver fir", "Norway spruce", "beech", "sycamore", "larch", "Scots pine"), a
    /// four-letter code ("abal", "piab", "fasy", "acps", "lade", "pisy") or a group word
    /// ("conifer", "coniferous", "broadleaf", "broadleaved", "broad-leaved", "deciduous",
    /// "other conifer", "other broadleaf", "unknown").
    ///
    /// Case is ignored, and `_`, `-` and runs of spaces all count as one space. Note that
    /// "deciduous" means a broadleaf here, although larch is a deciduous conifer. Returns
    /// `None` for anything else.
    pub fn parse(text: &str) -> Option<Species> {
        let normalised = text
            .to_lowercase()
            .replace(['_', '-'], " ")
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
        let species = match normalised.as_str() {
            "abies alba" | "silver fir" | "european silver fir" | "abal" => Species::AbiesAlba,
            "picea abies" | "norway spruce" | "spruce" | "piab" => Species::PiceaAbies,
            "fagus sylvatica" | "beech" | "european beech" | "common beech" | "fasy" => {
                Species::FagusSylvatica
            }
            "acer pseudoplatanus" | "sycamore" | "sycamore maple" | "acps" => {
                Species::AcerPseudoplatanus
            }
            "larix decidua" | "larch" | "european larch" | "lade" => Species::LarixDecidua,
            "pinus sylvestris" | "scots pine" | "scotch pine" | "pisy" => Species::PinusSylvestris,
            "conifer" | "coniferous" | "other conifer" => Species::OtherConifer,
            "broadleaf" | "broadleaved" | "broad leaved" | "broad leaf" | "deciduous"
            | "other broadleaf" => Species::OtherBroadleaf,
            "unknown" => Species::Unknown,
            _ => return None,
        };
        Some(species)
    }
}

impl fmt::Display for Species {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_codes_parse_back() {
        for species in Species::ALL {
            assert_eq!(Species::parse(species.name()), Some(species), "{species}");
            if let Some(code) = species.code() {
                assert_eq!(Species::parse(code), Some(species));
                assert_eq!(Species::parse(&code.to_uppercase()), Some(species));
            }
        }
    }

    #[test]
    fn parse_accepts_common_spellings() {
        let cases = [
            ("ABIES_ALBA", Species::AbiesAlba),
            ("  Abies   alba ", Species::AbiesAlba),
            ("Silver fir", Species::AbiesAlba),
            ("norway_spruce", Species::PiceaAbies),
            ("Beech", Species::FagusSylvatica),
            ("sycamore", Species::AcerPseudoplatanus),
            ("Larch", Species::LarixDecidua),
            ("Scots Pine", Species::PinusSylvestris),
            ("pinus-sylvestris", Species::PinusSylvestris),
            ("Conifer", Species::OtherConifer),
            ("broadleaf", Species::OtherBroadleaf),
            ("Broad-leaved", Species::OtherBroadleaf),
            ("deciduous", Species::OtherBroadleaf),
        ];
        for (text, want) in cases {
            assert_eq!(Species::parse(text), Some(want), "{text:?}");
        }
        for text in ["", "oak", "abies", "pinus sylvestris x"] {
            assert_eq!(Species::parse(text), None, "{text:?}");
        }
    }

    #[test]
    fn conifer_classification() {
        let conifers = [
            Species::AbiesAlba,
            Species::PiceaAbies,
            Species::LarixDecidua,
            Species::PinusSylvestris,
            Species::OtherConifer,
        ];
        for species in Species::ALL {
            let want = if species == Species::Unknown {
                None
            } else {
                Some(conifers.contains(&species))
            };
            assert_eq!(species.is_conifer(), want, "{species}");
        }
    }
}
