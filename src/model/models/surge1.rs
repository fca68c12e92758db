//! One-degree-of-freedom surge: (m - X_udot) u_dot = X_u|u| u |u| + T, x_dot = u (the surge
//! line of paper eq. 2-3 with v = r = 0). The smallest model hydroid has: the straight-line
//! acceleration run of the surge stage, filtered instead of regressed, and the example of
//! docs/architecture.md ("how to add a model").

use super::{
    positive_inertia, sname, CoefDef, Example, InputDef, InputRule, Model, Scales, StateDef, Unphysical,
    Vehicle, VehicleProblem,
};
use crate::numerics::ad::Scalar;
use crate::model::coefficients::{CompiledRelations, Relation};
use crate::base::quantity::Quantity;

crate::coefficient_table! {
    /// Coefficient vector layout.
    COEFFICIENTS;
    XUD = sname::XUD,
    XUU = sname::XUU,
}

/// The surge model of a vehicle of mass `mass`.
#[derive(Debug, Clone)]
pub struct Surge1 {
    /// Mass, kg.
    pub mass: f64,
    scales: Scales,
    relations: CompiledRelations,
}

impl Model for Surge1 {
    const NAME: &'static str = "surge1";
    const DESCRIPTION: &'static str = "straight-line surge: added mass, quadratic drag and \
        thrust (paper eq. 2-3 with v = r = 0)";
    const COEFFICIENTS: &'static [CoefDef] = COEFFICIENTS;
    const INPUTS: &'static [InputDef] = &[InputDef {
        quantity: Quantity::Thrust,
        rule: InputRule::Interpolate,
    }];

    const COMPLETING_RELATIONS: &'static [&'static [Relation]] = &[];

    fn build(v: &Vehicle) -> Result<Self, Vec<VehicleProblem>> {
        v.no_particulars(Self::NAME)?;
        Ok(Surge1 {
            mass: v.mass,
            scales: v.spheroid_scales(),
            relations: CompiledRelations::compile(&[], &[]),
        })
    }

    fn states(&self) -> &'static [StateDef] {
        &[
            StateDef {
                name: "u",
                quantity: Quantity::U,
            },
            StateDef {
                name: "x",
                quantity: Quantity::X,
            },
        ]
    }

    fn relations(&self) -> &CompiledRelations {
        &self.relations
    }

    fn compared(&self) -> &'static [Quantity] {
        &[Quantity::U]
    }

    fn typical_magnitude(&self, name: &str) -> f64 {
        self.scales.of_name(name)
    }

    fn derivatives<T: Scalar>(&self, x: &[T], u: &[f64], c: &[T], dx: &mut [T]) {
        let speed = x[0];
        // paper eq. 2-3, surge line with v = r = 0
        dx[0] = (c[XUU] * speed * speed.abs() + u[0]) / (-c[XUD] + self.mass);
        dx[1] = speed;
    }

    fn check(&self, x: &[f64], c: &[f64]) -> Result<(), Unphysical> {
        positive_inertia("m - Xud", self.mass - c[XUD])?;
        if x.iter().any(|v| !v.is_finite()) {
            return Err(Unphysical::NotFinite("state"));
        }
        Ok(())
    }

    fn example_vehicle() -> Vehicle {
        Vehicle::paper_spheroid()
    }

    fn example(&self) -> Example {
        Example {
            coefficients: &[("Xud", -1.164), ("Xuu", -1.33)],
            state: vec![0.5, 0.0],
            inputs: vec![22.0],
            estimated: &["Xud", "Xuu"],
            duration: 20.0,
        }
    }
}
