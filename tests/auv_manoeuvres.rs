//! `hydroid simulate` for the NPS AUV II (`npsauv`, docs/models/npsauv.md): rate-limited
//! inputs (ramps), the helm on the stern planes (the vertical zig-zag of submarine and AUV
//! practice) and on the rudder (the zig-zag of ITTC 7.5-04-02-01), and the bundled
//! configurations and exports (configs/simulate/npsauv_*.toml, cfd_exports/npsauv_*).

use crate::common;

use common::{hydroid, root, text};
use hydroid::app::simulate::config::{load, load_str, LoadedSim};
use hydroid::app::simulate::synth::{synthesize, Columns};
use hydroid::base::quantity::Quantity;

/// The bundled configurations and the exports they write.
const BUNDLED: [(&str, &str); 3] = [
    ("npsauv_helix", "npsauv_helix.dat"),
    ("npsauv_zigzag_vertical", "npsauv_zigzag_vertical.csv"),
    ("npsauv_zigzag_horizontal", "npsauv_zigzag_horizontal.csv"),
];

fn bundled_text(name: &str) -> String {
    std::fs::read_to_string(root().join(format!("configs/simulate/{name}.toml"))).unwrap()
}

/// `text` as a configuration beside the bundled ones, or its problems.
fn load_text(text: &str) -> Result<LoadedSim, String> {
    load_str(&root().join("configs/simulate/x.toml"), text).map_err(|e| e.to_string())
}

/// The motion of a configuration without measurement noise.
fn clean_run(text: &str) -> Columns {
    let mut sim = load_text(text).unwrap();
    sim.config.noise.sigma.clear();
    synthesize(&sim.config).unwrap()
}

/// The helix configuration shortened to 12 s, with `manoeuvre` lines in place of its steps.
fn helix_with(manoeuvre: &str) -> String {
    bundled_text("npsauv_helix")
        .replace("duration = 60", "duration = 12")
        .replace(
            "steps = [ { time = 5, rudder = \"10 deg\", stern_planes = \"10 deg\" } ]",
            manoeuvre,
        )
}

/// A step with a rate becomes a ramp of that slope lasting |change| / rate; a sequence of
/// steps through a rate-limited actuator turns around where the next step comes; an
/// interpolated input (rpm) ramps the same way; inputs without a rate still jump.
#[test]
fn a_step_with_a_rate_becomes_a_ramp() {
    let cols = clean_run(&helix_with(
        "steps = [ { time = 2, rudder = \"10 deg\", stern_planes = \"10 deg\", rpm = \"600 rpm\" },\n\
         { time = 3, bow_planes = \"5 deg\" }, { time = 4, bow_planes = \"-5 deg\" } ]\n\
         rates = { rudder = \"5 deg/s\", bow_planes = \"4 deg/s\", rpm = \"50 rpm/s\" }",
    ));
    let t = &cols[&Quantity::Time];
    let dt = t[1] - t[0];
    let deg = |q: Quantity| -> Vec<f64> { cols[&q].iter().map(|v| v.to_degrees()).collect() };
    let rudder = deg(Quantity::Rudder);
    // the ramp: where the rudder moves, its slope and the time it takes
    let moving: Vec<usize> = (1..t.len())
        .filter(|&k| (rudder[k] - rudder[k - 1]).abs() > 1e-9)
        .collect();
    let (first, last) = (moving[0], *moving.last().unwrap());
    let start = t[first - 1];
    let duration = t[last] - start;
    let slope = (rudder[last] - rudder[first - 1]) / duration;
    println!("rudder ramp: from {start:.2} s for {duration:.3} s at {slope:.4} deg/s");
    assert!((start - 2.0).abs() < 1e-9, "starts at the step: {start}");
    assert!(
        (duration - 2.0).abs() < 1e-9,
        "10 deg at 5 deg/s: {duration} s"
    );
    assert!((slope - 5.0).abs() < 1e-9, "{slope}");
    for k in first..=last {
        let want = 5.0 * (t[k] - 2.0);
        assert!(
            (rudder[k] - want).abs() < 1e-9,
            "t = {}: {} vs {want}",
            t[k],
            rudder[k]
        );
    }
    assert!((rudder[t.len() - 1] - 10.0).abs() < 1e-9);
    // no rate: the stern planes jump at the step
    let planes = deg(Quantity::SternPlanes);
    let jump = t.iter().position(|x| *x >= 2.0 - 1e-9).unwrap();
    assert!(planes[jump - 1].abs() < 1e-12 && (planes[jump] - 10.0).abs() < 1e-9);
    // a sequence: +5 deg from 3 s at 4 deg/s, then -5 deg from 4 s: the bow planes reach
    // 4 deg at 4 s, turn there and reach -5 deg 9 / 4 = 2.25 s later
    let bow = deg(Quantity::BowPlanes);
    let at = |s: f64| t.iter().position(|x| (x - s).abs() < dt / 2.0).unwrap();
    assert!((bow[at(4.0)] - 4.0).abs() < 1e-9, "{}", bow[at(4.0)]);
    assert!(bow[at(4.0) + 1] < bow[at(4.0)], "turns at the next step");
    assert!((bow[at(6.25)] + 5.0).abs() < 1e-9, "{}", bow[at(6.25)]);
    assert!(
        bow[at(6.25) - 1] > -5.0 + 1e-6,
        "arrives at 6.25 s, not before"
    );
    // an interpolated input: 500 to 600 rpm at 50 rpm/s takes 2 s (rev/s inside)
    let rpm: Vec<f64> = cols[&Quantity::Rpm].iter().map(|n| n * 60.0).collect();
    assert!((rpm[at(3.0)] - 550.0).abs() < 1e-9, "{}", rpm[at(3.0)]);
    assert!((rpm[at(4.0)] - 600.0).abs() < 1e-9 && (rpm[at(3.99)] - 599.5).abs() < 1e-9);
}

/// A bad rate names its key: an input the model lacks, a unit of another dimension, a rate
/// that is not positive, and a rate for the surface the helm moves.
#[test]
fn bad_rates_name_their_keys() {
    let e = load_text(&helix_with(
        "rates = { thrust = \"5 N/s\", rudder = \"5 deg\", stern_planes = \"-1 deg/s\", \
         bow_planes = \"2 m/s\" }",
    ))
    .unwrap_err();
    println!("{e}");
    assert!(
        e.contains("manoeuvre.rates.thrust") && e.contains("not an input of the npsauv model"),
        "{e}"
    );
    assert!(
        e.contains("manoeuvre.rates.rudder: a rate of rudder per second"),
        "{e}"
    );
    assert!(
        e.contains("manoeuvre.rates.stern_planes: must be a positive rate"),
        "{e}"
    );
    assert!(e.contains("manoeuvre.rates.bow_planes"), "{e}");
    let vertical = bundled_text("npsauv_zigzag_vertical").replace(
        "inputs = { rpm = \"1500 rpm\" }",
        "inputs = { rpm = \"1500 rpm\" }\nrates = { stern_planes = \"3 deg/s\" }",
    );
    let e = load_text(&vertical).unwrap_err();
    assert!(
        e.contains("manoeuvre.rates.stern_planes: the helm moves the stern planes"),
        "{e}"
    );
}

/// A zig-zag as the helm sailed it: the samples where the surface was reversed (the helm saw
/// the watched angle there and turned the surface the other way), the execute value of the
/// watched angle, and the overshoots (largest excursion beyond the reversing change after
/// each reversal, deg).
struct ZigZag {
    reversals: Vec<usize>,
    start: f64,
    overshoots: Vec<f64>,
    period: f64,
}

/// Measures a zig-zag on `surface` watching `watched` (ITTC 7.5-04-02-01: overshoot angles
/// and the period of the first full cycle, the time between the first and the third
/// reversal), executed at `execute` s with reversing change `change` (rad).
fn zigzag(
    cols: &Columns,
    surface: Quantity,
    watched: Quantity,
    execute: f64,
    change: f64,
) -> ZigZag {
    let t = &cols[&Quantity::Time];
    let d = &cols[&surface];
    let a = &cols[&watched];
    let k0 = t.iter().position(|x| *x >= execute - 1e-9).unwrap();
    let start = a[k0];
    // the command's sign: that of the deflection's latest movement
    let mut reversals = Vec::new();
    let mut moving = 0.0;
    for k in k0..t.len() - 1 {
        let step = d[k + 1] - d[k];
        if step.abs() > 1e-12 {
            if moving != 0.0 && step.signum() != moving {
                reversals.push(k);
            }
            moving = step.signum();
        }
    }
    let mut overshoots = Vec::new();
    for (i, &k) in reversals.iter().enumerate() {
        let end = reversals.get(i + 1).copied().unwrap_or(t.len());
        let side = (a[k] - start).signum();
        let peak = a[k..end]
            .iter()
            .map(|x| (x - start) * side)
            .fold(f64::MIN, f64::max);
        overshoots.push((peak - change).to_degrees());
    }
    let period = match reversals.as_slice() {
        [r1, _, r3, ..] => t[*r3] - t[*r1],
        _ => f64::NAN,
    };
    ZigZag {
        reversals,
        start,
        overshoots,
        period,
    }
}

/// Checks that every reversal came on the first sample at which the watched angle had
/// changed by `change` from its execute value (towards the side the surface drove it).
fn reverses_at_the_change(cols: &Columns, z: &ZigZag, watched: Quantity, change: f64) {
    let a = &cols[&watched];
    assert!(z.reversals.len() >= 4, "{} reversals", z.reversals.len());
    for &k in &z.reversals {
        let now = (a[k] - z.start).abs();
        let before = (a[k - 1] - z.start).abs();
        assert!(
            now >= change && before < change,
            "reversal at sample {k}: change {:.4} deg, one sample before {:.4} deg",
            now.to_degrees(),
            before.to_degrees()
        );
    }
    // the reversals alternate sides
    for w in z.reversals.windows(2) {
        assert!((a[w[0]] - z.start).signum() != (a[w[1]] - z.start).signum());
    }
}

/// One bundled zig-zag export: `surface` reverses at +-`change_deg` of `watched` within one
/// sample from 5 s on; every overshoot but the last (which the end of the run may cut) and
/// the period lie in the given ranges (deg, s); the other plane's angle `other` stays below
/// `other_max_deg`.
struct ZigZagCase {
    export: &'static str,
    surface: Quantity,
    watched: Quantity,
    change_deg: f64,
    overshoots: std::ops::Range<f64>,
    period: std::ops::Range<f64>,
    other: Quantity,
    other_max_deg: f64,
}

fn check_zigzag(case: ZigZagCase) {
    let cols = clean_run(&bundled_text(case.export));
    let change = case.change_deg.to_radians();
    let z = zigzag(&cols, case.surface, case.watched, 5.0, change);
    let t = &cols[&Quantity::Time];
    println!(
        "{}: reversals at {:?} s, overshoots {:?} deg, period {:.2} s",
        case.export,
        z.reversals.iter().map(|k| t[*k]).collect::<Vec<_>>(),
        z.overshoots
            .iter()
            .map(|o| (o * 100.0).round() / 100.0)
            .collect::<Vec<_>>(),
        z.period
    );
    reverses_at_the_change(&cols, &z, case.watched, change);
    for o in &z.overshoots[..z.overshoots.len() - 1] {
        assert!(case.overshoots.contains(o), "{o} deg");
    }
    assert!(case.period.contains(&z.period), "{} s", z.period);
    let other = cols[&case.other].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(
        other < case.other_max_deg.to_radians(),
        "{}",
        other.to_degrees()
    );
}

/// The vertical 10/10 zig-zag (configs/simulate/npsauv_zigzag_vertical.toml, 1500 rpm): the
/// stern planes reverse at +-10 deg of pitch change, within one sample, and the pitch
/// oscillates with plausible overshoots and period; the horizontal plane stays still.
#[test]
fn the_vertical_zigzag_oscillates_in_pitch() {
    check_zigzag(ZigZagCase {
        export: "npsauv_zigzag_vertical",
        surface: Quantity::SternPlanes,
        watched: Quantity::Pitch,
        change_deg: 10.0,
        // positive (the pitch goes on after the reversal) and a fraction of the reversing
        // change for a vehicle this stable in pitch (BG = 0.061 m); measured 1.9 to 2.2 deg,
        // period 24.0 s
        overshoots: 0.5..5.0,
        period: 10.0..40.0,
        // the horizontal plane is hardly touched (only through the products of inertia)
        other: Quantity::Yaw,
        other_max_deg: 1.0,
    });
}

/// The horizontal 20/20 zig-zag (configs/simulate/npsauv_zigzag_horizontal.toml): the rudder
/// reverses at +-20 deg of heading change within one sample; overshoots and period plausible.
#[test]
fn the_horizontal_zigzag_oscillates_in_heading() {
    check_zigzag(ZigZagCase {
        export: "npsauv_zigzag_horizontal",
        surface: Quantity::Rudder,
        watched: Quantity::Yaw,
        change_deg: 20.0,
        // measured 13.5 to 14.9 deg, period 32.9 s: a large overshoot, as for a slender body
        // with a small rudder at 1.9 m/s
        overshoots: 5.0..20.0,
        period: 20.0..60.0,
        // the vertical plane is only touched through the heel and the products of inertia
        other: Quantity::Pitch,
        other_max_deg: 5.0,
    });
}

/// The helm on the stern planes needs the model to have them: a model without stern planes
/// or pitch names the surface's key.
#[test]
fn the_helm_needs_the_surface_and_its_angle() {
    let kvlcc2 = std::fs::read_to_string(root().join("configs/simulate/kvlcc2_zigzag20.toml"))
        .unwrap()
        .replace(
            "rudder = \"20 deg\"\nheading = \"20 deg\"",
            "surface = \"stern_planes\"\ndeflection = \"10 deg\"\npitch = \"10 deg\"",
        );
    let e = load_text(&kvlcc2).unwrap_err();
    assert!(
        e.contains("manoeuvre.steering.surface: the mmg3 model has no stern planes input or no pitch state"),
        "{e}"
    );
    // and `heading` is the rudder's word
    let e = load_text(
        &bundled_text("npsauv_zigzag_vertical")
            .replace("pitch = \"10 deg\"", "heading = \"10 deg\""),
    )
    .unwrap_err();
    assert!(
        e.contains("manoeuvre.steering.heading: is not used by the helm of the stern planes"),
        "{e}"
    );
}

/// The bundled configurations load and carry configs/vehicles/npsauv.toml's vehicle, fluid
/// and coefficients unchanged but for the cross-flow form (the exports were simulated with
/// MSS's 11-station sum, `cross_flow = "stations"`; the vehicle file gives the default); their exports stay under 2 MB and read back with `hydroid
/// inspect` (tests/cli.rs checks that they are what the configurations write).
#[test]
fn bundled_configurations_and_exports() {
    let form = |t: &mut toml::Table| {
        let mut p = t["vehicle"]["particulars"].as_table().unwrap().clone();
        let form = p.remove("cross_flow").unwrap();
        t["vehicle"].as_table_mut().unwrap()["particulars"] = toml::Value::Table(p);
        form.as_str().unwrap().to_string()
    };
    let mut vehicle: toml::Table = toml::from_str(
        &std::fs::read_to_string(root().join("configs/vehicles/npsauv.toml")).unwrap(),
    )
    .unwrap();
    assert_eq!(form(&mut vehicle), "integral");
    for (name, export) in BUNDLED {
        let path = root().join(format!("configs/simulate/{name}.toml"));
        load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let mut file: toml::Table = toml::from_str(&bundled_text(name)).unwrap();
        assert_eq!(form(&mut file), "stations", "{name}");
        for section in ["vehicle", "fluid", "coefficients"] {
            assert_eq!(file[section], vehicle[section], "{name}: [{section}]");
        }
        let bundled = root().join("cfd_exports").join(export);
        let size = std::fs::metadata(&bundled).unwrap().len();
        assert!(size < 2_000_000, "{export}: {size} bytes");
        let o = hydroid(&["inspect", bundled.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{export}: {}", text(&o.stderr));
        println!("{export}: {size} bytes\n{}", text(&o.stdout));
    }
}
