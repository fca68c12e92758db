//! The coverage study of the issue "Captive CFD runs and one joint estimate": the spheroid
//! twin (configs/spheroid_joint.toml: polar, surge run, PMM pure sway and pure yaw, the
//! paper's manoeuvre) re-simulated with 100 noise seeds and identified in both HEKF modes.
//! Joint mode must hold the truth inside 2 sigma for 93-98 % of the coefficient-seed pairs
//! and inside 1 sigma for 65-71 % (issue 22's 68 +- 3 %; measured 95.2 % and 70.5 %), and
//! never give a sigma much larger
//! than consider mode's. Consider mode (the HEKF from its own priors, the captive
//! estimates not used) leaves the yaw equation's scale to free-running
//! data, which cannot fix it (docs/hekf.md, "Identifiability"): its run flags those
//! coefficients as not determined, and the 90-98 % holds for the rest.

use crate::common;

use std::path::Path;

/// The exports of the twin, re-simulated with each seed.
const SIMULATED: [&str; 5] = [
    "polar_sweep",
    "surge_run",
    "turn_paper",
    "spheroid_pmm_sway",
    "spheroid_pmm_yaw",
];

const SEEDS: u64 = 100;

/// One seed's outcome in one mode: per coefficient, its z = (value - truth) / sigma, its
/// sigma, whether the run flagged it as not determined, and (joint mode) whether the run
/// warned that halving or doubling the noise model moves it.
struct Outcome {
    z: Vec<f64>,
    /// z against the statistical sigma alone (the budget's `hekf` row, without the
    /// noise-model direction; joint mode).
    z_statistical: Vec<f64>,
    sigma: Vec<f64>,
    flagged: Vec<bool>,
    noise_warned: Vec<bool>,
    /// Whether the noise-model direction entered the uncertainty budget (it does only beyond
    /// what a right noise model moves the estimates by chance, docs/hekf.md).
    noise_row: bool,
}

/// The twin identified in joint mode, with consider mode run beside it (`stages.hekf.modes`).
fn identify(example: &Path) -> (Outcome, Outcome) {
    let out = example.join("out");
    let o = common::run_config(&example.join("configs/spheroid_joint.toml"), &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let r = common::json(&out.join("results.json"));
    let rows = &r["stages"]["hekf"]["modes"]["rows"];
    let noise_warning = r["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|w| w["message"].as_str())
        .find(|m| m.starts_with("halving or doubling the noise model"))
        .map(|m| m.split_once(": ").map_or("", |p| p.1).to_string())
        .unwrap_or_default();
    let mode = |key: &str| {
        let mut outcome = Outcome {
            z: Vec::new(),
            z_statistical: Vec::new(),
            sigma: Vec::new(),
            flagged: Vec::new(),
            noise_warned: Vec::new(),
            noise_row: false,
        };
        for (name, truth) in common::spheroid_joint_truth() {
            let row = common::named(rows, name);
            let (v, s) = (row[key][0].as_f64().unwrap(), row[key][1].as_f64().unwrap());
            outcome.z.push((v - truth) / s);
            outcome.sigma.push(s);
            let budget = &common::named(&r["comparison"], name)["budget"];
            let statistical = budget["hekf"].as_f64().unwrap_or(s);
            outcome.noise_row |= key == "joint" && budget.get("noise").is_some();
            outcome.z_statistical.push((v - truth) / statistical);
            outcome
                .flagged
                .push(key == "consider" && row["undetermined_by_runs"] == true);
            outcome.noise_warned.push(
                key == "joint"
                    && noise_warning
                        .split(", ")
                        .any(|part| part.starts_with(&format!("{name} "))),
            );
        }
        outcome
    };
    (mode("joint"), mode("consider"))
}

/// Re-simulates the twin's exports in `example` with seed set `k` and identifies it in both
/// modes.
fn seed(example: &Path, originals: &[(String, String)], k: u64) -> (Outcome, Outcome) {
    for (name, text) in originals {
        let seeded: String = text
            .lines()
            .map(|l| match l.strip_prefix("seed = ") {
                Some(v) => format!("seed = {}", v.trim().parse::<u64>().unwrap() + 1000 * k),
                None => l.to_string(),
            })
            .collect::<Vec<_>>()
            .join("\n");
        let path = example.join(format!("configs/simulate/{name}.toml"));
        std::fs::write(&path, seeded).unwrap();
        let o = common::hydroid(&["simulate", path.to_str().unwrap(), "--force", "-q"]);
        assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    }
    identify(example)
}

/// Per coefficient of joint mode (printed): its share within 1 sigma and its name, and Nrr's
/// standard deviation of z over the seeds.
fn per_coefficient<'a>(
    outcomes: &[(Outcome, Outcome)],
    truths: &[(&'a str, f64)],
) -> (Vec<(f64, &'a str)>, f64) {
    let mut shares = Vec::new();
    let mut nrr_sd = f64::NAN;
    for (i, (name, _)) in truths.iter().enumerate() {
        let z: Vec<f64> = outcomes.iter().map(|(j, _)| j.z[i]).collect();
        let n = z.len() as f64;
        let within = |k: f64| z.iter().filter(|v| v.abs() < k).count() as f64 / n;
        let mean = z.iter().sum::<f64>() / n;
        let sd = (z.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        shares.push((within(1.0), *name));
        if *name == "Nrr" {
            nrr_sd = sd;
        }
        eprintln!(
            "joint {name}: within 1 sigma {:.0} %, 2 sigma {:.0} %, z mean {mean:+.2}, sd {sd:.2}",
            100.0 * within(1.0),
            100.0 * within(2.0)
        );
    }
    (shares, nrr_sd)
}

/// Joint mode's share within 1 sigma with the statistical sigmas alone (no noise-model row),
/// and the standard error of the reported share within 1 sigma over the seeds (the spread of
/// each seed's share over sqrt(seeds): a seed's coefficients move together).
fn statistical_share_and_its_error(outcomes: &[(Outcome, Outcome)]) -> (f64, f64) {
    let share = |z: &[f64]| z.iter().filter(|v| v.abs() < 1.0).count() as f64 / z.len() as f64;
    let all: Vec<f64> = outcomes
        .iter()
        .flat_map(|(j, _)| j.z_statistical.clone())
        .collect();
    let per_seed: Vec<f64> = outcomes.iter().map(|(j, _)| share(&j.z)).collect();
    let n = per_seed.len() as f64;
    let mean = per_seed.iter().sum::<f64>() / n;
    let var = per_seed.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (share(&all), (var / n).sqrt())
}

/// Joint mode: the data's information only adds, but each mode's sigma also holds its own
/// noise-model direction and process noise (docs/hekf.md, "The noise model"), which in joint
/// mode carry the weighting of the captive estimates against the runs: a chance sway misfit
/// taken as process noise in one seed makes its Yrr sigma 6 times consider mode's. At least
/// 95 % of the coefficient-seed pairs have a joint sigma at most 20 % above consider mode's
/// (or the run warns that the noise model moves it).
fn joint_sigmas_near_consider_modes(outcomes: &[(Outcome, Outcome)], truths: &[(&str, f64)]) {
    let mut wider = Vec::new();
    for (k, (j, c)) in outcomes.iter().enumerate() {
        for (i, (name, _)) in truths.iter().enumerate() {
            if j.sigma[i] > c.sigma[i] * 1.2 && !j.noise_warned[i] {
                wider.push(format!(
                    "outcome {k}: {name} {} > {}",
                    j.sigma[i], c.sigma[i]
                ));
            }
        }
    }
    let pairs = outcomes.len() * truths.len();
    eprintln!(
        "joint sigma above 1.2 x consider: {} of {pairs}: {wider:?}",
        wider.len()
    );
    assert!(wider.len() * 20 <= pairs, "{wider:#?}");
}

#[test]
fn joint_mode_covers_the_truth_over_100_seeds() {
    let truths = common::spheroid_joint_truth();
    let originals: Vec<(String, String)> = SIMULATED
        .iter()
        .map(|n| {
            let p = common::root().join(format!("configs/simulate/{n}.toml"));
            (n.to_string(), std::fs::read_to_string(p).unwrap())
        })
        .collect();
    // two workers, each with its own copy of the example
    let workers: Vec<tempfile::TempDir> = (0..2).map(|_| common::example_copy()).collect();
    let outcomes: Vec<(Outcome, Outcome)> =
        common::parallel::on_two_threads(SEEDS as usize, |w, k| {
            seed(workers[w].path(), &originals, k as u64 + 1)
        });
    assert_eq!(outcomes.len(), SEEDS as usize);
    let share = |pairs: Vec<f64>| {
        pairs.iter().filter(|z| z.abs() < 2.0).count() as f64 / pairs.len() as f64
    };
    let joint = share(outcomes.iter().flat_map(|(j, _)| j.z.clone()).collect());
    let joint_1 = outcomes
        .iter()
        .flat_map(|(j, _)| j.z.clone())
        .filter(|z| z.abs() < 1.0)
        .count() as f64
        / (outcomes.len() * truths.len()) as f64;
    let consider_determined = share(
        outcomes
            .iter()
            .flat_map(|(_, c)| {
                c.z.iter()
                    .zip(&c.flagged)
                    .filter(|(_, f)| !**f)
                    .map(|(z, _)| *z)
                    .collect::<Vec<_>>()
            })
            .collect(),
    );
    let consider_all = share(outcomes.iter().flat_map(|(_, c)| c.z.clone()).collect());
    let (mut per_coefficient, nrr_sd) = per_coefficient(&outcomes, &truths);
    eprintln!(
        "inside 1 sigma: joint {:.1} %; inside 2 sigma: joint {:.1} %, consider {:.1} % \
         (determined only {:.1} %)",
        100.0 * joint_1,
        100.0 * joint,
        100.0 * consider_all,
        100.0 * consider_determined
    );
    assert!((0.93..=0.98).contains(&joint), "joint: {joint}");
    // issue 22: 68 +- 3 % within 1 sigma
    assert!(
        (0.65..=0.71).contains(&joint_1),
        "joint, 1 sigma: {joint_1}"
    );
    assert!(
        (0.90..=0.98).contains(&consider_determined),
        "consider, determined coefficients: {consider_determined}"
    );
    // docs/hekf.md at its printed digits: "within 2 sigma for 95.2 % and within 1 sigma for
    // 70.5 % ... per coefficient 64-76 % within 1 sigma, Nrr and Xuu the widest"
    per_coefficient.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut widest: Vec<&str> = per_coefficient.iter().rev().take(2).map(|p| p.1).collect();
    widest.sort_unstable();
    assert_eq!(
        format!(
            "{:.1} % and {:.1} %; per coefficient {:.0}-{:.0} %, {} the widest; Nrr z sd {:.2}",
            100.0 * joint,
            100.0 * joint_1,
            100.0 * per_coefficient[0].0,
            100.0 * per_coefficient[per_coefficient.len() - 1].0,
            widest.join(", "),
            nrr_sd
        ),
        "95.2 % and 70.5 %; per coefficient 64-76 %, Nrr, Xuu the widest; Nrr z sd 0.83"
    );
    // docs/hekf.md: "70.3 % with the statistical sigmas alone ... a standard error of 1.8 %
    // ... the direction entered in 13 of 100 seeds"
    let (statistical, error) = statistical_share_and_its_error(&outcomes);
    let with_noise_row = outcomes.iter().filter(|(j, _)| j.noise_row).count();
    assert_eq!(
        format!(
            "{:.1} % {:.1} %; noise row in {with_noise_row} of {}",
            100.0 * statistical,
            100.0 * error,
            outcomes.len()
        ),
        "70.3 % 1.8 %; noise row in 13 of 100"
    );
    joint_sigmas_near_consider_modes(&outcomes, &truths);
    // consider mode leaves the yaw scale (Nrd with Nvv, Nrr, Nuvl) to free-running data, and
    // says so
    for (k, (_, c)) in outcomes.iter().enumerate() {
        for name in ["Nrd", "Nvv"] {
            let i = truths.iter().position(|(n, _)| *n == name).unwrap();
            assert!(c.flagged[i], "seed {k}: consider mode does not flag {name}");
        }
    }
}
