//! DGMPM's spatial order ([`SchemeOrder`]): the paper's first-order Godunov flux, or the
//! same with limited second-order wave corrections (LeVeque 2002, §6.8-6.15; Clawpack
//! classic `order = 2`). Written as an integer in scene files (`order = 2`) and on the
//! command line (`--order 2`); the names are spelled here once.
use serde::{Deserialize, Serialize};

/// DGMPM's spatial order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SchemeOrder {
    /// The paper's first-order Godunov (upwind) face flux (default).
    First,
    /// The Godunov flux plus the limited second-order wave corrections
    /// `½ Σ_p |s^p| (1 − Δt|s^p|/Δx) φ(θ^p) W^p` (`limiter`).
    Second,
}

impl SchemeOrder {
    /// Every variant, in declaration order.
    pub const ALL: [Self; 2] = [Self::First, Self::Second];
    /// Every name, in declaration order.
    pub const NAMES: &'static [&'static str] = &["1", "2"];

    /// The name used in scene files, flags, tables and file names.
    pub fn name(self) -> &'static str {
        match self {
            Self::First => "1",
            Self::Second => "2",
        }
    }

    /// The order as a number.
    pub fn number(self) -> u8 {
        match self {
            Self::First => 1,
            Self::Second => 2,
        }
    }

    /// The variant of a name.
    pub fn parse(text: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|v| v.name() == text)
    }

    /// The allowed values, for error messages.
    pub fn allowed() -> String {
        "1 or 2".to_string()
    }
}

impl std::fmt::Display for SchemeOrder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for SchemeOrder {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u8(self.number())
    }
}

impl<'de> Deserialize<'de> for SchemeOrder {
    /// An integer (`order = 2`) or its name as a string (`order = "2"`).
    fn deserialize<De: serde::Deserializer<'de>>(d: De) -> Result<Self, De::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = SchemeOrder;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "the order, {}", SchemeOrder::allowed())
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<SchemeOrder, E> {
                self.visit_str(&v.to_string())
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<SchemeOrder, E> {
                self.visit_str(&v.to_string())
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<SchemeOrder, E> {
                Err(E::custom(format!(
                    "unknown value {v} (allowed: {})",
                    SchemeOrder::allowed()
                )))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<SchemeOrder, E> {
                SchemeOrder::parse(v).ok_or_else(|| {
                    E::custom(format!(
                        "unknown value {v} (allowed: {})",
                        SchemeOrder::allowed()
                    ))
                })
            }
        }
        d.deserialize_any(Visitor)
    }
}

#[cfg(feature = "clap")]
impl clap::ValueEnum for SchemeOrder {
    fn value_variants<'a>() -> &'a [Self] {
        &Self::ALL
    }
    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        Some(clap::builder::PossibleValue::new(self.name()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Deserialize)]
    struct S {
        order: SchemeOrder,
    }

    #[test]
    fn integers_and_names_parse_and_other_values_list_the_allowed_ones() {
        let o = |text: &str| toml::from_str::<S>(text).map(|s| s.order);
        assert_eq!(o("order = 2").unwrap(), SchemeOrder::Second);
        assert_eq!(o("order = \"1\"").unwrap(), SchemeOrder::First);
        for bad in [
            "order = 3",
            "order = 2.5",
            "order = \"second\"",
            "order = -1",
        ] {
            let Err(e) = o(bad) else {
                panic!("{bad}: accepted")
            };
            let e = e.to_string();
            assert!(e.contains("1 or 2"), "{bad}: {e}");
        }
    }
}
