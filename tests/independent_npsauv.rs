//! Identification accuracy of hydroid's `npsauv` model on data it did not make (issue 22):
//! the NPS AUV II generator of tests/independent/npsauv.rs (Healey & Lienard 1993 with the
//! published set, Fossen's rigid-body kinetics, strip-theory cross-flow drag; own RK4 at
//! 2.5 ms, fins moving continuously through a rate-limited servo, a 50 Hz log with sensor
//! noise), identified by `hydroid run` (as a library) with a configuration like the bundled
//! configs/npsauv_joint.toml: the paper's 17 coefficients from the helix and a horizontal
//! 20/20 zig-zag jointly, every other coefficient held at its published value, hydroid's
//! default tuning and the sensors' noise as the bundled configuration gives it.

use crate::independent;

use independent::accuracy::{identify, Outcome};
use independent::npsauv::{self, CrossFlow, Hl, NpsAuv};
use std::fmt::Write as _;
use std::path::Path;

/// hydroid's names for the fixture's coefficients where they differ (configs/npsauv_joint.toml).
fn hydroid_name(csv: &str) -> &str {
    match csv {
        "Xrr" => "Xrr_hl",
        "Xvr" => "Xvr_hl",
        "Xvv" => "Xvv_hl",
        "Xww" => "Xww_hl",
        "Muq" => "Mq",
        "Muw" => "Mw",
        other => other,
    }
}

/// Seconds of helix and of zig-zag logged (50 Hz).
const HELIX: f64 = 40.0;
const ZIGZAG: f64 = 50.0;

/// Writes the two logs and a configuration into `dir`; returns the configuration's path.
/// `form` is hydroid's `vehicle.particulars.cross_flow` (None: its default).
fn write_case(dir: &Path, auv: &NpsAuv, form: Option<&str>) -> std::path::PathBuf {
    let helix = npsauv::helix(auv, HELIX, 2201);
    let zigzag = npsauv::zigzag(auv, ZIGZAG, 2202);
    helix.log.write_csv(dir, "helix.csv");
    zigzag.log.write_csv(dir, "zigzag.csv");
    let truth = npsauv::paper_17_truth(&auv.hl);
    let estimated: Vec<&str> = truth.iter().map(|t| t.0).collect();
    let mut c = String::new();
    writeln!(
        c,
        "title = \"NPS AUV II: 17 coefficients from independently generated helix and zig-zag\"\n\
         [vehicle]\nname = \"NPS AUV II (Healey & Lienard 1993)\"\n\
         mass = {mass}\nlength = {l}\nixx = {ixx}\niyy = {iyy}\nizz = {izz}\n\
         buoyancy = {b}\nbg = {zg}\nreference_area = 28.09\nreference_length = {l}\n\
         [fluid]\nrho = {rho}\nmu = 0.00108\n\
         [vehicle.particulars]\nixy = -13.58\niyz = -13.58\nixz = -13.58\nx_g = 0.0\ny_g = 0.0\n\
         cdy = {cdy}\ncdz = {cdz}\nhull_height = {h}\nhull_breadth = {bb}\ncd0 = {cd0}\n\
         propeller_k = {k}\npropeller_ct = {ct}\n{form}[coefficients]",
        mass = auv.mass,
        l = auv.length,
        ixx = auv.inertia[0][0],
        iyy = auv.inertia[1][1],
        izz = auv.inertia[2][2],
        b = auv.buoyancy,
        zg = auv.r_g[2],
        rho = auv.rho,
        cdy = auv.cdy,
        cdz = auv.cdz,
        h = auv.hull_height,
        bb = auv.hull_breadth,
        cd0 = auv.cd0,
        k = auv.prop_k,
        ct = auv.prop_ct,
        form = form.map_or(String::new(), |f| format!("cross_flow = \"{f}\"\n")),
    )
    .unwrap();
    for (name, v) in independent::published("npsauv_healey_lienard1993.csv") {
        let h = hydroid_name(&name);
        if !estimated.contains(&h) {
            writeln!(c, "{h} = {v:e}").unwrap();
        }
    }
    let columns = "[hekf.runs.columns]\ntime = \"Time\"\nx = \"X\"\ny = \"Y\"\nz = \"Z\"\n\
        u = \"u\"\nv = \"v\"\nw = \"w\"\np = \"p\"\nq = \"q\"\nr = \"r\"\nroll = \"Roll\"\n\
        pitch = \"Pitch\"\nyaw = \"Heading\"\nrudder = \"Rudder\"\n\
        stern_planes = \"Stern Planes\"\nbow_planes = \"Bow Planes\"\nrpm = \"Propeller Speed\"\n";
    // fins held at each logged sample by the generator are read held (`between`); moving
    // fins are read as hydroid reads any log (`auto`: the logged ramps interpolated)
    let between = if npsauv::HOLD_FINS.with(|h| h.get()) {
        "between = { rudder = \"hold\", stern_planes = \"hold\", bow_planes = \"hold\" }\n"
    } else {
        ""
    };
    write!(
        c,
        "[hekf]\nmodel = \"npsauv\"\nestimate = {estimated:?}\n\
         noise = {{ x = \"0.01 m\", y = \"0.01 m\", z = \"0.01 m\", u = \"0.01 m/s\", \
         v = \"0.01 m/s\", w = \"0.01 m/s\", p = \"0.1 deg/s\", q = \"0.1 deg/s\", \
         r = \"0.1 deg/s\", roll = \"0.05 deg\", pitch = \"0.05 deg\", yaw = \"0.05 deg\" }}\n\
         [[hekf.runs]]\nname = \"helix\"\nfile = \"helix.csv\"\n{between}{columns}\
         [[hekf.runs]]\nname = \"zig-zag\"\nfile = \"zigzag.csv\"\n{between}{columns}"
    )
    .unwrap();
    let path = dir.join("npsauv.toml");
    std::fs::write(&path, c).unwrap();
    path
}

fn run(cross_flow: CrossFlow, form: Option<&str>) -> Outcome {
    let auv = NpsAuv::build(Hl::published(), cross_flow);
    let dir = tempfile::tempdir().unwrap();
    let config = write_case(dir.path(), &auv, form);
    let outcome = identify(&config, &npsauv::paper_17_truth(&auv.hl));
    println!("{}", outcome.table());
    for w in &outcome.warnings {
        println!("warning: {w}");
    }
    outcome
}

/// The helix (40 s) and the horizontal 20/20 zig-zag (50 s), 50 Hz, fins moving at
/// 10 deg/s, the generator's drag Healey & Lienard's integral over the hull, identified with
/// hydroid's defaults (`cross_flow = "integral"`, the fins read by `between = "auto"`).
/// Measured: 17/17 within 2 sigma, worst |z| 1.56 (Kv), Nv +0.14 %, Nr +0.08 %, Ndr +0.06 %;
/// Yp flagged (sigma 25 %). Before the cross-flow form was a setting (hydroid summing MSS's 11
/// stations, 1.1 L in all, whose pure-yaw moment is 1.44 times the integral's): 11/17, Nv
/// +12.7 % (z -18.6), Ndr +1.3 % (z -14.2), Nr +1.7 % (z -6.9). Asserted: all determined
/// coefficients within 2 sigma, and docs/validation.md's numbers at their printed digits (the
/// runs before the setting are a record, not repeated).
#[test]
fn helix_and_zigzag_at_50_hz_with_moving_fins() {
    let o = run(CrossFlow::StripTheory, None);
    o.assert_undetermined_flagged();
    assert_eq!(o.within_two_sigma(), (17, 17), "{}", o.table());
    assert_eq!(
        format!("{}; {}", worst(&o), errors(&o, &["Nv", "Nr", "Ndr"])),
        "worst z 1.56 (Kv); Nv +0.14 %, Nr +0.08 %, Ndr +0.06 %",
        "{}",
        o.table()
    );
}

/// "worst z 1.56 (Kv)": the largest |z| of the determined coefficients and whose it is, as
/// docs/validation.md prints it.
fn worst(o: &Outcome) -> String {
    let r = o
        .determined()
        .max_by(|a, b| a.z.abs().total_cmp(&b.z.abs()))
        .expect("a determined coefficient");
    format!("worst z {:.2} ({})", r.z.abs(), r.name)
}

/// "Nv +0.14 %, Nr +0.08 %": the errors of `names` as docs/validation.md prints them.
fn errors(o: &Outcome, names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("{n} {:+.2} %", o.row(n).error_percent()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// MSS's 11-station sum and the fins held at each logged sample as the hull feels them, read
/// with `cross_flow = "stations"` and `between = "hold"`: the generator and hydroid's model
/// then agree in form, and this checks the generator (kinetics, signs, units, the column maps)
/// against hydroid. Measured: 17/17 within 2 sigma, worst |z| 1.53 (Kv; 1.57 while the last
/// RK4 stage of each interval read the held fins' next sample); asserted at the digits of
/// docs/validation.md.
#[test]
fn helix_and_zigzag_with_the_station_sum_and_held_fins() {
    npsauv::HOLD_FINS.with(|h| h.set(true));
    let o = run(CrossFlow::Stations, Some("stations"));
    npsauv::HOLD_FINS.with(|h| h.set(false));
    o.assert_undetermined_flagged();
    assert_eq!(o.within_two_sigma(), (17, 17), "{}", o.table());
    assert_eq!(worst(&o), "worst z 1.53 (Kv)", "{}", o.table());
}

/// MSS npsauv.m's form as written (11 stations, pitch integrand w + x q), fins moving, read
/// with `cross_flow = "mss"`. Measured: 17/17 within 2 sigma, worst |z| 1.53 (Kv), Mw -0.35 %
/// (z -0.94). With hydroid's former station sum and its strip-theory pitch moment the pitch
/// form moved Mw by +1.9 % (z +5.5) and Mq, Mds beyond 2 sigma.
#[test]
fn helix_and_zigzag_with_the_mss_cross_flow_form() {
    let o = run(CrossFlow::Mss, Some("mss"));
    o.assert_undetermined_flagged();
    assert_eq!(o.within_two_sigma(), (17, 17), "{}", o.table());
    // docs/validation.md: "worst z 1.53; Mw -0.35 %" (the run with the former pitch moment is
    // a record, not repeated)
    assert_eq!(
        format!("{}; {}", worst(&o), errors(&o, &["Mw"])),
        "worst z 1.53 (Kv); Mw -0.35 %",
        "{}",
        o.table()
    );
}
