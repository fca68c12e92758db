//! The model registry: the `registry!` list in `src/model/models/mod.rs` names every model once
//! (its module, its type); this module turns the list into [`ModelName`] (the configuration's
//! `model = "..."`), [`with_model`](super::with_model) (build the named model for a vehicle and run generic code
//! with it) and the catalogue of every model's coefficients. `hydroid coefficients`, the
//! conformance suite and every stage pick a new model up from here.

use super::{CoefDef, Model, ModelName};
use crate::base::quantity::Quantity;
use crate::model::coefficients::{CoefficientSet, YawMoment};
use std::sync::OnceLock;

/// Something to do with a model whose type is chosen at run time (see [`with_model`](super::with_model)).
pub trait ModelVisitor {
    /// What the visit returns.
    type Output;
    /// Called with the model.
    fn visit<M: Model>(self, model: &M) -> Self::Output;
}

/// Declares the models: `Variant => module::Type` per model; declares each module and
/// generates [`ModelName`] and [`with_model`](super::with_model).
macro_rules! registry {
    ($($(#[$doc:meta])* $variant:ident => $module:ident :: $ty:ident),+ $(,)?) => {
        $(pub mod $module; pub use $module::$ty;)+

        /// Which vehicle model: one variant per registered model, named in configurations by
        /// the model's [`Model::NAME`].
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
        pub enum ModelName {
            #[default]
            $($(#[$doc])* $variant),+
        }

        impl ModelName {
            /// Every model, in registry order.
            pub const ALL: &'static [ModelName] = &[$(ModelName::$variant),+];

            /// Every model's configuration name, in registry order.
            pub const NAMES: &'static [&'static str] = &[$(<$ty as $crate::model::models::Model>::NAME),+];

            /// The name used in configurations (`spheroid3`).
            pub fn as_str(self) -> &'static str {
                match self {
                    $(ModelName::$variant => <$ty as $crate::model::models::Model>::NAME),+
                }
            }

            /// The coefficient table of the model, without building it.
            pub fn coefficients(self) -> &'static [$crate::model::models::CoefDef] {
                match self {
                    $(ModelName::$variant => <$ty as $crate::model::models::Model>::COEFFICIENTS),+
                }
            }

            /// A vehicle the model is checked on.
            pub fn example_vehicle(self) -> $crate::model::models::Vehicle {
                match self {
                    $(ModelName::$variant => <$ty as $crate::model::models::Model>::example_vehicle()),+
                }
            }

            /// The relations that complete a reported coefficient set for the model.
            pub fn completing_relations(
                self,
            ) -> &'static [&'static [$crate::model::coefficients::Relation]] {
                match self {
                    $(ModelName::$variant => <$ty as $crate::model::models::Model>::COMPLETING_RELATIONS),+
                }
            }

            /// The input quantities of the model, without building it.
            pub fn inputs(self) -> &'static [$crate::model::models::InputDef] {
                match self {
                    $(ModelName::$variant => <$ty as $crate::model::models::Model>::INPUTS),+
                }
            }
        }

        /// Builds the model `name` for `vehicle` in its yaw-moment reading and hands it to
        /// `visitor`, or says what the vehicle data lacks for it.
        pub fn with_model<V: $crate::model::models::ModelVisitor, B: $crate::model::models::BuildFrom + ?Sized>(
            name: ModelName,
            vehicle: &B,
            visitor: V,
        ) -> Result<V::Output, Vec<$crate::model::models::VehicleProblem>> {
            use $crate::model::models::Model;
            let reading = vehicle.yaw_moment();
            match name {
                $(ModelName::$variant => Ok(visitor.visit(
                    &$ty::build(vehicle.vehicle())?.with_yaw_moment(reading),
                ))),+
            }
        }
    };
}
pub(crate) use registry;

impl ModelName {
    /// The model named `name` in a configuration.
    pub fn from_name(name: &str) -> Option<ModelName> {
        ModelName::ALL.iter().copied().find(|m| m.as_str() == name)
    }

    /// Completes `set` by the relations the model declares (symmetry, axisymmetry) that hold
    /// in the run's yaw-moment `reading`: what the model's re-simulation and the report need.
    pub fn complete(self, set: &mut CoefficientSet, reading: YawMoment) {
        for relations in self.completing_relations() {
            set.complete(relations, reading);
        }
    }
}

impl std::fmt::Display for ModelName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl serde::Serialize for ModelName {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

impl<'de> serde::Deserialize<'de> for ModelName {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        ModelName::from_name(&s)
            .ok_or_else(|| serde::de::Error::unknown_variant(&s, ModelName::NAMES))
    }
}

/// Every coefficient of every model, each name once, in registry and table order (the
/// catalogue hydroid knows).
pub fn all_coefficients() -> &'static [CoefDef] {
    static ALL: OnceLock<Vec<CoefDef>> = OnceLock::new();
    ALL.get_or_init(|| {
        let mut all: Vec<CoefDef> = Vec::new();
        for m in ModelName::ALL {
            for c in m.coefficients() {
                if !all.iter().any(|a| a.name == c.name) {
                    all.push(*c);
                }
            }
        }
        all
    })
}

/// A coefficient of any model by name.
pub fn coefficient(name: &str) -> Option<&'static CoefDef> {
    all_coefficients().iter().find(|c| c.name == name)
}

/// The closest known coefficient name, for "did you mean" messages.
pub fn nearest_coefficient(name: &str) -> Option<&'static str> {
    crate::base::suggest::nearest(name, all_coefficients().iter().map(|c| c.name))
}

/// Every input quantity of any model, each once, in registry order.
pub fn all_inputs() -> &'static [Quantity] {
    static ALL: OnceLock<Vec<Quantity>> = OnceLock::new();
    ALL.get_or_init(|| {
        let mut all: Vec<Quantity> = Vec::new();
        for m in ModelName::ALL {
            for i in m.inputs() {
                if !all.contains(&i.quantity) {
                    all.push(i.quantity);
                }
            }
        }
        all
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_ones_list_the_models() {
        for m in ModelName::ALL {
            assert_eq!(ModelName::from_name(m.as_str()), Some(*m));
            let v: ModelName = serde_json::from_str(&format!("\"{m}\"")).unwrap();
            assert_eq!(v, *m);
        }
        let e = serde_json::from_str::<ModelName>("\"spheroid4\"").unwrap_err();
        assert!(e
            .to_string()
            .starts_with("unknown variant `spheroid4`, expected one of `spheroid3`"));
    }

    #[test]
    fn every_relation_names_known_coefficients() {
        use crate::model::coefficients::{AXISYMMETRY, SYMMETRY};
        for rel in SYMMETRY.iter().chain(AXISYMMETRY) {
            assert!(coefficient(rel.target).is_some(), "{}", rel.target);
            for (_, n) in rel.terms {
                assert!(coefficient(n).is_some(), "{n}");
            }
        }
    }

    #[test]
    fn coefficient_names_are_unique_within_a_model_and_agree_across_models() {
        for m in ModelName::ALL {
            let t = m.coefficients();
            for (i, a) in t.iter().enumerate() {
                assert!(
                    !t[i + 1..].iter().any(|b| b.name == a.name),
                    "{m}: {}",
                    a.name
                );
                // the same name means the same coefficient in every model
                assert_eq!(coefficient(a.name), Some(a), "{m}: {}", a.name);
            }
        }
    }
}
