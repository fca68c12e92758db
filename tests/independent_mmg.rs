//! Identification accuracy of hydroid's `mmg3` model on data it did not make (issue 22): the
//! KVLCC2 1/45.7 generator of tests/independent/mmg.rs (Yasukawa & Yoshimura 2015 equations
//! and Tables 2-3; own RK4 at 5 ms; the rudder moving at 2.32 deg/s x sqrt(45.7) = 15.68
//! deg/s through the steering gear; propeller at its self-propulsion speed; a 10 Hz basin
//! log with sensor noise), identified by `hydroid run` (as a library) with a configuration
//! like the bundled configs/ship_kvlcc2.toml: the twelve sway and yaw hull derivatives,
//! everything else held at the published values, hydroid's default tuning.

mod independent;

use independent::accuracy::{identify, Outcome};
use independent::mmg::{self, Kvlcc2};
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

/// Writes the +-35 deg turns (200 s) and the 20/20 zig-zag (150 s), logged at `hz`, and a
/// configuration fitting `fit` (names of the runs: "turn35", "turn35_port", "zigzag20"),
/// the others as validation.
/// With `held` the hull feels the rudder held at its logged samples (a diagnostic).
fn write_case(dir: &Path, ship: &Kvlcc2, hz: f64, fit: &[&str], held: bool) -> std::path::PathBuf {
    let runs = [
        (
            "turn35",
            mmg::turn_held(ship, held, 35f64.to_radians(), 200.0, hz, 2801),
        ),
        (
            "turn35_port",
            mmg::turn_held(ship, held, -35f64.to_radians(), 200.0, hz, 2802),
        ),
        ("zigzag20", mmg::zigzag_held(ship, held, 150.0, hz, 2803)),
    ];
    let truth = mmg::hull_truth(ship);
    let estimated: Vec<&str> = truth.iter().map(|t| t.0).collect();
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
    writeln!(
        c,
        "[hekf]\nmodel = \"mmg3\"\npreset = \"hydroid\"\nestimate = {estimated:?}"
    )
    .unwrap();
    for (name, run) in &runs {
        run.log.write_csv(dir, &format!("{name}.csv"));
        let table = if fit.contains(name) {
            "hekf.runs"
        } else {
            "hekf.validation"
        };
        writeln!(
            c,
            "[[{table}]]\nname = \"{name}\"\nfile = \"{name}.csv\"\n{between}[{table}.columns]\n\
             {COLUMNS}",
            // a rudder the generator holds at each logged sample is read held; a moving one as
            // hydroid reads any log (`auto`: the logged ramp interpolated)
            between = if held {
                "between = { rudder = \"hold\" }\n"
            } else {
                ""
            }
        )
        .unwrap();
    }
    let path = dir.join("kvlcc2.toml");
    std::fs::write(&path, c).unwrap();
    path
}

fn run(hz: f64, fit: &[&str], held: bool) -> Outcome {
    let ship = Kvlcc2::model();
    let dir = tempfile::tempdir().unwrap();
    let config = write_case(dir.path(), &ship, hz, fit, held);
    let outcome = identify(&config, &mmg::hull_truth(&ship));
    println!("{}", outcome.table());
    for w in &outcome.warnings {
        println!("warning: {w}");
    }
    outcome
}

/// The bundled set-up: the +-35 deg turns fitted, the zig-zag for validation, 10 Hz, the
/// logged rudder read as hydroid reads any log (`between = "auto"`: its ramps interpolated).
/// Measured: 7 of 9 determined coefficients within 2 sigma; Nv_p +0.10 % (z -0.25), Nr_p
/// +0.20 % (z -0.5), but Yv_p and Yr_p off by 2.9 and 4.1 % at 3 sigma, as with the rudder
/// held on both sides (the diagnostic below): what is left is the sway equation's form, not
/// the sampling (held, before `between`: 2 of 9, Nv_p and Nr_p at z +6.5 and +6.6).
#[test]
#[ignore = "issue 22: 7/9 within 2 sigma: Yv_p -0.3242 +- 0.0030 (truth -0.315, +2.9 %, z -3.0), Yr_p 0.0796 +- 0.0011 (0.083, -4.1 %, z -3.2); Yvvr_p, Yrrr_p, Nvvv_p undetermined and flagged"]
fn turns_at_10_hz_identify_the_hull_derivatives() {
    let o = run(10.0, &["turn35", "turn35_port"], false);
    o.assert_undetermined_flagged();
    let (k, n) = o.within_two_sigma();
    assert_eq!(k, n, "{}", o.table());
}

/// The turns and the zig-zag fitted jointly, 10 Hz, the rudder read by `between = "auto"`.
/// Measured: 9 of 10 determined coefficients within 2 sigma, worst Nv_p at z -2.04 (+0.19 %);
/// Yv_p +0.23 %, Yr_p -0.34 %, Nr_p +0.20 %; the cubic terms correlated 0.92 to 0.98 and
/// flagged (read held, before `between`: 0 of 10, Yv_p z -11.2, Yvvv_p z +15.4).
#[test]
#[ignore = "issue 22: 9/10 within 2 sigma: Nv_p -0.13727 +- 0.00013 (truth -0.137, +0.19 %, z -2.04); Yrrr_p, Nvvv_p undetermined and flagged"]
fn turns_and_zigzag_at_10_hz_identify_the_hull_derivatives() {
    let o = run(10.0, &["turn35", "turn35_port", "zigzag20"], false);
    o.assert_undetermined_flagged();
    let (k, n) = o.within_two_sigma();
    assert_eq!(k, n, "{}", o.table());
}

/// Diagnostic: the turns again, the hull feeling the rudder held at each logged sample (as
/// mmg3 assumes) while the log is the same: what is left is model form, not sampling.
/// Measured: 7 of 9 within 2 sigma; Nv_p +0.16 % (z -0.4), Nr_p +0.27 % (z -0.7), but
/// Yv_p -0.3241 +- 0.0029 (+2.9 %, z -3.2) and Yr_p 0.0796 +- 0.0010 (-4.0 %, z -3.3).
#[test]
#[ignore = "diagnostic for issue 22: the rudder's inter-sample rule taken out; 7/9, Yv_p z -3.2, Yr_p z -3.3"]
fn turns_at_10_hz_with_the_rudder_held_between_samples() {
    let o = run(10.0, &["turn35", "turn35_port"], true);
    let (k, n) = o.within_two_sigma();
    assert_eq!(k, n, "{}", o.table());
}
