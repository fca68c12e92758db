//! What a model says about each of its coefficients, in one table per model from which the
//! index constants are generated ([`coefficient_table!`](crate::coefficient_table)).

/// One coefficient of a model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoefDef {
    /// ASCII SNAME name (`Xud` = X_udot).
    pub name: &'static str,
    /// SI unit of the dimensional value (`kg`, `kg m^2`; `-` for a pure number).
    pub unit: &'static str,
    /// One-line meaning.
    pub meaning: &'static str,
    /// How large it typically is for the vehicle (scales priors and the filter's states).
    pub size: Size,
    /// When the model's equations use it non-dimensional, the reference it is made
    /// non-dimensional on (`0.5 rho L^3`); None for a dimensional coefficient.
    pub reference: Option<&'static str>,
    /// Zero unless given or estimated: an offset or an extension term the model's source
    /// does not have (a rudder angle offset), which a configuration need not list.
    pub optional: bool,
    /// The values physics admits (a frequency is positive, a diagonal added mass has the
    /// sign of its convention); [`Range::ANY`] when the sign can vary. The filter keeps an
    /// estimate inside it (docs/hekf.md, "Admissible ranges").
    pub range: Range,
    /// What an estimate pressed against its range's bound usually means for this
    /// coefficient (None: the general reasons, docs/hekf.md).
    pub at_bound: Option<&'static str>,
    /// A parameter of the disturbance model (a wave spectrum's peak frequency or damping),
    /// which sets how the filter weighs the data rather than the vehicle's response: when
    /// estimated, it is found by the innovations' likelihood, not as a filter state (an
    /// augmented EKF is biased for such parameters; `stages::hekf::likelihood`).
    pub disturbance: bool,
}

/// The values a coefficient may take: between `lo` and `hi` (either infinite), the bounds
/// themselves included unless `open`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Lower bound (SI), `-inf` for none.
    pub lo: f64,
    /// Upper bound (SI), `inf` for none.
    pub hi: f64,
    /// The bounds themselves are excluded (a frequency: `w0 > 0`).
    pub open: bool,
}

impl Range {
    /// Any value.
    pub const ANY: Range = Range {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
        open: false,
    };

    /// Whether the range bounds anything.
    pub fn is_bounded(&self) -> bool {
        self.lo > f64::NEG_INFINITY || self.hi < f64::INFINITY
    }

    /// Whether `v` lies in the range.
    pub fn contains(&self, v: f64) -> bool {
        if self.open {
            v > self.lo && v < self.hi
        } else {
            v >= self.lo && v <= self.hi
        }
    }

    /// The range in words with the unit: `> 0 rad/s`, `<= 0 kg`, `between 0 and 1 -`.
    pub fn describe(&self, unit: &str) -> String {
        let num = crate::base::numfmt::num;
        let u = if unit == "-" || unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        match (self.lo.is_finite(), self.hi.is_finite(), self.open) {
            (true, true, false) => format!("between {} and {}{u}", num(self.lo), num(self.hi)),
            (true, true, true) => {
                format!("strictly between {} and {}{u}", num(self.lo), num(self.hi))
            }
            (true, false, open) => format!("{} {}{u}", if open { ">" } else { ">=" }, num(self.lo)),
            (false, true, open) => format!("{} {}{u}", if open { "<" } else { "<=" }, num(self.hi)),
            (false, false, _) => "any".to_string(),
        }
    }
}

impl CoefDef {
    /// The same coefficient, zero unless given or estimated (see [`CoefDef::optional`]).
    pub const fn zero_unless_given(mut self) -> Self {
        self.optional = true;
        self
    }

    /// The same coefficient, admissible only above zero (a frequency, a damping ratio).
    pub const fn positive(mut self) -> Self {
        self.range = Range {
            lo: 0.0,
            hi: f64::INFINITY,
            open: true,
        };
        self
    }

    /// The same coefficient, admissible only at or below zero (a diagonal added mass in
    /// Fossen's convention, `m - X_udot`; zero admitted, where a filter may start).
    pub const fn non_positive(mut self) -> Self {
        self.range = Range {
            lo: f64::NEG_INFINITY,
            hi: 0.0,
            open: false,
        };
        self
    }

    /// The same coefficient, admissible only at or above zero (an added mass in the MMG
    /// convention, `m + m_x`; zero admitted, where a filter may start).
    pub const fn non_negative(mut self) -> Self {
        self.range = Range {
            lo: 0.0,
            hi: f64::INFINITY,
            open: false,
        };
        self
    }

    /// The same coefficient, a parameter of the disturbance model (see
    /// [`CoefDef::disturbance`]).
    pub const fn of_disturbance(mut self) -> Self {
        self.disturbance = true;
        self
    }

    /// The same coefficient, with what an estimate at its range's bound usually means.
    pub const fn at_bound_means(mut self, means: &'static str) -> Self {
        self.at_bound = Some(means);
        self
    }

    /// The same coefficient, admissible only between `lo` and `hi` (SI, included).
    pub const fn within(mut self, lo: f64, hi: f64) -> Self {
        self.range = Range {
            lo,
            hi,
            open: false,
        };
        self
    }

    /// A dimensional coefficient whose size follows from its unit in the prime system.
    pub const fn prime(name: &'static str, unit: &'static str, meaning: &'static str) -> Self {
        CoefDef {
            name,
            unit,
            meaning,
            size: Size::Prime,
            reference: None,
            optional: false,
            range: Range::ANY,
            at_bound: None,
            disturbance: false,
        }
    }

    /// A coefficient of a fixed typical size `size` in its unit, made non-dimensional on
    /// `reference` (`0.5 rho L^5`) when it has one.
    pub const fn fixed(
        name: &'static str,
        unit: &'static str,
        meaning: &'static str,
        size: f64,
        reference: Option<&'static str>,
    ) -> Self {
        CoefDef {
            name,
            unit,
            meaning,
            size: Size::Fixed(size),
            reference,
            optional: false,
            range: Range::ANY,
            at_bound: None,
            disturbance: false,
        }
    }

    /// A dimensional added-mass coefficient whose size is the vehicle's added mass `of`.
    pub const fn added(
        name: &'static str,
        unit: &'static str,
        meaning: &'static str,
        of: AddedMassTerm,
    ) -> Self {
        CoefDef {
            name,
            unit,
            meaning,
            size: Size::AddedMass(of),
            reference: None,
            optional: false,
            range: Range::ANY,
            at_bound: None,
            disturbance: false,
        }
    }
}

/// The typical size of a coefficient for a vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Size {
    /// From the unit in the prime system: q, q L, q L^2, q L^3 for kg/m, kg, kg m, kg m^2,
    /// with q = 0.5 rho A_ref (Fossen 2011, section 7.1 for the prime system).
    Prime,
    /// The vehicle's analytic added mass when it has one (Lamb's k-factors for a spheroid,
    /// Fossen 1994, section 2.4.1), else as [`Size::Prime`].
    AddedMass(AddedMassTerm),
    /// A fixed magnitude in the coefficient's SI unit.
    Fixed(f64),
}

/// Which analytic added mass sizes an added-mass coefficient.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AddedMassTerm {
    /// X_udot.
    Surge,
    /// Y_vdot (and Z_wdot of an axisymmetric body).
    Sway,
    /// N_rdot (and M_qdot, and K_pdot where nothing better is known).
    Yaw,
    /// A coupling term (Y_rdot, N_vdot ...): sqrt(|Y_vdot N_rdot|), which has its unit kg m.
    Coupling,
}

/// The analytic added mass of a vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AddedMass {
    /// Surge added mass X_udot, kg.
    pub xud: f64,
    /// Sway added mass Y_vdot, kg.
    pub yvd: f64,
    /// Yaw added inertia N_rdot, kg m^2.
    pub nrd: f64,
}

/// The vehicle's reference sizes that [`Size`] is read against.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scales {
    /// 0.5 rho A_ref, kg/m: the force per speed squared.
    pub q: f64,
    /// Length, m.
    pub length: f64,
    /// Analytic added masses when the geometry gives them.
    pub added: Option<AddedMass>,
}

impl Scales {
    /// The typical magnitude of the coefficient named `name` (any model's) for this vehicle
    /// (SI); q for a name no model has.
    pub fn of_name(&self, name: &str) -> f64 {
        super::registry::coefficient(name).map_or(self.q, |d| self.of(d))
    }

    /// The typical magnitude of coefficient `def` for this vehicle (SI).
    pub fn of(&self, def: &CoefDef) -> f64 {
        let (q, l) = (self.q, self.length);
        match (def.size, self.added) {
            (Size::Fixed(v), _) => return v.abs(),
            (Size::AddedMass(t), Some(a)) => {
                return match t {
                    AddedMassTerm::Surge => a.xud.abs(),
                    AddedMassTerm::Sway => a.yvd.abs(),
                    AddedMassTerm::Yaw => a.nrd.abs(),
                    AddedMassTerm::Coupling => (a.yvd * a.nrd).abs().sqrt(),
                }
            }
            _ => {}
        }
        match def.unit {
            "kg/m" => q,
            "kg" => q * l,
            "kg m" => q * l * l,
            "kg m^2" => q * l * l * l,
            _ => q,
        }
    }
}

/// Declares a model's coefficient table and generates its index constants, so that the
/// order of the table is the only place an index is written:
///
/// ```ignore
/// coefficient_table! {
///     /// The surge model's coefficients.
///     pub COEFFICIENTS;
///     XUD = sname::XUD,
///     XUU = sname::XUU,
/// }
/// // COEFFICIENTS: &[CoefDef] = [XUD, XUU]; XUD = 0, XUU = 1
/// ```
#[macro_export]
macro_rules! coefficient_table {
    ($(#[$doc:meta])* $vis:vis $table:ident; $($idx:ident = $def:expr),+ $(,)?) => {
        #[allow(non_camel_case_types, clippy::upper_case_acronyms, dead_code)]
        #[derive(Clone, Copy)]
        enum CoefficientIndex {
            $($idx),+
        }
        $(
            #[allow(dead_code)]
            #[doc = concat!("Index of `", stringify!($idx), "` in the coefficient vector.")]
            $vis const $idx: usize = CoefficientIndex::$idx as usize;
        )+
        $(#[$doc])*
        $vis const $table: &[$crate::model::models::CoefDef] = &[$($def),+];
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    mod table {
        use crate::model::models::CoefDef;
        crate::coefficient_table! {
            /// A test table.
            pub TABLE;
            A = CoefDef::prime("Xuu", "kg/m", "drag"),
            B = CoefDef::prime("Nrr", "kg m^2", "yaw damping"),
        }
    }

    #[test]
    fn the_table_generates_its_indices() {
        assert_eq!((table::A, table::B), (0, 1));
        assert_eq!(table::TABLE[table::B].name, "Nrr");
    }

    #[test]
    fn sizes_follow_the_unit_or_the_added_mass() {
        let s = Scales {
            q: 2.0,
            length: 3.0,
            added: None,
        };
        let nrd = CoefDef::added("Nrd", "kg m^2", "", AddedMassTerm::Yaw);
        assert_eq!(s.of(&nrd), 54.0);
        let with = Scales {
            added: Some(AddedMass {
                xud: -1.0,
                yvd: -4.0,
                nrd: -9.0,
            }),
            ..s
        };
        assert_eq!(with.of(&nrd), 9.0);
        let yrd = CoefDef::added("Yrd", "kg m", "", AddedMassTerm::Coupling);
        assert_eq!(with.of(&yrd), 6.0);
        assert_eq!(with.of(&CoefDef::prime("Xuu", "kg/m", "")), 2.0);
    }
}
