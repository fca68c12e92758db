//! `[reference]`: published coefficient values to compare with, one set (`[reference]`) or
//! several (`[[reference]]`, e.g. a paper's identified values and the published truth).

use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize, Serializer};
use std::collections::BTreeMap;

/// Published coefficient values to compare with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceConfig {
    /// Citation shown in reports.
    pub name: String,
    /// Coefficient values, SI.
    pub values: BTreeMap<String, f64>,
}

/// The reference sets in the order given; the first is the one the plots show.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct References(pub Vec<ReferenceConfig>);

impl References {
    /// No reference given.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The first set (the comparison table's first reference column and the plots').
    pub fn primary(&self) -> Option<&ReferenceConfig> {
        self.0.first()
    }

    /// The sets after the first, each a further pair of columns of the comparison table.
    pub fn others(&self) -> &[ReferenceConfig] {
        self.0.get(1..).unwrap_or_default()
    }

    /// Every set, in order.
    pub fn iter(&self) -> std::slice::Iter<'_, ReferenceConfig> {
        self.0.iter()
    }
}

impl Serialize for References {
    /// One set as a table (`[reference]`), several as an array of tables.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self.0.as_slice() {
            [one] => one.serialize(s),
            many => many.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for References {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct OneOrMany;
        impl<'de> Visitor<'de> for OneOrMany {
            type Value = References;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a table [reference] with name and values, or tables [[reference]]")
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<References, A::Error> {
                let one = ReferenceConfig::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(References(vec![one]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<References, A::Error> {
                Vec::<ReferenceConfig>::deserialize(de::value::SeqAccessDeserializer::new(seq))
                    .map(References)
            }
        }
        d.deserialize_any(OneOrMany)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize, Serialize)]
    struct Doc {
        #[serde(default, skip_serializing_if = "References::is_empty")]
        reference: References,
    }

    #[test]
    fn one_table_or_several_read_and_write_back_the_same() {
        let one = "[reference]\nname = \"paper\"\nvalues = { Yv = -0.1 }\n";
        let d: Doc = toml::from_str(one).unwrap();
        assert_eq!(d.reference.0.len(), 1);
        assert_eq!(d.reference.primary().unwrap().values["Yv"], -0.1);
        assert!(d.reference.others().is_empty());
        let back: Doc = toml::from_str(&toml::to_string(&d).unwrap()).unwrap();
        assert_eq!(back.reference, d.reference);

        let two = "[[reference]]\nname = \"paper\"\nvalues = { Yv = -0.1 }\n\n\
                   [[reference]]\nname = \"truth\"\nvalues = { Yv = -0.099 }\n";
        let d: Doc = toml::from_str(two).unwrap();
        assert_eq!(d.reference.primary().unwrap().name, "paper");
        assert_eq!(d.reference.others()[0].name, "truth");
        let back: Doc = toml::from_str(&toml::to_string(&d).unwrap()).unwrap();
        assert_eq!(back.reference, d.reference);

        let none: Doc = toml::from_str("").unwrap();
        assert!(none.reference.is_empty() && none.reference.primary().is_none());
    }

    #[test]
    fn a_misspelt_key_is_named() {
        let e = toml::from_str::<Doc>("[reference]\nname = \"p\"\nvaleus = {}\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("valeus"), "{e}");
        let e = toml::from_str::<Doc>("[[reference]]\nname = \"p\"\nvaleus = {}\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("valeus"), "{e}");
    }
}
