//! Linear relations between coefficients: the geometric symmetry relations of the spheroid
//! paper (eq. 4), the axial symmetry of a body of revolution, and their compiled form that
//! models evaluate on any scalar type.

use crate::ad::Scalar;

/// A linear relation `target = sum(c_i * term_i)` between coefficients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relation {
    /// The coefficient the relation defines.
    pub target: &'static str,
    /// (factor, coefficient) terms.
    pub terms: &'static [(f64, &'static str)],
    /// Where the relation comes from.
    pub cite: &'static str,
}

/// The geometric symmetry relations of the spheroid paper, eq. 4 (Fossen's added-mass
/// Coriolis terms for a body symmetric about its x-z plane), plus the splits of Y_uv and N_uv
/// into their drag/lift and Munk/lift parts. Order matters: Nuva precedes Nuv.
pub const SYMMETRY: &[Relation] = &[
    Relation {
        target: "Nvd",
        terms: &[(1.0, "Yrd")],
        cite: "paper eq. 4: Nvd = Yrd",
    },
    Relation {
        target: "Xrr",
        terms: &[(-1.0, "Yrd")],
        cite: "paper eq. 4: Xrr = -Yrd",
    },
    Relation {
        target: "Xvr",
        terms: &[(-1.0, "Yvd")],
        cite: "paper eq. 4: Xvr = -Yvd",
    },
    Relation {
        target: "Yur",
        terms: &[(1.0, "Xud")],
        cite: "paper eq. 4: Yur = Xud",
    },
    Relation {
        target: "Nur",
        terms: &[(1.0, "Yrd")],
        cite: "paper eq. 4: Nur = Yrd",
    },
    Relation {
        target: "Nuva",
        terms: &[(-1.0, "Xud"), (1.0, "Yvd")],
        cite: "paper eq. 4: Nuva = -(Xud - Yvd)",
    },
    Relation {
        target: "Yuv",
        terms: &[(1.0, "Yuvd"), (1.0, "Yuvl")],
        cite: "paper eq. 2: Yuv = Yuvd + Yuvl",
    },
    Relation {
        target: "Nuv",
        terms: &[(1.0, "Nuva"), (1.0, "Nuvl")],
        cite: "paper eq. 2: Nuv = Nuva + Nuvl",
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
        cite: "axisymmetry: Zwd = Yvd",
    },
    Relation {
        target: "Mqd",
        terms: &[(1.0, "Nrd")],
        cite: "axisymmetry: Mqd = Nrd",
    },
    Relation {
        target: "Zqd",
        terms: &[(-1.0, "Yrd")],
        cite: "axisymmetry: Zqd = -Yrd",
    },
    Relation {
        target: "Mwd",
        terms: &[(-1.0, "Nvd")],
        cite: "axisymmetry: Mwd = -Nvd",
    },
    Relation {
        target: "Xww",
        terms: &[(1.0, "Xvv")],
        cite: "axisymmetry: Xww = Xvv",
    },
    Relation {
        target: "Xuw",
        terms: &[(1.0, "Xuv")],
        cite: "axisymmetry: Xuw = Xuv",
    },
    Relation {
        target: "Zww",
        terms: &[(1.0, "Yvv")],
        cite: "axisymmetry: Zww = Yvv",
    },
    Relation {
        target: "Zqq",
        terms: &[(-1.0, "Yrr")],
        cite: "axisymmetry: Zqq = -Yrr",
    },
    Relation {
        target: "Zuw",
        terms: &[(1.0, "Yuv")],
        cite: "axisymmetry: Zuw = Yuv",
    },
    Relation {
        target: "Mww",
        terms: &[(-1.0, "Nvv")],
        cite: "axisymmetry: Mww = -Nvv",
    },
    Relation {
        target: "Mqq",
        terms: &[(1.0, "Nrr")],
        cite: "axisymmetry: Mqq = Nrr",
    },
    Relation {
        target: "Muwl",
        terms: &[(-1.0, "Nuvl")],
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
    /// Keeps the relations whose target and terms are all in `names`, in order.
    pub fn compile(relations: &[&[Relation]], names: &[&str]) -> Self {
        let idx = |n: &str| names.iter().position(|x| *x == n);
        let mut ops = Vec::new();
        for rel in relations.iter().flat_map(|r| r.iter()) {
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
