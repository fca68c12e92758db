use super::*;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::collections::BTreeMap;

fn heading_rate(rec: &Record) -> Option<Finding> {
    rates::all(rec)
        .into_iter()
        .find(|(q, _)| *q == Quantity::R)
        .map(|(_, f)| f)
}

/// A slow steady turn (the NPS AUV helix: 1 deg/s) sampled at 100 Hz with a heading
/// noise of 0.05 deg and a yaw-rate noise of 0.1 deg/s; `rate_scale` mislabels the rate.
fn slow_turn(rate_scale: f64) -> Record {
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    let psi_noise = Normal::new(0.0, 0.05f64.to_radians()).unwrap();
    let r_noise = Normal::new(0.0, 0.1f64.to_radians()).unwrap();
    let k = 6000;
    let rate = -1.0f64.to_radians();
    let mut channels = BTreeMap::new();
    let t: Vec<f64> = (0..k).map(|i| i as f64 * 0.01).collect();
    let psi = t
        .iter()
        .map(|t| rate * t + psi_noise.sample(&mut rng))
        .collect();
    let r = t
        .iter()
        .map(|_| rate_scale * (rate + r_noise.sample(&mut rng)))
        .collect();
    channels.insert(Quantity::Time, t);
    channels.insert(Quantity::Yaw, psi);
    channels.insert(Quantity::R, r);
    Record::from_channels("slow turn", "turn.csv", channels)
}

#[test]
fn a_slow_noisy_turn_is_not_taken_for_a_heading_mistake() {
    // over 5 samples the heading moves 0.05 deg, its noise as much: the windows must grow
    assert_eq!(heading_rate(&slow_turn(1.0)), None);
}

#[test]
fn a_heading_that_does_not_move_beyond_its_noise_is_not_judged() {
    // a vertical zig-zag: the heading holds, r is noise
    let mut still = slow_turn(1.0);
    let n = still.channels[&Quantity::Yaw].len();
    let psi: Vec<f64> = (0..n).map(|k| 1e-3 * ((k * 7919) % 13) as f64).collect();
    still.channels.insert(Quantity::Yaw, psi);
    let r: Vec<f64> = (0..n)
        .map(|k| 2e-3 * ((k * 104729) % 11) as f64 - 0.01)
        .collect();
    still.channels.insert(Quantity::R, r);
    assert_eq!(heading_rate(&still), None);
}

#[test]
fn a_rate_in_degrees_read_as_radians_is_still_named_in_a_slow_turn() {
    // a rate in deg/s read as rad/s: 57 times too large
    let f = heading_rate(&slow_turn(180.0 / std::f64::consts::PI)).expect("a finding");
    assert!(f.blocking, "{f:?}");
    assert!(
        f.warning.meaning.contains("deg/s read as rad/s"),
        "{:?}",
        f.warning
    );
}

/// A planar run: a ship at `speed` m/s on a weave (heading 20 deg sin(2 pi t / 60 s)),
/// sampled every `dt` s for `duration` s, positions with a noise of `pos_noise` m and a
/// printed resolution of `resolution` m, velocities with 1 % of their size as noise, the
/// heading with 0.05 deg and the yaw rate with 0.05 deg/s; a roll that follows the turn.
fn weave(dt: f64, duration: f64, pos_noise: f64, resolution: f64) -> Record {
    let mut rng = rand::rngs::StdRng::seed_from_u64(11);
    let speed = 1.2;
    let n = (duration / dt).round() as usize + 1;
    let w = 2.0 * std::f64::consts::PI / 60.0;
    let amp = 20f64.to_radians();
    let mut noise = |s: f64| {
        if s > 0.0 {
            Normal::new(0.0, s).unwrap().sample(&mut rng)
        } else {
            0.0
        }
    };
    let quantise = |x: f64| {
        if resolution > 0.0 {
            (x / resolution).round() * resolution
        } else {
            x
        }
    };
    let mut ch: BTreeMap<Quantity, Vec<f64>> = BTreeMap::new();
    let (mut x, mut y) = (0.0, 0.0);
    let sway = 0.05;
    for k in 0..n {
        let t = k as f64 * dt;
        let psi = amp * (w * t).sin();
        let r = amp * w * (w * t).cos();
        if k > 0 {
            // exact increments of the path (midpoint heading: the step is short)
            let pm = amp * (w * (t - 0.5 * dt)).sin();
            x += (speed * pm.cos() - sway * pm.sin()) * dt;
            y += (speed * pm.sin() + sway * pm.cos()) * dt;
        }
        let mut push = |q: Quantity, v: f64| ch.entry(q).or_default().push(v);
        push(Quantity::Time, t);
        push(Quantity::X, quantise(x + noise(pos_noise)));
        push(Quantity::Y, quantise(y + noise(pos_noise)));
        push(Quantity::Yaw, psi + noise(0.05f64.to_radians()));
        push(Quantity::R, r + noise(0.05f64.to_radians()));
        push(Quantity::U, speed + noise(0.01 * speed));
        push(Quantity::V, sway + noise(0.01 * speed));
        push(Quantity::Roll, -0.3 * psi);
    }
    Record::from_channels("weave", "weave.csv", ch)
}

fn kinematics(rec: &Record) -> Vec<Finding> {
    let mut out = Vec::new();
    out.extend(travel::speed(rec).map(|f| f.0));
    out.extend(rates::all(rec).into_iter().map(|f| f.1));
    out.extend(travel::track(rec));
    out.extend(travel::sway_over_surge(rec));
    out
}

#[test]
fn valid_runs_at_high_rates_with_noisy_positions_pass_every_kinematic_check() {
    // issue 24 item 9: a CFD history every 2e-4 s with positions printed to 1 mm (they move
    // 0.24 mm a step), and a basin log at 100 Hz with 2 cm of position noise (they move
    // 12 mm a step)
    for (dt, duration, noise, resolution) in [(2e-4, 12.0, 0.0, 1e-3), (0.01, 120.0, 0.02, 0.0)] {
        let rec = weave(dt, duration, noise, resolution);
        let found = kinematics(&rec);
        assert!(found.is_empty(), "dt = {dt}: {found:#?}");
    }
}

#[test]
fn gps_noise_of_metres_on_a_slow_vehicle_is_not_taken_for_a_mix_up() {
    // a sea trial with GNSS positions (1 to 3 m of noise, 10 Hz and 100 Hz) on a vehicle
    // at 1.2 m/s: over the longest windows it travels about as far as the noise, so the
    // track cannot be judged; the check must say nothing rather than blame the frames
    for (dt, noise) in [(0.1, 1.0), (0.01, 2.0), (0.01, 3.0)] {
        let rec = weave(dt, 120.0, noise, 0.0);
        let found = kinematics(&rec);
        assert!(found.is_empty(), "dt = {dt}, noise {noise} m: {found:#?}");
    }
}

#[test]
fn swapped_surge_and_sway_are_named_through_position_noise() {
    // the same mix-up as below, with positions noisy by 0.5 m: still named
    let mut rec = weave(0.05, 240.0, 0.5, 0.0);
    let u = rec.channels.remove(&Quantity::U).unwrap();
    let v = rec.channels.remove(&Quantity::V).unwrap();
    rec.channels.insert(Quantity::U, v);
    rec.channels.insert(Quantity::V, u);
    let f = travel::track(&rec).expect("a finding");
    assert!(f.blocking, "{f:?}");
    assert!(f.warning.meaning.contains("u and v look swapped"), "{f:?}");
}

#[test]
fn positions_in_km_and_time_in_minutes_are_named() {
    let mut km = weave(0.05, 240.0, 0.0, 0.0);
    for q in [Quantity::X, Quantity::Y] {
        km.channels
            .get_mut(&q)
            .unwrap()
            .iter_mut()
            .for_each(|v| *v *= 1e-3);
    }
    let (f, suspect) = travel::speed(&km).expect("a finding");
    assert!(f.blocking && suspect == travel::Suspect::Other, "{f:?}");
    assert!(
        f.warning.meaning.contains("kilometres read as metres"),
        "{f:?}"
    );
    assert!(f.warning.message.contains("9.997e-4 times"), "{f:?}");

    let mut minutes = weave(0.05, 240.0, 0.0, 0.0);
    minutes
        .channels
        .get_mut(&Quantity::Time)
        .unwrap()
        .iter_mut()
        .for_each(|t| *t /= 60.0);
    let (f, suspect) = travel::speed(&minutes).expect("a finding");
    assert!(f.blocking && suspect == travel::Suspect::Time, "{f:?}");
    assert!(
        f.warning.meaning.contains("minutes read as seconds"),
        "{f:?}"
    );
}

#[test]
fn swapped_surge_and_sway_are_named() {
    let mut rec = weave(0.05, 240.0, 0.0, 0.0);
    let u = rec.channels.remove(&Quantity::U).unwrap();
    let v = rec.channels.remove(&Quantity::V).unwrap();
    rec.channels.insert(Quantity::U, v.clone());
    rec.channels.insert(Quantity::V, u.clone());
    let f = travel::track(&rec).expect("a finding");
    assert!(f.blocking, "{f:?}");
    assert!(f.warning.meaning.contains("u and v look swapped"), "{f:?}");
    // without positions, the approach says it (a warning)
    rec.channels.remove(&Quantity::X);
    let f = travel::sway_over_surge(&rec).expect("a finding");
    assert!(
        !f.blocking && f.warning.meaning.contains("swapped"),
        "{f:?}"
    );
}

#[test]
fn a_rate_column_that_holds_an_angle_is_not_the_rate() {
    // the roll angle mapped to r: it follows the turn, but its integral is not the heading
    let mut rec = weave(0.05, 240.0, 0.0, 0.0);
    let roll = rec.channels[&Quantity::Roll].clone();
    rec.channels.insert(Quantity::R, roll);
    rec.channels.remove(&Quantity::Roll);
    let f = heading_rate(&rec).expect("a finding");
    assert!(f.blocking, "{f:?}");
    assert!(f.warning.meaning.contains("is not the yaw rate"), "{f:?}");
    assert!(
        f.warning.meaning.contains("moves like the heading"),
        "{f:?}"
    );
}
