//! Is the filter consistent with its own noise model? The chi-square test of the mean
//! normalised innovation squared (Bar-Shalom, Li & Kirubarajan 2001, section 5.4), turned into
//! a warning that says which measurement carries the excess and what it means for the sigmas.

use super::identify::{Excursion, Rejection, RunData};
use super::result::RunSummary;
use super::STAGE;
use crate::base::warning::Warning;
use crate::model::models::Model;

/// A mean NIS below this fraction of its lower bound, with process noise calibrated from the
/// misfit, is a filter that follows the measurements rather than the model (issue 49: NIS 2.7
/// against a band of 5.7-6.3 with the yaw rate's process noise raised 2400 times).
const FAR_BELOW: f64 = 0.6;

/// The warning for one run whose mean NIS lies outside its 95 % bounds, or None.
pub fn nis_warning(run: &RunSummary) -> Option<Warning> {
    let nis = run.nis.as_ref()?;
    if nis.consistent || !nis.mean.is_finite() {
        return None;
    }
    let [lo, hi] = nis.mean_bounds;
    let seen = format!(
        "the innovations are inconsistent with the noise model: mean NIS {} for {} measurement{} \
         per sample (a consistent filter gives {}-{}), {:.0} % of samples outside their 95 % \
         bounds (5 % expected)",
        sig3(nis.mean),
        nis.dof,
        if nis.dof == 1 { "" } else { "s" },
        sig3(lo),
        sig3(hi),
        100.0 * nis.fraction_outside
    );
    if nis.mean > hi {
        // innovation RMS against the measurement noise: where the misfit shows
        let excess = run
            .innovation_rms
            .iter()
            .zip(&run.noise)
            .filter(|(_, n)| n.sigma > 0.0)
            .map(|(rms, n)| (rms / n.sigma, n.quantity))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        let largest =
            excess
                .filter(|(ratio, _)| ratio.is_finite())
                .map_or_else(String::new, |(ratio, q)| {
                    format!(
                        "; the largest misfit is in {q}, whose innovations are {} times its noise \
                     sigma",
                        sig3(ratio)
                    )
                });
        let factor = (nis.mean / nis.dof as f64).sqrt();
        Some(
            Warning::new(
                STAGE,
                format!("{seen}{largest}"),
                format!(
                    "the model, with the coefficients held fixed and the inputs given, does not \
                 follow this run to within its measurement noise: the estimates absorb the \
                 misfit and the filter's own sigmas (\"from the data alone\") are too small by a \
                 factor of about {} or more. Usual causes: a fixed coefficient from an earlier \
                 stage or the configuration that is off (its uncertainty is in the sigmas, see \
                 the uncertainty budget, but not its bias), a wrong input such as the thrust or \
                 rudder, or measurement noise set too small",
                    sig3(factor)
                ),
            )
            .for_run(&run.name)
            .failed(crate::base::warning::Test::Innovations),
        )
    } else if nis.mean < FAR_BELOW * lo && !run.process_noise.is_empty() {
        Some(
            Warning::new(
                STAGE,
                format!(
                    "{seen}, with process noise calibrated from the model's misfit on {}",
                    run.process_noise
                        .keys()
                        .map(String::as_str)
                        .collect::<Vec<&str>>()
                        .join(", ")
                ),
                "the filter followed the measurements rather than the model: the process noise \
                 lets the states go where the data are, so the coefficients rest on little of \
                 the dynamics and may sit in a distant mode with sigmas that describe only its \
                 neighbourhood. Do not use these estimates: check the re-simulation, and run \
                 again with hekf.adapt_noise = false or a process noise given \
                 (hekf.process_noise)",
            )
            .for_run(&run.name)
            .failed(crate::base::warning::Test::Innovations),
        )
    } else {
        Some(
            Warning::new(
                STAGE,
                seen,
                "the innovations are smaller than the noise model says: the measurement noise \
                 is set larger than the data's, so the sigmas are too large (conservative)",
            )
            .for_run(&run.name)
            .failed(crate::base::warning::Test::Innovations),
        )
    }
}

/// The warning for the stretches where a quantity stayed beyond the gate in the last pass.
pub fn excursion_warning<M: Model>(
    model: &M,
    run: &RunData,
    excursions: &[Excursion],
    gate: f64,
) -> Option<Warning> {
    const SHOWN: usize = 5;
    if excursions.is_empty() {
        return None;
    }
    let line = |k: usize| run.lines.get(k).copied().unwrap_or(0);
    let mut at: Vec<String> = excursions
        .iter()
        .take(SHOWN)
        .map(|x| {
            format!(
                "{} at lines {}-{} (t = {}-{} s, up to {} sigma)",
                model.output_quantities()[run.measured[x.measurement]],
                line(x.first),
                line(x.last),
                sig3(run.times[x.first]),
                sig3(run.times[x.last]),
                sig3(x.peak)
            )
        })
        .collect();
    if excursions.len() > SHOWN {
        at.push(format!("and {} more", excursions.len() - SHOWN));
    }
    let samples: usize = excursions.iter().map(|x| x.last + 1 - x.first).sum();
    Some(
        Warning::new(
            STAGE,
            format!(
                "the innovations stayed beyond the {} sigma gate over {} stretch{} ({} \
                 sample{}): {}",
                crate::base::numfmt::fixed_trimmed(gate, 2),
                excursions.len(),
                if excursions.len() == 1 { "" } else { "es" },
                samples,
                if samples == 1 { "" } else { "s" },
                at.join(", ")
            ),
            "not isolated outliers (they were used): the model departs from the data there by \
             far more than the noise explains, e.g. after a gap, at a step of an input, or \
             with a wrong input, fixed coefficient, unit or frame; the estimates absorb that \
             misfit, so treat them as doubtful until the cause is known",
        )
        .for_run(&run.name),
    )
}

/// The warning for the measurements the innovation gate rejected in the last pass, naming
/// their file lines.
pub fn gate_warning<M: Model>(model: &M, run: &RunData, rejected: &[Rejection]) -> Option<Warning> {
    const SHOWN: usize = 5;
    if rejected.is_empty() {
        return None;
    }
    let outputs = model.output_quantities();
    let name = |a: usize| outputs[run.measured[a]];
    let mut at: Vec<String> = rejected
        .iter()
        .take(SHOWN)
        .map(|r| {
            format!(
                "{} at line {} (t = {} s, {} sigma)",
                name(r.measurement),
                run.lines.get(r.sample).copied().unwrap_or(0),
                sig3(run.times[r.sample]),
                sig3(r.sigmas)
            )
        })
        .collect();
    if rejected.len() > SHOWN {
        at.push(format!("and {} more", rejected.len() - SHOWN));
    }
    let samples = run.len() * run.measured.len();
    let share = rejected.len() as f64 / samples.max(1) as f64;
    Some(
        Warning::new(
            STAGE,
            format!(
                "the innovation gate rejected {} measurement{} ({} % of them): {}",
                rejected.len(),
                if rejected.len() == 1 { "" } else { "s" },
                crate::base::numfmt::num(100.0 * share),
                at.join(", ")
            ),
            if share > 0.001 {
                "more than isolated outliers: the model does not follow the run everywhere, so \
                 the estimates are doubtful; check the warnings above and the NIS (hekf.gate \
                 sets the gate, 0 switches it off)"
            } else {
                "these measurements were far outside what the model predicted and are left \
                 out; check the export at those lines (hekf.gate sets the gate, 0 switches it \
                 off)"
            },
        )
        .for_run(&run.name),
    )
}

fn sig3(v: f64) -> String {
    crate::base::numfmt::num(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::quantity::Quantity;
    use crate::numerics::estimation::nis::summarize;
    use crate::stages::hekf::tuning::NoiseChoice;

    fn run(nis: &[f64], rms: Vec<f64>) -> RunSummary {
        RunSummary {
            name: "turn".into(),
            file: "turn.csv".into(),
            samples: nis.len(),
            duration: 1.0,
            mean_dt: 0.01,
            measured: vec!["u".into(), "r".into()],
            noise: [Quantity::U, Quantity::R]
                .into_iter()
                .map(|quantity| NoiseChoice {
                    quantity,
                    sigma: 1e-3,
                    source: "configured".into(),
                    rounding: None,
                    estimate_variance: 0.0,
                })
                .collect(),
            process_noise: Default::default(),
            nis: summarize(nis, 2, 0.0),
            innovation_rms: rms,
            between: Default::default(),
            states: None,
            warnings: Vec::new(),
        }
    }

    #[test]
    fn inflated_innovations_name_the_channel_and_the_factor() {
        let w = nis_warning(&run(&vec![8.0; 1000], vec![1.1e-3, 2.7e-3])).expect("warned");
        assert!(w.message.contains("mean NIS 8"), "{}", w.message);
        assert!(
            w.message.contains("largest misfit is in r"),
            "{}",
            w.message
        );
        assert!(w.meaning.contains("factor of about 2"), "{}", w.meaning);
        assert_eq!(w.run.as_deref(), Some("turn"));
    }

    #[test]
    fn consistent_innovations_give_no_warning_and_small_ones_say_conservative() {
        // chi-square with 2 dof has mean 2: alternate 1 and 3
        let nis: Vec<f64> = (0..1000)
            .map(|k| if k % 2 == 0 { 1.0 } else { 3.0 })
            .collect();
        assert!(nis_warning(&run(&nis, vec![1e-3, 1e-3])).is_none());
        let w = nis_warning(&run(&vec![0.5; 1000], vec![5e-4, 5e-4])).expect("warned");
        assert!(w.meaning.contains("conservative"), "{}", w.meaning);
    }

    #[test]
    fn small_innovations_under_calibrated_process_noise_say_not_to_use_the_estimates() {
        // the same small innovations, the process noise calibrated from the misfit: the
        // filter followed the measurements (issue 49)
        let mut adapted = run(&vec![0.5; 1000], vec![5e-4, 5e-4]);
        adapted.process_noise.insert("r".into(), 116.0);
        let w = nis_warning(&adapted).expect("warned");
        assert!(
            w.meaning.contains("Do not use these estimates"),
            "{}",
            w.meaning
        );
        assert!(w.message.contains("misfit on r"), "{}", w.message);
        // just below the band is conservative, not a distant mode
        let mut near = run(&vec![1.7; 1000], vec![5e-4, 5e-4]);
        near.process_noise.insert("r".into(), 116.0);
        let w = nis_warning(&near).expect("warned");
        assert!(w.meaning.contains("conservative"), "{}", w.meaning);
    }
}
