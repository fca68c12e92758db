//! Manoeuvre measures against hand-computed values on constructed tracks.

use hydroid::manoeuvre::imo::{turning_checks, zigzag_checks};
use hydroid::manoeuvre::{
    turning_circle, zigzag, ComparisonTable, Criterion, History, Measure, Ship, Side,
    TurningOptions, Verdict, ZigZagOptions,
};
use std::f64::consts::PI;

const U: f64 = 2.0; // approach speed, m/s
const R: f64 = 100.0; // turning radius, m
const T0: f64 = 10.0; // execute, s
const DT: f64 = 0.5; // sampling interval, s

/// A straight approach along the heading `psi0` at U, then at T0 a circle of radius R to
/// `side` at the same speed until the heading has changed by `turn`; the rudder steps to
/// 35 deg (sign by side) one sample after the execute.
fn circle(psi0: f64, side: f64, turn: f64, velocities: bool) -> History {
    let n = ((T0 + turn * R / U) / DT).ceil() as usize + 1;
    let mut cols: [Vec<f64>; 5] = Default::default();
    for i in 0..n {
        let t = i as f64 * DT;
        let theta = (U * (t - T0) / R).max(0.0);
        // Track in the frame of the original course: along, across (to starboard).
        let (a, c) = if t <= T0 {
            (U * (t - T0), 0.0)
        } else {
            (R * theta.sin(), side * R * (1.0 - theta.cos()))
        };
        let (s, co) = psi0.sin_cos();
        let psi = (psi0 + side * theta).rem_euclid(2.0 * PI); // wrapped like a compass
        let rudder = if t <= T0 {
            0.0
        } else {
            side * 35f64.to_radians()
        };
        for (col, v) in cols.iter_mut().zip([
            t,
            psi,
            50.0 + a * co - c * s,
            -20.0 + a * s + c * co,
            rudder,
        ]) {
            col.push(v);
        }
    }
    let [t, psi, x, y, d] = cols;
    let h = History::new(t.clone(), psi)
        .unwrap()
        .with_track(x, y)
        .unwrap()
        .with_rudder(d)
        .unwrap();
    if velocities {
        h.with_velocity(vec![U; t.len()], vec![0.0; t.len()])
            .unwrap()
    } else {
        h
    }
}

fn value(m: &Measure) -> f64 {
    m.value().unwrap_or_else(|| panic!("missing: {m:?}"))
}

fn close(m: &Measure, expected: f64, tol: f64) {
    let v = value(m);
    assert!((v - expected).abs() <= tol, "{v} != {expected} (tol {tol})");
}

fn check_circle(h: &History, side: Side) {
    let c = turning_circle(h, &TurningOptions::default()).unwrap();
    assert_eq!(c.side, side);
    assert!((c.execute_time - T0).abs() < 1e-12);
    // Chord error of linear interpolation on the arc: R (1 - cos(U DT / 2R)) ~ 1.3e-3 m.
    close(&c.advance, R, 2e-3);
    close(&c.transfer, R, 2e-3);
    close(&c.tactical_diameter, 2.0 * R, 2e-3);
    close(&c.steady_diameter, 2.0 * R, 1e-6);
    close(&c.time_to_90, 0.5 * PI * R / U, 1e-9);
    close(&c.time_to_180, PI * R / U, 1e-9);
    close(&c.approach_speed, U, 1e-9);
    close(&c.steady_speed, U, 1e-9);
    close(&c.speed_ratio, 1.0, 1e-9);
    close(&c.rudder_angle, side.sign() * 35f64.to_radians(), 1e-12);
    close(&c.rudder_time, DT, 1e-9);
}

#[test]
fn starboard_circle_after_a_straight_approach() {
    check_circle(&circle(0.0, 1.0, 1.5 * PI, true), Side::Starboard);
}

#[test]
fn port_circle_on_a_heading_that_wraps_through_north() {
    // Original course 250 deg, turning to port through 360/0: the heading wraps.
    check_circle(
        &circle(250f64.to_radians(), -1.0, 1.5 * PI, false),
        Side::Port,
    );
    check_circle(
        &circle(20f64.to_radians(), -1.0, 1.5 * PI, false),
        Side::Port,
    );
}

#[test]
fn a_given_execute_time_replaces_the_rudder() {
    let h = circle(0.0, 1.0, 1.2 * PI, false);
    let c = turning_circle(
        &h,
        &TurningOptions {
            execute_time: Some(T0),
        },
    )
    .unwrap();
    close(&c.tactical_diameter, 2.0 * R, 2e-3);
    let e = turning_circle(
        &h,
        &TurningOptions {
            execute_time: Some(-1.0),
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("outside the run"), "{e}");
}

#[test]
fn a_turn_short_of_90_deg_says_what_is_missing_and_never_writes_nan() {
    let h = circle(0.0, 1.0, 60f64.to_radians(), true);
    let c = turning_circle(&h, &TurningOptions::default()).unwrap();
    assert!((c.max_heading_change.to_degrees() - 60.0).abs() < 0.5);
    for m in [
        &c.advance,
        &c.transfer,
        &c.time_to_90,
        &c.tactical_diameter,
        &c.time_to_180,
    ] {
        match m {
            Measure::Missing(r) => assert!(r.contains("needs") && r.contains("deg"), "{r}"),
            Measure::Value(v) => panic!("expected missing, got {v}"),
        }
    }
    assert!(matches!(c.steady_diameter, Measure::Missing(_)));
    let json = serde_json::to_string(&c).unwrap();
    assert!(!json.contains("null") && !json.contains("NaN"), "{json}");
    let ship = Ship::new(200.0, 8.0).unwrap();
    let checks = turning_checks(&c, &ship);
    assert!(checks
        .iter()
        .all(|k| matches!(k.verdict, Verdict::NotAssessed(_))));
    let table = ComparisonTable::new(&c.measures(), None, &checks, &[]);
    assert!(table
        .notes
        .iter()
        .any(|n| n.starts_with("advance (measured): the heading changes by 60")));
}

#[test]
fn a_history_without_track_or_execute_is_refused_with_the_reason() {
    let h = History::new(vec![0.0, 1.0, 2.0], vec![0.0; 3]).unwrap();
    let e = turning_circle(&h, &TurningOptions::default()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "the turning circle needs the track (x, y), which the history does not have"
    );
    let e = zigzag(&h, &ZigZagOptions::default()).unwrap_err();
    assert!(e.to_string().contains("needs the rudder angle"), "{e}");
}

// Zig-zag: heading change A sin(w (t - T0)) after T0, executes at 10 deg, bang-bang rudder.
const A: f64 = 15.0; // deg
const PERIOD: f64 = 40.06; // s (peaks fall between samples)
const ZDT: f64 = 0.05; // s

fn zig(side: f64, until: f64, with_rudder: bool) -> History {
    let w = 2.0 * PI / PERIOD;
    let e = (10.0 / A).asin() / w; // time from T0 to the second execute
    let n = (until / ZDT) as usize + 1;
    let (mut t, mut psi, mut d, mut x, mut y) = (vec![], vec![], vec![], vec![], vec![]);
    for i in 0..n {
        let ti = i as f64 * ZDT;
        let phase = ti - T0;
        let change = if phase > 0.0 {
            A * (w * phase).sin()
        } else {
            0.0
        };
        // +10 deg until the second execute, -10 until the third, +10 until the fourth ...
        let half = PERIOD / 2.0;
        let k = ((phase - e) / half).floor();
        let rudder = if phase <= 1e-9 {
            0.0
        } else if phase < e {
            10.0
        } else if k as i64 % 2 == 0 {
            -10.0
        } else {
            10.0
        };
        t.push(ti);
        psi.push((side * change).to_radians());
        d.push((side * rudder).to_radians());
        x.push(U * ti);
        y.push(0.0);
    }
    let h = History::new(t, psi).unwrap().with_track(x, y).unwrap();
    if with_rudder {
        h.with_rudder(d).unwrap()
    } else {
        h
    }
}

fn check_zigzag(side: f64) {
    let z = zigzag(&zig(side, 120.0, true), &ZigZagOptions::default()).unwrap();
    let w = 2.0 * PI / PERIOD;
    let e = (10.0 / A).asin() / w;
    assert_eq!(
        z.side,
        if side > 0.0 {
            Side::Starboard
        } else {
            Side::Port
        }
    );
    assert!(z.rudder_angle_detected && z.heading_angle_detected);
    close(&z.rudder_angle, 10f64.to_radians(), 1e-12);
    assert!((z.heading_angle - 10f64.to_radians()).abs() < 1e-12);
    assert!((z.execute_time - T0).abs() < 1e-9);
    // Overshoots 15 - 10 = 5 deg; peak refined by a parabola through three samples.
    close(&z.first_overshoot.map(f64::to_degrees), 5.0, 1e-6);
    close(&z.second_overshoot.map(f64::to_degrees), 5.0, 1e-6);
    // Crossings interpolated linearly on the sine: error ~ DT^2 / 8 * w^2 tan(...) < 1e-4 s.
    close(&z.initial_turning_time, e, 1e-4);
    close(&z.initial_turning_distance, U * e, 2e-4);
    close(&z.time_to_check_yaw, PERIOD / 4.0 - e, 1e-4);
    close(&z.period, PERIOD, 1e-4);
    close(&z.approach_speed, U, 1e-9);
}

#[test]
fn zigzag_10_10_to_starboard_with_bang_bang_rudder() {
    check_zigzag(1.0);
}

#[test]
fn zigzag_10_10_to_port() {
    check_zigzag(-1.0);
}

#[test]
fn zigzag_without_rudder_needs_the_angles_given_and_misses_what_the_run_lacks() {
    let opts = ZigZagOptions {
        execute_time: Some(T0),
        rudder_angle: None,
        heading_angle: Some(10f64.to_radians()),
    };
    // Ends before the fourth execute: no second overshoot's end, no period.
    let z = zigzag(&zig(1.0, 50.0, false), &opts).unwrap();
    close(&z.first_overshoot.map(f64::to_degrees), 5.0, 1e-6);
    assert!(matches!(&z.rudder_angle, Measure::Missing(r) if r.contains("no rudder")));
    assert!(matches!(&z.period, Measure::Missing(r) if r.contains("fourth execute")));
    assert!(matches!(&z.second_overshoot, Measure::Missing(_)));
    let json = serde_json::to_string(&z).unwrap();
    assert!(!json.contains("null"), "{json}");
    let given_execute = ZigZagOptions {
        execute_time: Some(T0),
        ..Default::default()
    };
    let e = zigzag(&zig(1.0, 50.0, false), &given_execute).unwrap_err();
    assert!(e.to_string().contains("execute heading angle"), "{e}");
}

#[test]
fn imo_checks_of_a_10_10_zigzag_with_the_comparison_table() {
    let z = zigzag(&zig(1.0, 120.0, true), &ZigZagOptions::default()).unwrap();
    // L/V = 12 s: first overshoot limit 5 + 6 = 11 deg, second 17.5 + 9 = 26.5 deg.
    let ship = Ship::new(96.0, 8.0).unwrap();
    let checks = zigzag_checks(&z, &ship);
    let kinds: Vec<Criterion> = checks.iter().map(|c| c.criterion).collect();
    assert_eq!(
        kinds,
        [
            Criterion::FirstOvershoot10,
            Criterion::SecondOvershoot10,
            Criterion::InitialTurning
        ]
    );
    assert!((checks[0].limit.to_degrees() - 11.0).abs() < 1e-9);
    assert!((checks[1].limit.to_degrees() - 26.5).abs() < 1e-9);
    assert!(checks.iter().all(|c| c.verdict == Verdict::Pass));
    // A short ship: L/V = 1.5 s gives 10 deg and 25 deg, still passed, but it travels
    // U e = 9.29 m to 10 deg heading change, more than 2.5 L = 7.5 m.
    let short = Ship::new(3.0, 2.0).unwrap();
    let c = zigzag_checks(&z, &short);
    assert_eq!(c[2].verdict, Verdict::Fail);
    let model = zigzag(&zig(1.0, 120.0, true), &ZigZagOptions::default()).unwrap();
    let table = ComparisonTable::new(&z.measures(), Some(&model.measures()), &c, &c);
    let text = table.to_string();
    let row = text
        .lines()
        .find(|l| l.starts_with("first overshoot angle"))
        .unwrap();
    assert!(
        row.contains("5.000") && row.contains("<= 10.00 (MSC.137(76) 5.3.3.1)"),
        "{text}"
    );
    assert!(
        text.lines()
            .any(|l| l.starts_with("distance to the execute heading") && l.contains("(fail)")),
        "{text}"
    );
    let md = table.to_markdown();
    assert!(
        md.starts_with("| measure | unit | measured | identified model | limit |"),
        "{md}"
    );
}

#[test]
fn a_20_20_zigzag_is_checked_against_25_deg() {
    let opts = ZigZagOptions {
        rudder_angle: Some(20f64.to_radians()),
        heading_angle: Some(10f64.to_radians()),
        ..Default::default()
    };
    let z = zigzag(&zig(1.0, 120.0, true), &opts).unwrap();
    assert!(zigzag_checks(&z, &Ship::new(100.0, 5.0).unwrap()).is_empty());
}
