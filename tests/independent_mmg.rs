//! Identification accuracy of hydroid's `mmg3` model on data it did not make (issue 22): the
//! KVLCC2 1/45.7 generator of tests/independent/mmg.rs (Yasukawa & Yoshimura 2015 equations
//! and Tables 2-3; own RK4 at 5 ms; the rudder moving at 2.32 deg/s x sqrt(45.7) = 15.68
//! deg/s through the steering gear; propeller at its self-propulsion speed; a 10 Hz basin
//! log with sensor noise), identified by `hydroid run` (as a library) with a configuration
//! like the bundled configs/ship_kvlcc2.toml: the twelve sway and yaw hull derivatives,
//! everything else held at the published values, hydroid's default tuning.
//!
//! The accuracy tests are coverage studies over 20 noise seeds: whether the sigmas cover the
//! errors is a property of the spread over seeds, which one seed cannot show (the single-seed
//! tests these replace failed on their seed, 2801, at z -3.0 for Y'v, the tail of a spread the
//! sigmas describe; see the first test).

use crate::independent;

use independent::accuracy::{identify, Outcome, Study};
use independent::mmg::{self, Kvlcc2, Sensors};
use std::fmt::Write as _;
use std::path::Path;

/// hydroid's mmg3 names of the fixture's parameters (configs/ship_kvlcc2.toml); None for
/// those that are particulars or not parameters of the model.
fn hydroid_name(csv: &str) -> Option<String> {
    let direct = [
        ("R_0_dash", "R0_p"),
        ("m_x_dash", "mx_p"),
        ("m_y_dash", "my_p"),
        ("J_z_dash", "Jz_p"),
        ("t_P", "tP"),
        ("w_P0", "wP0"),
        ("k_0", "k0"),
        ("k_1", "k1"),
        ("k_2", "k2"),
        ("t_R", "tR"),
        ("a_H", "aH"),
        ("x_H_dash", "xH_p"),
        ("epsilon", "epsilon"),
        ("kappa", "kappa"),
        ("f_alpha", "f_alpha"),
        ("l_R", "lR_p"),
        ("gamma_R_plus", "gammaR_pos"),
        ("gamma_R_minus", "gammaR_neg"),
    ];
    if let Some((_, h)) = direct.iter().find(|(c, _)| *c == csv) {
        return Some(h.to_string());
    }
    // X_vv_dash -> Xvv_p, Y_vrr_dash -> Yvrr_p ...
    let hull = csv.strip_suffix("_dash")?;
    let (head, tail) = hull.split_once('_')?;
    matches!(head, "X" | "Y" | "N").then(|| format!("{head}{tail}_p"))
}

const COLUMNS: &str = "time = \"time\"\nx = \"x\"\ny = \"y\"\nyaw = \"heading\"\nu = \"u\"\n\
    v = \"v\"\nr = \"yaw rate\"\nrudder = \"rudder\"\nrpm = \"propeller\"\n";

/// How one case is made and read.
#[derive(Debug, Clone, Copy)]
struct Case<'a> {
    /// The runs fitted ("turn35", "turn35_port", "zigzag20"); the others are validation.
    fit: &'a [&'a str],
    /// The hull feels the rudder held at each logged sample (a diagnostic: the rudder then
    /// acts exactly as a held input does in hydroid) while the log still samples the moving
    /// rudder.
    held: bool,
    /// The rudder's `between` rule in the configuration; None: hydroid's default (`auto`,
    /// which reads a logged ramp linearly).
    read: Option<&'static str>,
    /// Noise seed of the starboard turn; the port turn and the zig-zag take the next two.
    seed: u64,
    /// The sensor noise, a multiple of the basin's ([`Sensors::basin`]).
    noise: f64,
}

/// The configuration's vehicle, fluid and held coefficients (all but `estimated`), as the
/// bundled configs/ship_kvlcc2.toml writes them.
fn vehicle_text(ship: &Kvlcc2, estimated: &[&str]) -> String {
    let mut c = String::new();
    writeln!(
        c,
        "title = \"KVLCC2 1/45.7: MMG hull derivatives from independently generated runs\"\n\
         [vehicle]\nname = \"KVLCC2 1/45.7 model (Yasukawa & Yoshimura 2015)\"\n\
         mass = {m}\nlength = {l}\nizz = {izz}\nreference_area = 3.22\nreference_length = {l}\n\
         [vehicle.particulars]\ndraught = \"{d} m\"\nx_g = \"{xg} m\"\n\
         propeller_diameter = \"{dp} m\"\npropeller_x = \"{xp} m\"\nrudder_area = \"{ar} m^2\"\n\
         rudder_height = \"{hr} m\"\nrudder_x = \"{xr} m\"\nwake_c1 = {c1}\n\
         wake_c2_pos = {c2p}\nwake_c2_neg = {c2m}\n[fluid]\nrho = {rho}\nmu = 0.001\n\
         [coefficients]",
        m = ship.mass,
        l = ship.lpp,
        izz = ship.izz_midship,
        d = ship.draught,
        xg = ship.x_g,
        dp = ship.d_p,
        xp = ship.p["x_P_dash"] * ship.lpp,
        ar = ship.a_r,
        hr = ship.h_r,
        xr = -0.5 * ship.lpp,
        c1 = ship.p["C_1"],
        c2p = ship.p["C_2_plus"],
        c2m = ship.p["C_2_minus"],
        rho = ship.rho,
    )
    .unwrap();
    for (name, v) in &ship.p {
        if let Some(h) = hydroid_name(name) {
            if !estimated.contains(&h.as_str()) {
                writeln!(c, "{h} = {v}").unwrap();
            }
        }
    }
    c
}

/// Writes the +-35 deg turns (200 s) and the 20/20 zig-zag (150 s), logged at 10 Hz, and a
/// configuration fitting `case.fit`, the others as validation.
fn write_case(dir: &Path, ship: &Kvlcc2, case: &Case) -> std::path::PathBuf {
    let (held, seed) = (case.held, case.seed);
    let sensors = Sensors::basin().scaled(case.noise);
    let turn =
        |deg: f64, seed| mmg::turn_sensed(ship, held, deg.to_radians(), 200.0, 10.0, sensors, seed);
    let runs = [
        ("turn35", turn(35.0, seed)),
        ("turn35_port", turn(-35.0, seed + 1)),
        (
            "zigzag20",
            mmg::zigzag_sensed(ship, held, 150.0, 10.0, sensors, seed + 2),
        ),
    ];
    let truth = mmg::hull_truth(ship);
    let estimated: Vec<&str> = truth.iter().map(|t| t.0).collect();
    let mut c = vehicle_text(ship, &estimated);
    writeln!(
        c,
        "[hekf]\nmodel = \"mmg3\"\npreset = \"hydroid\"\nestimate = {estimated:?}"
    )
    .unwrap();
    let between = case
        .read
        .map(|r| format!("between = {{ rudder = \"{r}\" }}\n"))
        .unwrap_or_default();
    for (name, run) in &runs {
        run.log.write_csv(dir, &format!("{name}.csv"));
        let table = if case.fit.contains(name) {
            "hekf.runs"
        } else {
            "hekf.validation"
        };
        writeln!(
            c,
            "[[{table}]]\nname = \"{name}\"\nfile = \"{name}.csv\"\n{between}[{table}.columns]\n\
             {COLUMNS}"
        )
        .unwrap();
    }
    let path = dir.join("kvlcc2.toml");
    std::fs::write(&path, c).unwrap();
    path
}

/// Generates and identifies one case.
fn run(case: &Case) -> Outcome {
    let ship = Kvlcc2::model();
    let dir = tempfile::tempdir().unwrap();
    let config = write_case(dir.path(), &ship, case);
    identify(&config, &mmg::hull_truth(&ship))
}

/// Noise seeds of a coverage study: the first is the seed of the single-seed tests these
/// replace (2801, 2802, 2803).
const SEEDS: u64 = 20;

/// `case` over [`SEEDS`] noise seeds (2801 + 10 k), two at a time.
fn study(case: Case) -> Study {
    let outcomes: Vec<(u64, Outcome)> =
        crate::common::parallel::on_two_threads(SEEDS as usize, |_, k| {
            let seed = 2801 + 10 * k as u64;
            (seed, run(&Case { seed, ..case }))
        });
    for (seed, o) in &outcomes {
        let (k, n) = o.within_two_sigma();
        println!(
            "seed {seed}: {k} of {n} determined within 2 sigma, worst |z| {:.2}",
            o.worst_z()
        );
    }
    let study = Study {
        outcomes: outcomes.into_iter().map(|(_, o)| o).collect(),
    };
    println!("{}", study.table());
    study
}

/// What a calibrated identification gives over the seeds: in every seed, every coefficient
/// the run leaves undetermined is flagged; 93 % or more of the determined coefficient-seed
/// pairs within 2 sigma and 55 to 85 % within 1 (68 % for a calibrated sigma; the pairs are
/// correlated, so the band is wide); no coefficient's sigma too small (root mean square z at
/// most 1.5 over the seeds); and in the coefficients hydroid never flags (the linear
/// derivatives) no bias: mean z within 3 standard errors of 0 (3 / sqrt(seeds)) and the
/// mean error within `error_percent` of the truth.
#[track_caller]
fn assert_calibrated(study: &Study, error_percent: f64) {
    let table = study.table();
    for o in &study.outcomes {
        o.assert_undetermined_flagged();
    }
    let (one, two, _) = study.coverage();
    assert!(two >= 0.93, "{table}");
    assert!((0.55..=0.85).contains(&one), "{table}");
    let n = study.outcomes.len();
    for c in study.spreads() {
        if c.determined == n {
            assert!(c.rms_z <= 1.5, "{}: {table}", c.name);
        }
        if c.flagged == 0 {
            assert!(
                c.mean_z.abs() <= 3.0 / (n as f64).sqrt()
                    && c.mean_error_percent.abs() <= error_percent,
                "{}: {table}",
                c.name
            );
        }
    }
}

/// The bundled set-up: the +-35 deg turns fitted, the zig-zag for validation, 10 Hz, the
/// logged rudder read as hydroid reads any log (`between = "auto"`: its ramps interpolated),
/// over 20 noise seeds. The runs determine Y'v, Y'r, N'v, N'r and some cubic terms; hydroid
/// flags the others (the cubic terms correlated 0.91 to 0.98).
///
/// Measured (2026-11-26, seeds 2801 + 10 k): 96.7 % of the 180 determined coefficient-seed
/// pairs within 2 sigma, 67.2 % within 1; Y'v mean error +0.44 % (mean z -0.46, rms z 1.18,
/// the estimates' spread 1.10 times the mean sigma), Y'r -0.62 % (mean z -0.48, rms 1.19),
/// N'v and N'r +0.03 % (rms z 0.89, 0.91); 3 of the 20 seeds have a determined coefficient
/// beyond 2 sigma (2801: Y'v +2.9 % at z -3.0 and Y'r -4.1 % at z -3.1; 2901: 2.5; 2921:
/// 2.1). Another 20 seeds (10001 + 10 k): Y'v +0.26 % (mean z -0.25, rms 0.98), 97.5 % within
/// 2 sigma. Seed 2801 is noise, not a difference of the models' forms (tests/independent/mmg.rs
/// and src/model/models/mmg3.rs agree term by term, Y&Y 2015 eq. 4-26): the same seed with the
/// sensor noise scaled by 0.1 gives Y'v +0.23 %, by 0.01 -0.02 %; with the hull feeling the
/// rudder held, the same as with it moving (the last test). The undetermined cubic terms stay
/// near their start, 0 (Y'rrr -103 %, N'vvv -84 %, mean z -0.91 and +0.89 with a spread of
/// 0.15 sigma): their sigma is the prior's width, and covers it; started at the truth, Y'v and
/// Y'r come out the same (mean z -0.50, -0.53).
#[test]
fn turns_at_10_hz_cover_the_truth_over_20_seeds() {
    let s = study(Case {
        fit: &["turn35", "turn35_port"],
        held: false,
        read: None,
        seed: 0,
        noise: 1.0,
    });
    assert_calibrated(&s, 1.0);
    // docs/validation.md's row at its printed digits
    let spread = |name: &str| {
        s.spreads()
            .into_iter()
            .find(|c| c.name == name)
            .expect("a hull derivative")
    };
    let (yv, yr, nv, nr) = (
        spread("Yv_p"),
        spread("Yr_p"),
        spread("Nv_p"),
        spread("Nr_p"),
    );
    let first = &s.outcomes[0];
    assert_eq!(
        format!(
            "{} | Y'v {:+.2} %, Y'r {:+.2} % mean error (rms z {:.2}, {:.2}), N'v, N'r {:+.2} %, \
             {:+.2} %; seed 2801 alone: Y'v z {:+.1}, Y'r z {:+.1}",
            pairs_within_two(&s),
            yv.mean_error_percent,
            yr.mean_error_percent,
            yv.rms_z,
            yr.rms_z,
            nv.mean_error_percent,
            nr.mean_error_percent,
            first.row("Yv_p").z,
            first.row("Yr_p").z
        ),
        "96.7 % of 180 pairs | Y'v +0.44 %, Y'r -0.62 % mean error (rms z 1.18, 1.19), N'v, \
         N'r +0.03 %, +0.03 %; seed 2801 alone: Y'v z -3.0, Y'r z -3.1",
        "{}",
        s.table()
    );
    // docs/models/ships.md: "from the turns 96.7 % and 67.2 % [within 2 and 1 sigma], Y'v and
    // Y'r 0.44 % and 0.62 % off on average ... against sigmas of 1.0 % and 1.3 %"
    let mean_sigma = |name: &str| {
        let n = s.outcomes.len() as f64;
        s.outcomes
            .iter()
            .map(|o| 100.0 * o.row(name).sigma / o.row(name).truth.abs())
            .sum::<f64>()
            / n
    };
    assert_eq!(
        format!(
            "{:.1} % within 1; sigmas {:.1} % and {:.1} %",
            100.0 * s.coverage().0,
            mean_sigma("Yv_p"),
            mean_sigma("Yr_p")
        ),
        "67.2 % within 1; sigmas 1.0 % and 1.3 %",
        "{}",
        s.table()
    );
}

/// "96.7 % of 180 pairs": the share of the determined coefficient-seed pairs within 2 sigma,
/// as docs/validation.md prints it.
fn pairs_within_two(s: &Study) -> String {
    let (_, two, pairs) = s.coverage();
    format!("{:.1} % of {pairs} pairs", 100.0 * two)
}

/// The turns and the zig-zag fitted jointly, 10 Hz, the rudder read by `between = "auto"`,
/// over 20 noise seeds: all twelve hull derivatives but Y'rrr and N'vvv determined in most
/// seeds; hydroid flags the cubic terms (correlated 0.92 to 0.98).
///
/// Measured (2026-11-26, seeds 2801 + 10 k): 99.5 % of the 198 determined pairs within 2
/// sigma, 76.3 % within 1 (the sigmas a little wide: rms z 0.76 to 0.95); mean errors Y'v
/// +0.09 %, Y'r -0.12 %, N'v and N'r +0.04 % against sigmas of about 0.16 %, 0.21 %, 0.10 %
/// and 0.11 %; every mean z within +-0.42. Seed 2801 alone gives N'v at z -2.04, the one pair
/// of 198 beyond 2 sigma. Another 20 seeds (10001 + 10 k): 97.0 % within 2 sigma, 65.5 %
/// within 1, every mean z within +-0.24.
#[test]
fn turns_and_zigzag_at_10_hz_cover_the_truth_over_20_seeds() {
    let s = study(Case {
        fit: &["turn35", "turn35_port", "zigzag20"],
        held: false,
        read: None,
        seed: 0,
        noise: 1.0,
    });
    assert_calibrated(&s, 0.2);
    // docs/validation.md's row at its printed digits: the largest mean error of the linear
    // terms, the largest |mean z| of all twelve, the share within 1 sigma
    let spreads = s.spreads();
    let linear = spreads
        .iter()
        .filter(|c| ["Yv_p", "Yr_p", "Nv_p", "Nr_p"].contains(&c.name.as_str()))
        .map(|c| c.mean_error_percent.abs())
        .fold(0.0, f64::max);
    let mean_z = spreads.iter().map(|c| c.mean_z.abs()).fold(0.0, f64::max);
    assert_eq!(
        format!(
            "{} | linear terms within 0.2 % on average ({linear:.2} % the largest), every mean \
             z within +-{mean_z:.2}, {:.1} % within 1 sigma",
            pairs_within_two(&s),
            100.0 * s.coverage().0
        ),
        "99.5 % of 198 pairs | linear terms within 0.2 % on average (0.12 % the largest), every \
         mean z within +-0.42, 76.3 % within 1 sigma",
        "{}",
        s.table()
    );
}

/// The rudder between samples, with the noise fixed (seed 2801): the generator's hull
/// feeling the rudder held at each logged sample (read `hold`: the physics then are
/// exactly what the filter assumes) against the hull feeling the moving rudder, read as
/// hydroid reads any log (`auto`: the logged ramp interpolated) and read held (`hold`, the
/// default before `between`). Interpolating the moving rudder must give what the held case
/// gives (each determined coefficient within 0.05 sigma); holding it must not (the
/// yaw moment's timing moves by half a sample: N'v and N'r 4 sigma or more away).
///
/// Measured (2026-11-26, a step reading a held input at its start): interpolated against
/// held, every determined coefficient within 0.01 sigma (0.22 sigma for N'v and N'r while the
/// last RK4 stage of each interval read the held rudder's next sample: the test below); read
/// held, N'v 6.1 and N'r 6.4 sigma off.
#[test]
fn a_moving_rudder_read_linearly_gives_what_a_held_rudder_gives() {
    let case = |held: bool, read: Option<&'static str>| Case {
        fit: &["turn35", "turn35_port"],
        held,
        read,
        seed: 2801,
        noise: 1.0,
    };
    let (held, moving, moving_held) = std::thread::scope(|s| {
        let a = s.spawn(|| run(&case(true, Some("hold"))));
        let b = s.spawn(|| run(&case(false, None)));
        let c = run(&case(false, Some("hold")));
        (a.join().unwrap(), b.join().unwrap(), c)
    });
    let apart = |o: &Outcome| -> Vec<(String, f64)> {
        held.determined()
            .map(|r| {
                let other = o.row(&r.name);
                (r.name.clone(), (other.estimate - r.estimate) / r.sigma)
            })
            .collect()
    };
    let (linear, step) = (apart(&moving), apart(&moving_held));
    println!(
        "{}\n{}\n{}",
        held.table(),
        moving.table(),
        moving_held.table()
    );
    println!("interpolated - held, in sigmas: {linear:.2?}\nread held - held: {step:.2?}");
    assert!(linear.iter().all(|(_, d)| d.abs() <= 0.05), "{linear:?}");
    let moved = |name: &str| step.iter().find(|(n, _)| n == name).map_or(0.0, |p| p.1);
    assert!(moved("Nv_p") >= 4.0 && moved("Nr_p") >= 4.0, "{step:?}");
    // docs/validation.md: "N'v, N'r 6.1 and 6.4 sigma off; ... within 0.05 sigma, 0.01
    // measured"
    let most = linear.iter().map(|(_, d)| d.abs()).fold(0.0, f64::max);
    assert_eq!(
        format!(
            "N'v, N'r {:.1} and {:.1} sigma off; {most:.2} measured",
            moved("Nv_p"),
            moved("Nr_p")
        ),
        "N'v, N'r 6.1 and 6.4 sigma off; 0.01 measured",
        "{step:?} {linear:?}"
    );
}

/// The models' forms, with the noise taken almost out: seed 2801 of the turns (the draw that
/// put Y'v 3 sigma off) with every sensor's noise a hundredth of the basin's, the rudder
/// moving and read linearly. A difference of form between the generator (Y&Y 2015 as written
/// in tests/independent/mmg.rs) and mmg3 would stay as the noise goes; the linear
/// derivatives come within 0.05 % of the truth.
///
/// Measured (2026-11-26): Y'v -0.02 %, Y'r +0.02 %, N'v +0.03 %, N'r +0.02 % (at a tenth of
/// the noise Y'v +0.23 %, at the basin's +2.9 %: the error goes with the noise).
#[test]
fn with_a_hundredth_of_the_noise_the_linear_derivatives_come_within_0_05_percent() {
    // docs/validation.md: "-0.02 %, +0.02 %, +0.03 %, +0.02 %"
    low_noise_within_0_05_percent(false, None, 2, "-0.02 %, +0.02 %, +0.03 %, +0.02 %");
}

/// The same with the hull feeling the rudder held at its samples and the log read held: the
/// physics are then exactly the zero-order hold hydroid assumes, and the estimates come as
/// close. Until 2026-11-26 they did not: hydroid's RK4 (src/numerics/ode.rs) read a held input at each
/// stage's time, so the last stage of an interval's last step, at the next sample time, saw
/// the next sample and a sixth of each step's rudder change acted early (N'v +0.16 %, N'r
/// +0.17 %, z -24). A step now reads a held input at its start (`ode::StageTime`).
#[test]
fn held_rudder_with_a_hundredth_of_the_noise_within_0_05_percent() {
    // docs/validation.md: "-0.029 %, +0.036 %, +0.045 %, +0.041 %"
    low_noise_within_0_05_percent(
        true,
        Some("hold"),
        3,
        "-0.029 %, +0.036 %, +0.045 %, +0.041 %",
    );
}

/// Seed 2801 of the turns at a hundredth of the basin's noise: Y'v, Y'r, N'v and N'r
/// within 0.05 % of the truth, their errors printed to `decimals` as `said`.
fn low_noise_within_0_05_percent(
    held: bool,
    read: Option<&'static str>,
    decimals: usize,
    said: &str,
) {
    let o = run(&Case {
        fit: &["turn35", "turn35_port"],
        held,
        read,
        seed: 2801,
        noise: 0.01,
    });
    println!("{}", o.table());
    for name in ["Yv_p", "Yr_p", "Nv_p", "Nr_p"] {
        let r = o.row(name);
        assert!(r.error_percent().abs() <= 0.05, "{name}: {}", o.table());
    }
    let printed: Vec<String> = ["Yv_p", "Yr_p", "Nv_p", "Nr_p"]
        .iter()
        .map(|n| format!("{:+.decimals$} %", o.row(n).error_percent()))
        .collect();
    assert_eq!(printed.join(", "), said, "{}", o.table());
}
