//! Linear relations between coefficients: the geometric symmetry relations of the spheroid
//! paper (eq. 4), the axial symmetry of a body of revolution, and their compiled form that
//! models evaluate on any scalar type.

use crate::numerics::ad::Scalar;

/// A linear relation `target = sum(c_i * term_i)` between coefficients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relation {
    /// The coefficient the relation defines.
    pub target: &'static str,
    /// (factor, coefficient) terms.
    pub terms: &'static [(f64, &'static str)],
    /// The yaw-moment reading the relation belongs to; `None`: it holds in every reading.
    pub reading: Option<YawMoment>,
    /// Where the relation comes from.
    pub cite: &'static str,
}

impl Relation {
    /// Whether the relation holds in the yaw-moment reading `reading`.
    pub fn holds_in(&self, reading: YawMoment) -> bool {
        self.reading.is_none_or(|r| r == reading)
    }
}

/// What the linear yaw-moment coefficients of a run hold, and so which of N_uv and its lift
/// part N_uvl is free and which follows from the Munk moment Nuva = -(Xud - Yvd) (paper
/// eq. 2 and 4). One reading holds for every model built in a run of hydroid.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum YawMoment {
    /// N_uvl is the lift moment only, the Munk moment is added: Nuv = Nuva + Nuvl (the seed
    /// paper's reading, eq. 2 and 5; a polar from empirical lift formulas). What a model
    /// assumes when nothing says otherwise.
    #[default]
    LiftOnly,
    /// N_uv is the whole linear yaw moment, Munk moment included (what a CFD static drift run
    /// measures); the lift part follows: Nuvl = Nuv - Nuva.
    Total,
}

impl YawMoment {
    /// The configuration's word (`total`, `lift-only`).
    pub fn as_str(self) -> &'static str {
        match self {
            YawMoment::LiftOnly => "lift-only",
            YawMoment::Total => "total",
        }
    }

    /// The configuration's words, for error messages.
    pub const NAMES: &'static [&'static str] = &["total", "lift-only"];

    /// The coefficient a static polar's moment slope C_Ma gives in this reading: `Nuv`
    /// (total) or `Nuvl` (lift-only).
    pub fn polar_coefficient(self) -> &'static str {
        match self {
            YawMoment::LiftOnly => "Nuvl",
            YawMoment::Total => "Nuv",
        }
    }

    /// The reading a set of known coefficient names implies: `Nuv` without `Nuvl` is the
    /// total moment, anything else the lift-only reading; None when both are given (they
    /// would over-determine Nuv = Nuva + Nuvl).
    pub fn of_names<'a>(names: impl IntoIterator<Item = &'a str>) -> Option<YawMoment> {
        let (mut nuv, mut nuvl) = (false, false);
        for n in names {
            nuv |= n == "Nuv";
            nuvl |= n == "Nuvl";
        }
        match (nuv, nuvl) {
            (true, true) => None,
            (true, false) => Some(YawMoment::Total),
            _ => Some(YawMoment::LiftOnly),
        }
    }

    /// Why Nuv (given by `nuv`) and Nuvl (given by `nuvl`) cannot both be given, and what to
    /// give instead.
    pub fn both_given(nuv: &str, nuvl: &str) -> String {
        format!(
            "Nuv (from {nuv}) and Nuvl (from {nuvl}) are both given, but Nuv = Nuva + Nuvl with \
             the Munk moment Nuva = -(Xud - Yvd) (paper eq. 2 and 4): give Nuv for the total yaw \
             moment (a CFD polar) or Nuvl for its lift part only, not both"
        )
    }

    /// One sentence for reports: what C_M holds and how the other part follows.
    pub fn statement(self) -> &'static str {
        match self {
            YawMoment::Total => {
                "C_M is the total yaw moment, Munk moment included; Nuvl = Nuv + Xud - Yvd \
                 follows"
            }
            YawMoment::LiftOnly => {
                "C_M is the lift moment only; the Munk moment Nuva = -(Xud - Yvd) is added \
                 (Rasekh & Mahdi 2020, eq. 2 and 4)"
            }
        }
    }
}

impl std::fmt::Display for YawMoment {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The geometric symmetry relations of the spheroid paper, eq. 4 (Fossen's added-mass
/// Coriolis terms for a body symmetric about its x-z plane), plus the splits of Y_uv and N_uv
/// into their drag/lift and Munk/lift parts. The split of N_uv runs one way or the other
/// with the [`YawMoment`] reading: lift-only derives Nuv = Nuva + Nuvl, total derives
/// Nuvl = Nuv - Nuva. Order matters: Nuva precedes both, and Nuvl precedes the axisymmetric
/// Muwl = -Nuvl of [`AXISYMMETRY`].
pub const SYMMETRY: &[Relation] = &[
    Relation {
        target: "Nvd",
        terms: &[(1.0, "Yrd")],
        reading: None,
        cite: "paper eq. 4: Nvd = Yrd",
    },
    Relation {
        target: "Xrr",
        terms: &[(-1.0, "Yrd")],
        reading: None,
        cite: "paper eq. 4: Xrr = -Yrd",
    },
    Relation {
        target: "Xvr",
        terms: &[(-1.0, "Yvd")],
        reading: None,
        cite: "paper eq. 4: Xvr = -Yvd",
    },
    Relation {
        target: "Yur",
        terms: &[(1.0, "Xud")],
        reading: None,
        cite: "paper eq. 4: Yur = Xud",
    },
    Relation {
        target: "Nur",
        terms: &[(1.0, "Yrd")],
        reading: None,
        cite: "paper eq. 4: Nur = Yrd",
    },
    Relation {
        target: "Nuva",
        terms: &[(-1.0, "Xud"), (1.0, "Yvd")],
        reading: None,
        cite: "paper eq. 4: Nuva = -(Xud - Yvd)",
    },
    Relation {
        target: "Yuv",
        terms: &[(1.0, "Yuvd"), (1.0, "Yuvl")],
        reading: None,
        cite: "paper eq. 2: Yuv = Yuvd + Yuvl",
    },
    Relation {
        target: "Nuv",
        terms: &[(1.0, "Nuva"), (1.0, "Nuvl")],
        reading: Some(YawMoment::LiftOnly),
        cite: "paper eq. 2: Nuv = Nuva + Nuvl",
    },
    Relation {
        target: "Nuvl",
        terms: &[(1.0, "Nuv"), (-1.0, "Nuva")],
        reading: Some(YawMoment::Total),
        cite: "paper eq. 2 and 4, total yaw moment: Nuvl = Nuv - Nuva = Nuv + Xud - Yvd",
    },
];

/// Axial symmetry of a body of revolution (Fossen 1994, section 2.4.1): the heave/pitch
/// coefficients mirror sway/yaw. Rotating the body 90 deg about x maps v to w, r to -q, Y to
/// Z and N to -M. Only the viscous and added-mass terms are listed: the added-mass Coriolis
/// terms of the 6-DOF model follow from the added-mass matrix itself (Fossen 2011, eq. 6.43).
pub const AXISYMMETRY: &[Relation] = &[
    Relation {
        target: "Zwd",
        terms: &[(1.0, "Yvd")],
        reading: None,
        cite: "axisymmetry: Zwd = Yvd",
    },
    Relation {
        target: "Mqd",
        terms: &[(1.0, "Nrd")],
        reading: None,
        cite: "axisymmetry: Mqd = Nrd",
    },
    Relation {
        target: "Zqd",
        terms: &[(-1.0, "Yrd")],
        reading: None,
        cite: "axisymmetry: Zqd = -Yrd",
    },
    Relation {
        target: "Mwd",
        terms: &[(-1.0, "Nvd")],
        reading: None,
        cite: "axisymmetry: Mwd = -Nvd",
    },
    Relation {
        target: "Xww",
        terms: &[(1.0, "Xvv")],
        reading: None,
        cite: "axisymmetry: Xww = Xvv",
    },
    Relation {
        target: "Xuw",
        terms: &[(1.0, "Xuv")],
        reading: None,
        cite: "axisymmetry: Xuw = Xuv",
    },
    Relation {
        target: "Zww",
        terms: &[(1.0, "Yvv")],
        reading: None,
        cite: "axisymmetry: Zww = Yvv",
    },
    Relation {
        target: "Zqq",
        terms: &[(-1.0, "Yrr")],
        reading: None,
        cite: "axisymmetry: Zqq = -Yrr",
    },
    Relation {
        target: "Zuw",
        terms: &[(1.0, "Yuv")],
        reading: None,
        cite: "axisymmetry: Zuw = Yuv",
    },
    Relation {
        target: "Mww",
        terms: &[(-1.0, "Nvv")],
        reading: None,
        cite: "axisymmetry: Mww = -Nvv",
    },
    Relation {
        target: "Mqq",
        terms: &[(1.0, "Nrr")],
        reading: None,
        cite: "axisymmetry: Mqq = Nrr",
    },
    Relation {
        target: "Muwl",
        terms: &[(-1.0, "Nuvl")],
        reading: None,
        cite: "axisymmetry: Muwl = -Nuvl",
    },
];

/// Relations resolved to indices into a model's coefficient vector, applied on any scalar
/// type so that automatic differentiation sees derived coefficients move with their terms.
#[derive(Debug, Clone, Default)]
pub struct CompiledRelations {
    ops: Vec<(usize, Vec<(f64, usize)>)>,
}

impl CompiledRelations {
    /// Keeps the relations whose target and terms are all in `names`, in order, in the
    /// lift-only reading (a model without yaw-moment relations reads the same either way).
    pub fn compile(relations: &[&[Relation]], names: &[&str]) -> Self {
        Self::compile_for(relations, names, YawMoment::LiftOnly)
    }

    /// Keeps the relations that hold in `reading` and whose target and terms are all in
    /// `names`, in order.
    pub fn compile_for(relations: &[&[Relation]], names: &[&str], reading: YawMoment) -> Self {
        let idx = |n: &str| names.iter().position(|x| *x == n);
        let mut ops = Vec::new();
        for rel in relations
            .iter()
            .flat_map(|r| r.iter())
            .filter(|r| r.holds_in(reading))
        {
            let Some(t) = idx(rel.target) else { continue };
            let Some(terms) = rel
                .terms
                .iter()
                .map(|(f, n)| idx(n).map(|i| (*f, i)))
                .collect::<Option<Vec<_>>>()
            else {
                continue;
            };
            ops.push((t, terms));
        }
        CompiledRelations { ops }
    }

    /// Indices of the coefficients that relations define (not free parameters).
    pub fn targets(&self) -> impl Iterator<Item = usize> + '_ {
        self.ops.iter().map(|(t, _)| *t)
    }

    /// Overwrites every derived coefficient in `values` from its terms.
    pub fn apply<T: Scalar>(&self, values: &mut [T]) {
        for (t, terms) in &self.ops {
            let mut acc = T::from(0.0);
            for (f, i) in terms {
                acc += values[*i] * *f;
            }
            values[*t] = acc;
        }
    }
}
