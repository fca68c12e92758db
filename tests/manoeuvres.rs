//! Manoeuvre measures against hand-computed values on constructed tracks.

use hydroid::dynamics::manoeuvre::imo::{turning_checks, zigzag_checks};
use hydroid::dynamics::manoeuvre::{
    measure_history, turning_circle, zigzag, AngleSource, ComparisonTable, Criterion, History,
    Measure, Nominal, Ship, Side, TurningOptions, Verdict, ZigZagOptions,
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
            ..Default::default()
        },
    )
    .unwrap();
    close(&c.tactical_diameter, 2.0 * R, 2e-3);
    let e = turning_circle(
        &h,
        &TurningOptions {
            execute_time: Some(-1.0),
            ..Default::default()
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

/// How a zig-zag log of [`zig_log`] is written: the rudder angle (deg; None: no rudder
/// column), how late the rudder is reversed after each nominal 10 deg crossing (s), the
/// approach rudder trim before the first execute (deg), and the step the heading is printed
/// to (deg; 0: exactly).
#[derive(Clone, Copy)]
struct Log {
    rudder: Option<f64>,
    late: f64,
    trim: f64,
    step: f64,
}

const EXACT: Log = Log {
    rudder: Some(10.0),
    late: 0.0,
    trim: 0.0,
    step: 0.0,
};

fn zig(side: f64, until: f64, with_rudder: bool) -> History {
    let rudder = with_rudder.then_some(10.0);
    zig_log(side, until, Log { rudder, ..EXACT })
}

fn zig_log(side: f64, until: f64, log: Log) -> History {
    let w = 2.0 * PI / PERIOD;
    let e = (10.0 / A).asin() / w; // time from T0 to the second execute
    let n = (until / ZDT) as usize + 1;
    let delta = log.rudder.unwrap_or(0.0);
    let (mut t, mut psi, mut d, mut x, mut y) = (vec![], vec![], vec![], vec![], vec![]);
    for i in 0..n {
        let ti = i as f64 * ZDT;
        let phase = ti - T0;
        let change = if phase > 0.0 {
            A * (w * phase).sin()
        } else {
            0.0
        };
        // +delta until the second execute, -delta until the third, +delta until the fourth ...
        // each reversal `late` s after the heading crosses 10 deg
        let half = PERIOD / 2.0;
        let k = ((phase - e - log.late) / half).floor();
        let rudder = if phase <= 1e-9 {
            log.trim
        } else if phase < e + log.late {
            delta
        } else if k as i64 % 2 == 0 {
            -delta
        } else {
            delta
        };
        let printed = if log.step > 0.0 {
            (side * change / log.step).round() * log.step
        } else {
            side * change
        };
        t.push(ti);
        psi.push(printed.to_radians());
        d.push((side * rudder).to_radians());
        x.push(U * ti);
        y.push(0.0);
    }
    let h = History::new(t, psi).unwrap().with_track(x, y).unwrap();
    if log.rudder.is_some() {
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
    assert!(matches!(
        z.rudder_angle_from,
        Some(AngleSource::Inferred { .. })
    ));
    assert!(matches!(z.heading_angle_from, AngleSource::Inferred { .. }));
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

// A turn as a ship sails it, with a pull-out after it.
const R_S: f64 = 0.02; // steady yaw rate, rad/s
const U_S: f64 = 1.2; // steady speed, m/s
const TAU: f64 = 15.0; // time constant of the transients, s

/// After the execute at T0 the yaw rate rises to R_S and the speed falls from U to U_S, both
/// as 1 - exp(-(t - T0) / TAU); the rudder (35 deg) is held until the heading has changed
/// `hold` (rad), then put back to zero (a pull-out): the yaw rate decays and the speed
/// recovers with the same time constant for `after` s. Integrated in 0.01 s steps (midpoint),
/// sampled every DT.
fn turn_with_pull_out(hold: f64, after: f64) -> History {
    let h = 0.01;
    let every = (DT / h).round() as usize;
    let (mut psi, mut x, mut y) = (0.0f64, 0.0f64, 0.0f64);
    let mut released: Option<(f64, f64, f64)> = None; // time, yaw rate and speed then
    let rate_speed = |t: f64, released: Option<(f64, f64, f64)>| -> (f64, f64) {
        match released {
            _ if t <= T0 => (0.0, U),
            None => {
                let f = (-(t - T0) / TAU).exp();
                (R_S * (1.0 - f), U_S + (U - U_S) * f)
            }
            Some((th, rh, uh)) => {
                let f = (-(t - th) / TAU).exp();
                (rh * f, U - (U - uh) * f)
            }
        }
    };
    let mut cols: [Vec<f64>; 7] = Default::default();
    let mut k = 0usize;
    loop {
        let t = k as f64 * h;
        if k.is_multiple_of(every) {
            let (_, speed) = rate_speed(t, released);
            let rudder = if t > T0 && released.is_none() {
                35f64.to_radians()
            } else {
                0.0
            };
            for (c, v) in cols.iter_mut().zip([t, psi, x, y, speed, 0.0, rudder]) {
                c.push(v);
            }
        }
        if released.is_some_and(|(th, _, _)| t > th + after) {
            break;
        }
        let (r, speed) = rate_speed(t + 0.5 * h, released);
        let mid = psi + 0.5 * h * r;
        psi += h * r;
        x += h * speed * mid.cos();
        y += h * speed * mid.sin();
        k += 1;
        if released.is_none() && psi >= hold {
            let (r, speed) = rate_speed(k as f64 * h, None);
            released = Some((k as f64 * h, r, speed));
        }
    }
    let [t, psi, x, y, u, v, d] = cols;
    History::new(t, psi)
        .and_then(|hy| hy.with_track(x, y))
        .and_then(|hy| hy.with_velocity(u, v))
        .and_then(|hy| hy.with_rudder(d))
        .unwrap()
}

/// The steady turning diameter and speed are read in the steady part of the turn with the
/// rudder held, not over the pull-out after it: 2 U_S / R_S and U_S / U.
#[test]
fn a_turn_with_a_pull_out_is_steady_only_while_the_rudder_is_held() {
    let h = turn_with_pull_out(3.0 * PI, 300.0);
    let c = turning_circle(&h, &TurningOptions::default()).unwrap();
    let held = c.rudder_changed_at.expect("the rudder is put back");
    assert!(
        (c.max_heading_change.to_degrees() - 540.0).abs() < 1.0,
        "{}",
        c.max_heading_change.to_degrees()
    );
    // steady once the transients (time constant TAU) have died down to a few per cent
    assert!(
        value(&c.steady_from) > T0 + 3.0 * TAU,
        "{:?}",
        c.steady_from
    );
    assert!(value(&c.steady_from) < held);
    close(&c.steady_diameter, 2.0 * U_S / R_S, 0.01 * 2.0 * U_S / R_S);
    close(&c.steady_yaw_rate, R_S, 0.01 * R_S);
    close(&c.steady_speed, U_S, 0.01 * U_S);
    close(&c.speed_ratio, U_S / U, 0.01 * U_S / U);
    close(&c.rudder_angle, 35f64.to_radians(), 1e-12);
    close(&c.nominal_rudder_angle, 35f64.to_radians(), 1e-12);
    assert!(
        c.hold_text().starts_with("rudder held until t = "),
        "{}",
        c.hold_text()
    );
}

/// A rudder put back before the turn is steady: the measures past it are missing, each
/// with the reason, and nothing is read from the pull-out.
#[test]
fn a_turn_pulled_out_early_has_no_steady_part_and_says_why() {
    let h = turn_with_pull_out(120f64.to_radians(), 200.0);
    let c = turning_circle(&h, &TurningOptions::default()).unwrap();
    assert!(c.advance.value().is_some());
    let Measure::Missing(r) = &c.tactical_diameter else {
        panic!("{:?}", c.tactical_diameter)
    };
    assert!(
        r.contains("with the rudder held (it is changed at t = "),
        "{r}"
    );
    for m in [&c.steady_diameter, &c.steady_speed, &c.speed_ratio] {
        let Measure::Missing(r) = m else {
            panic!("{m:?}")
        };
        assert!(
            r.contains("with the rudder held") && r.contains("needs"),
            "{r}"
        );
    }
}

/// A 20/10 zig-zag whose rudder is reversed 0.3 s after each 10 deg crossing (at 10.5 deg of
/// heading change), from an approach rudder trimmed 1 deg the other way: at its nominal
/// angles, inferred or given, the overshoots are the heading change beyond 10 deg (5 deg),
/// and the times run from the nominal crossings.
#[test]
fn a_late_reversal_is_measured_at_the_nominal_angles_inferred_or_given() {
    let log = Log {
        rudder: Some(20.0),
        late: 0.3,
        trim: -1.0,
        step: 0.0,
    };
    let e = (10.0 / A).asin() / (2.0 * PI / PERIOD);
    let given = ZigZagOptions {
        rudder_angle: Some(20f64.to_radians()),
        heading_angle: Some(10f64.to_radians()),
        ..Default::default()
    };
    for side in [1.0, -1.0] {
        let h = zig_log(side, 120.0, log);
        let inferred = zigzag(&h, &ZigZagOptions::default()).unwrap();
        let given = zigzag(&h, &given).unwrap();
        for z in [&inferred, &given] {
            close(&z.rudder_angle.map(f64::to_degrees), 20.0, 1e-9);
            assert!((z.heading_angle.to_degrees() - 10.0).abs() < 1e-9);
            close(&z.first_overshoot.map(f64::to_degrees), 5.0, 1e-5);
            close(&z.second_overshoot.map(f64::to_degrees), 5.0, 1e-5);
            close(&z.initial_turning_time, e, 1e-4);
            close(&z.time_to_check_yaw, PERIOD / 4.0 - e, 1e-4);
        }
        assert_eq!(
            inferred.nominal_text(),
            "rudder angle nominal 20 deg, inferred from the rudder held at 20.0 deg; \
             check angle nominal 10 deg, inferred from the reversal at 10.5 deg"
        );
        assert_eq!(
            given.nominal_text(),
            "rudder angle nominal 20 deg, given; check angle nominal 10 deg, given"
        );
    }
    // a 20/10 is judged by no IMO criterion, and the table says so
    let h = zig_log(-1.0, 120.0, log);
    let m = measure_history(&h, 100.0, Some(1.0), Nominal::default()).unwrap();
    assert!(m.checks.is_empty());
    let table =
        ComparisonTable::new(&m.measures(), None, &m.checks, &[]).with_notes(m.notes("measured"));
    let text = table.to_string();
    assert!(
        text.contains("IMO criteria (measured): no IMO criterion applies to a 20/10 zig-zag"),
        "{text}"
    );
    assert!(text.contains("check angle (nominal)"), "{text}");
    // given as a 10/10 it is judged as one; without the scale, the overshoot limits say why not
    let ten = Nominal {
        rudder: Some(10f64.to_radians()),
        check: Some(10f64.to_radians()),
    };
    let m = measure_history(&h, 100.0, None, ten).unwrap();
    assert_eq!(m.checks.len(), 1, "{:?}", m.checks);
    assert_eq!(m.not_judged.len(), 2, "{:?}", m.not_judged);
    assert!(m.not_judged[0].contains("give the scale ratio (vehicle.scale"));
}

/// A heading printed to 0.5 deg has a plateau of about 2.3 s at each peak: the peak is the
/// vertex of the parabola fitted across the plateau, not its first sample (1.2 s early). The
/// second execute is read on the printed heading too (up to 0.25 deg / 1.75 deg/s = 0.14 s
/// early), hence 0.3 s on the time to check yaw.
#[test]
fn the_peak_of_a_quantised_heading_is_found_across_its_plateau() {
    let e = (10.0 / A).asin() / (2.0 * PI / PERIOD);
    for side in [1.0, -1.0] {
        let h = zig_log(side, 120.0, Log { step: 0.5, ..EXACT });
        let z = zigzag(&h, &ZigZagOptions::default()).unwrap();
        close(&z.first_overshoot.map(f64::to_degrees), 5.0, 0.1);
        close(&z.second_overshoot.map(f64::to_degrees), 5.0, 0.1);
        close(&z.time_to_check_yaw, PERIOD / 4.0 - e, 0.3);
    }
}
