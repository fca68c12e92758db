//! The ship models against independent properties: the straight-run speed where thrust equals
//! resistance, the turning direction of a positive rudder, and the KVLCC2 35 deg turning
//! circle against the published free-running model tests.

use hydroid::dynamics::sim::{simulate, InputSeries};
use hydroid::model::models::mmg3::{self, Mmg3};
use hydroid::model::models::Model;

/// A run of `model` from `x0` with constant inputs, sampled every `dt` for `duration`.
fn run<M: Model>(
    model: &M,
    c: &[f64],
    x0: &[f64],
    inputs: &[f64],
    duration: f64,
    dt: f64,
) -> Vec<Vec<f64>> {
    let times: Vec<f64> = (0..=(duration / dt).round() as usize)
        .map(|k| k as f64 * dt)
        .collect();
    simulate(model, c, x0, &InputSeries::constant(inputs), &times, 4).expect("simulates")
}

/// Advance (x at 90 deg heading change) and tactical diameter (|y| at 180 deg) of a turn
/// starting at the origin heading north, linearly interpolated between samples.
fn advance_and_tactical_diameter(xs: &[Vec<f64>]) -> (f64, f64) {
    let at = |heading: f64, k: usize| -> f64 {
        let i = xs
            .iter()
            .position(|x| x[5].abs() >= heading)
            .expect("the turn reaches the heading");
        let (a, b) = (&xs[i - 1], &xs[i]);
        let f = (heading - a[5].abs()) / (b[5].abs() - a[5].abs());
        a[k] + f * (b[k] - a[k])
    };
    let half_pi = std::f64::consts::FRAC_PI_2;
    (at(half_pi, 3), at(2.0 * half_pi, 4).abs())
}

fn kvlcc2() -> (Mmg3, Vec<f64>) {
    let m = Mmg3::build(&mmg3::kvlcc2_model_vehicle()).expect("KVLCC2");
    let c = m.coefficient_vector(mmg3::KVLCC2);
    (m, c)
}

/// The KVLCC2 model's 35 deg turning circle (rudder put over at once from the approach speed)
/// against the free-running model tests Yasukawa & Yoshimura (2015) compare with: advance about
/// 3.1 L and tactical diameter about 3.2 L to either side. Tolerance 0.35 L (about 11 %): the
/// rudder goes over at once here instead of at the test's rate (about 0.2 L less advance), the
/// propeller turns at the resistance balance rather than the model's self-propulsion point,
/// and free-running tests of KVLCC2 in different basins scatter by about 5 %.
#[test]
fn kvlcc2_35_deg_turn_is_near_the_free_running_tests() {
    let (m, c) = kvlcc2();
    let x0 = [mmg3::KVLCC2_SPEED, 0.0, 0.0, 0.0, 0.0, 0.0];
    for delta in [35.0f64, -35.0] {
        let xs = run(
            &m,
            &c,
            &x0,
            &[delta.to_radians(), mmg3::KVLCC2_RPS],
            120.0,
            0.05,
        );
        let (ad, td) = advance_and_tactical_diameter(&xs);
        let (ad, td) = (ad / m.ship.lpp, td / m.ship.lpp);
        // measured here: 2.92 L and 3.11 L (35 deg), 2.93 L and 3.10 L (-35 deg)
        assert!((ad - 3.1).abs() < 0.35, "delta {delta}: advance {ad:.3} L");
        assert!(
            (td - 3.2).abs() < 0.35,
            "delta {delta}: tactical diameter {td:.3} L"
        );
    }
}

#[test]
fn straight_run_settles_where_thrust_equals_resistance() {
    // hand-computed balance (docs/models/ships.md): R = 0.5 rho L d U^2 R'_0 = 49.24 N at
    // U = 1.179 m/s is met by the thrust (1 - t_P) rho n^2 D^4 K_T(J) at n = 11.847 rps
    let (m, c) = kvlcc2();
    let xs = run(
        &m,
        &c,
        &[0.8, 0.0, 0.0, 0.0, 0.0, 0.0],
        &[0.0, mmg3::KVLCC2_RPS],
        600.0,
        0.5,
    );
    let last = xs.last().expect("samples");
    assert!(
        (last[0] - mmg3::KVLCC2_SPEED).abs() < 2e-3,
        "steady u = {}",
        last[0]
    );
    assert!(last[1].abs() < 1e-9 && last[2].abs() < 1e-9, "{last:?}");
}

#[test]
fn a_positive_rudder_turns_to_starboard() {
    // Yasukawa & Yoshimura 2015: delta > 0 gives r > 0 (z down: heading increases clockwise)
    let (m, c) = kvlcc2();
    let x0 = [mmg3::KVLCC2_SPEED, 0.0, 0.0, 0.0, 0.0, 0.0];
    for (delta, sign) in [(10f64, 1.0), (-10.0, -1.0)] {
        let xs = run(
            &m,
            &c,
            &x0,
            &[delta.to_radians(), mmg3::KVLCC2_RPS],
            20.0,
            0.1,
        );
        let last = xs.last().expect("samples");
        assert!(
            last[2] * sign > 0.0 && last[4] * sign > 0.0,
            "delta {delta}: {last:?}"
        );
    }
}
