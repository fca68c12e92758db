//! A user's candidates (`--candidates FILE`) checked as a configuration is: every unknown key
//! (with the closest known one), every value outside the magnitude a run can have (the
//! configuration's limits, [`crate::config::motion_limits`]), a sampling that does not
//! resolve the motion, a run of more samples than a candidate may make, a key its kind does
//! not use, a noise channel that is not a quantity; all listed at once with the file, the line
//! and the candidate, before any planning. What needs the identified run (the default speed,
//! duration and sampling of a manoeuvre, the channels it measures) is checked by
//! [`against`] before the candidates are evaluated.

use super::candidate::{Candidate, Kind};
use crate::base::error::{ConfigProblem, Error, Result};
use crate::base::numfmt::short;
use crate::base::quantity::Quantity;
use crate::config::motion_limits as limits;
use crate::config::Problems;
use serde::Deserialize;
use std::path::Path;

/// Most samples a candidate may make (duration / dt): twenty times the longest bundled
/// manoeuvre, about 100 MB of states and a minute of the filter's covariance recursion.
pub const MAX_SAMPLES: f64 = 200_000.0;
/// Longest candidate run, s (a day: longer than any CFD run, basin run or sea trial).
pub const MAX_DURATION: f64 = 86_400.0;
/// Most candidates in a file.
pub const MAX_CANDIDATES: usize = 1000;
/// Longest candidate name, characters (a table cell).
pub const MAX_NAME: usize = 200;
/// Most candidates `--verify` may check.
pub const MAX_VERIFY: usize = 20;
/// Most replicas `--verify K --replicas N` may identify in all (K N): about ten minutes of
/// manoeuvre replicas of the KVLCC2 on two cores (release build).
pub const MAX_REPLICAS: usize = 10_000;
/// Largest rudder or planes angle of a candidate manoeuvre, rad: the helm's of `hydroid
/// simulate` (57 deg).
const HELM_LIMIT: f64 = 1.0;

/// A candidates file: `[[candidate]]` tables.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    candidate: Vec<Candidate>,
}

/// Reads a user's candidates from a TOML file of `[[candidate]]` tables; every problem is
/// listed with the file, the line, the key and the candidate's name.
pub fn read(path: &Path) -> Result<Vec<Candidate>> {
    let text = crate::config::read(path)?;
    let mut p = Problems::new(path, &text);
    let file: Option<File> = crate::config::read_collecting(&mut p, &text, &[]);
    let Some(file) = file.filter(|_| p.is_empty()) else {
        return Err(refusal(path, p));
    };
    if file.candidate.is_empty() {
        p.add("candidate", "no [[candidate]] tables");
    }
    if file.candidate.len() > MAX_CANDIDATES {
        p.add(
            "candidate",
            format!(
                "{} candidates: at most {MAX_CANDIDATES} in a file",
                file.candidate.len()
            ),
        );
    }
    for (k, c) in file.candidate.iter().enumerate() {
        check(c, &format!("candidate[{k}]"), &mut p);
    }
    for (j, c) in file.candidate.iter().enumerate() {
        if let Some(i) = file.candidate[..j].iter().position(|o| o.name == c.name) {
            p.add(
                &format!("candidate[{j}].name"),
                format!(
                    "'{}' names candidates {} and {}: each once, for the table",
                    c.name,
                    i + 1,
                    j + 1
                ),
            );
        }
    }
    if p.is_empty() {
        Ok(file.candidate)
    } else {
        Err(refusal(path, p))
    }
}

/// The problems of a candidates file as one usage error (exit status 2).
fn refusal(path: &Path, p: Problems) -> Error {
    let list: Vec<ConfigProblem> = p.in_file_order();
    let mut s = format!(
        "{} problem{} in the candidates file {}:",
        list.len(),
        if list.len() == 1 { "" } else { "s" },
        path.display()
    );
    for problem in &list {
        s.push_str("\n  - ");
        s.push_str(&problem.to_string());
    }
    Error::Usage(s)
}

/// The keys a candidate of `kind` reads beyond the common ones (name, kind, speed,
/// duration_s, dt_s, noise, cost).
fn used(kind: Kind) -> &'static [&'static str] {
    match kind {
        Kind::Static => &["drift_deg", "yaw_rate_deg_s", "rudder_deg"],
        Kind::PmmSway | Kind::PmmYaw => &["amplitude", "frequency_hz", "rudder_deg"],
        Kind::Turn => &["rudder_deg", "v0", "r0_deg_s"],
        Kind::Zigzag => &["rudder_deg", "heading_deg", "v0", "r0_deg_s"],
        Kind::Free => &["v0", "r0_deg_s"],
        Kind::ZigzagVertical => &["planes_deg", "pitch_deg", "v0", "r0_deg_s"],
        Kind::Helix => &["rudder_deg", "planes_deg", "v0", "r0_deg_s"],
    }
}

/// The kind's name as a candidates file writes it.
fn kind_name(kind: Kind) -> String {
    serde_json::to_value(kind)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default()
}

/// The candidate's parameters that are set (non-zero), by key.
fn given(c: &Candidate) -> [(&'static str, f64); 10] {
    [
        ("drift_deg", c.drift_deg),
        ("yaw_rate_deg_s", c.yaw_rate_deg_s),
        ("rudder_deg", c.rudder_deg),
        ("heading_deg", c.heading_deg),
        ("planes_deg", c.planes_deg),
        ("pitch_deg", c.pitch_deg),
        ("amplitude", c.amplitude),
        ("frequency_hz", c.frequency_hz),
        ("v0", c.v0),
        ("r0_deg_s", c.r0_deg_s),
    ]
}

/// Every problem of candidate `c` at `key` that needs no model.
fn check(c: &Candidate, key: &str, p: &mut Problems) {
    let name = &c.name;
    let mut add = |k: &str, m: String| p.add(&format!("{key}.{k}"), format!("'{name}': {m}"));
    if name.trim().is_empty() || name.chars().count() > MAX_NAME {
        add(
            "name",
            format!("a name of 1 to {MAX_NAME} characters for the table"),
        );
    }
    let kind = kind_name(c.kind);
    for (k, v) in given(c) {
        if !v.is_finite() {
            add(k, format!("must be a finite number, got {v}"));
        } else if v != 0.0 && !used(c.kind).contains(&k) {
            add(
                k,
                format!(
                    "is not used by a {kind} candidate (it reads {})",
                    used(c.kind).join(", ")
                ),
            );
        }
    }
    if !(c.cost.is_finite() && c.cost > 0.0) {
        add("cost", format!("cost must be positive, not {}", c.cost));
    }
    if let Some(m) = c.speed.and_then(limits::speed) {
        add("speed", m);
    }
    timing(c, &mut add);
    angles(c, &mut add);
    required(c, &kind, &mut add);
    noise(c, &mut add);
}

/// Duration, sample interval, their number of samples, and a PMM's sampling of its motion.
fn timing(c: &Candidate, add: &mut impl FnMut(&str, String)) {
    let positive = |v: Option<f64>| v.is_none_or(|v| v.is_finite() && v > 0.0);
    if !positive(c.duration_s) || !positive(c.dt_s) {
        let which = if positive(c.duration_s) {
            "dt_s"
        } else {
            "duration_s"
        };
        add(which, "duration_s and dt_s must be positive".into());
        return;
    }
    if let Some(d) = c.duration_s.filter(|d| *d > MAX_DURATION) {
        add(
            "duration_s",
            format!(
                "{} s is longer than any candidate run (at most {} s, a day): a duration in \
                 ms, or a typing mistake?",
                short(d),
                short(MAX_DURATION)
            ),
        );
        return;
    }
    // a captive run's defaults are known; a manoeuvre's are the first fitted run's
    let (duration, dt) = match c.kind.is_captive() {
        true => (
            Some(super::captive::duration(c)),
            Some(c.dt_s.unwrap_or(super::captive::DT)),
        ),
        false => (c.duration_s, c.dt_s),
    };
    if let (Some(d), Some(dt)) = (duration, dt) {
        if dt > d {
            add(
                "dt_s",
                format!(
                    "the sample interval {} s is longer than the run ({} s)",
                    short(dt),
                    short(d)
                ),
            );
        } else if let Some(m) = limits::sample_count(d, dt, MAX_SAMPLES, "a candidate may make") {
            add("dt_s", m);
        }
    }
    let pmm = c.kind.is_pmm();
    if let (true, Some(d), Some(dt)) = (pmm && c.frequency_hz > 0.0, duration, dt) {
        let f = c.frequency_hz;
        if let Some(m) = limits::sampling(f, dt) {
            add("frequency_hz", m);
        } else if let Some(m) =
            limits::whole_periods(f, d, crate::stages::captive::harmonic::MIN_PERIODS)
        {
            add("duration_s", m);
        }
    }
}

/// Angles and rates within the magnitude any such value can have; a manoeuvre's rudder and
/// planes within the helm's limit; zig-zag changes within the reversing range.
fn angles(c: &Candidate, add: &mut impl FnMut(&str, String)) {
    let deg = |v: f64| format!("{} deg", short(v));
    let deg_s = |v: f64| format!("{} deg/s", short(v));
    let mut bounded = |k: &str, q: Quantity, v: f64, shown: String| {
        if let Some(m) = limits::magnitude(q, v, &shown) {
            add(k, m);
        }
    };
    bounded(
        "drift_deg",
        Quantity::Drift,
        c.drift_deg.to_radians(),
        deg(c.drift_deg),
    );
    let surfaces = [
        ("rudder_deg", Quantity::Rudder, c.rudder_deg),
        ("planes_deg", Quantity::SternPlanes, c.planes_deg),
    ];
    for (k, q, v) in surfaces {
        bounded(k, q, v.to_radians(), deg(v));
    }
    for (k, v) in [
        ("yaw_rate_deg_s", c.yaw_rate_deg_s),
        ("r0_deg_s", c.r0_deg_s),
    ] {
        bounded(k, Quantity::R, v.to_radians(), deg_s(v));
    }
    bounded("v0", Quantity::V, c.v0, format!("{} m/s", short(c.v0)));
    match c.kind {
        Kind::PmmSway => bounded(
            "amplitude",
            Quantity::V,
            c.amplitude,
            format!("{} m/s", short(c.amplitude)),
        ),
        Kind::PmmYaw => bounded(
            "amplitude",
            Quantity::R,
            c.amplitude.to_radians(),
            deg_s(c.amplitude),
        ),
        _ => {}
    }
    if !c.kind.is_captive() {
        for (k, _, v) in surfaces {
            if v.is_finite() && v.to_radians().abs() > HELM_LIMIT && v.abs() <= 90.0 {
                add(
                    k,
                    format!(
                        "{} is beyond the helm's 57 deg either side (as `hydroid simulate`'s)",
                        deg(v)
                    ),
                );
            }
        }
    }
    for (k, v, largest) in [
        ("heading_deg", c.heading_deg, 180.0),
        ("pitch_deg", c.pitch_deg, 90.0),
    ] {
        if v.is_finite() && v.abs() >= largest {
            add(
                k,
                format!(
                    "{} is beyond the reversing change of a zig-zag (below {largest} deg)",
                    deg(v)
                ),
            );
        }
    }
}

/// What a kind needs: a PMM its amplitude and frequency, a turn its rudder ...
fn required(c: &Candidate, kind: &str, add: &mut impl FnMut(&str, String)) {
    let (k, need) = match c.kind {
        Kind::PmmSway | Kind::PmmYaw if c.amplitude == 0.0 || c.frequency_hz <= 0.0 => (
            if c.amplitude == 0.0 {
                "amplitude"
            } else {
                "frequency_hz"
            },
            "a PMM run needs a non-zero amplitude and a positive frequency_hz",
        ),
        Kind::Turn if c.rudder_deg == 0.0 => ("rudder_deg", "a turn needs rudder_deg"),
        Kind::Zigzag if c.rudder_deg == 0.0 || c.heading_deg <= 0.0 => (
            "heading_deg",
            "a zig-zag needs rudder_deg and a positive heading_deg",
        ),
        Kind::ZigzagVertical if c.planes_deg == 0.0 || c.pitch_deg <= 0.0 => (
            "pitch_deg",
            "a vertical zig-zag needs planes_deg and a positive pitch_deg",
        ),
        Kind::Helix if c.rudder_deg == 0.0 || c.planes_deg == 0.0 => {
            ("planes_deg", "a helix needs rudder_deg and planes_deg")
        }
        _ => return,
    };
    add(k, format!("{need} (a {kind} candidate)"));
}

/// Each noise channel a quantity (with the closest one for a misspelt key), positive and
/// within its quantity's magnitude.
fn noise(c: &Candidate, add: &mut impl FnMut(&str, String)) {
    for (k, v) in &c.noise {
        let key = format!("noise.{k}");
        let Some(q) = Quantity::from_key(k) else {
            add(
                &key,
                format!(
                    "`{k}` is not a measured channel: fx, fy, mz ... for a captive run, u, v, \
                     r, yaw ... for a manoeuvre{}",
                    crate::base::suggest::did_you_mean(k, Quantity::ALL.iter().map(|q| q.key()))
                ),
            );
            continue;
        };
        // a unit that does not measure the channel's quantity ("0.2 m/s" for a force)
        if let Err(m) = v.expect_dim(q.dim()) {
            add(&key, format!("noise.{k} = {m}"));
            continue;
        }
        let si = v.si;
        if !(si.is_finite() && si > 0.0) {
            add(&key, format!("noise.{k} must be positive, not {}", v.text));
        } else if let Some(m) =
            limits::magnitude(q, si, &format!("{} {}", short(si), q.si_symbol()))
        {
            add(&key, m);
        }
    }
}

/// What a candidate is checked against once the run is identified: the speed, duration and
/// sampling its defaults take, the vehicle's length, and the channels it measures.
#[derive(Debug, Clone)]
pub struct Resolved<'a> {
    /// The first fitted run's initial surge speed, m/s.
    pub speed: f64,
    /// Its sample interval, s (a manoeuvre's default).
    pub dt: f64,
    /// Its duration, s (a manoeuvre's default).
    pub duration: f64,
    /// The vehicle's length, m.
    pub length: f64,
    /// The forces a captive run of the model measures.
    pub forces: &'a [Quantity],
    /// The outputs a manoeuvre measures.
    pub measured: Vec<Quantity>,
    /// The model's name.
    pub model: &'a str,
}

/// The problems of candidate `c` with its defaults resolved: a manoeuvre's samples, a PMM's
/// and a steady condition's motion against the speed and length (r', omega', v_a / U), and
/// noise channels the candidate does not measure.
pub fn against(c: &Candidate, r: &Resolved) -> Vec<String> {
    let mut out = Vec::new();
    let u = c.speed.unwrap_or(r.speed);
    let mut add = |k: &str, m: String| out.push(format!("{k}: {m}"));
    if !c.kind.is_captive() {
        let (d, dt) = (c.duration_s.unwrap_or(r.duration), c.dt_s.unwrap_or(r.dt));
        if let Some(m) = limits::sample_count(d, dt, MAX_SAMPLES, "a candidate may make") {
            add("duration_s", m);
        }
    }
    if u > 0.0 {
        let rate = |k: &str, v: f64, add: &mut dyn FnMut(&str, String)| {
            let shown = format!("{} deg/s", short(v));
            if let Some(m) = limits::rate_prime(v.to_radians(), r.length, u, &shown) {
                add(k, m);
            }
        };
        match c.kind {
            Kind::PmmSway => {
                if let Some(m) = limits::translation_amplitude(c.amplitude, u) {
                    add("amplitude", m);
                }
            }
            Kind::PmmYaw => rate("amplitude", c.amplitude, &mut add),
            Kind::Static => rate("yaw_rate_deg_s", c.yaw_rate_deg_s, &mut add),
            _ => rate("r0_deg_s", c.r0_deg_s, &mut add),
        }
        if c.kind == Kind::PmmSway || c.kind == Kind::PmmYaw {
            if let Some(m) = limits::omega_prime(c.frequency_hz, r.length, u) {
                add("frequency_hz", m);
            }
        }
    }
    let channels: Vec<&str> = if c.kind.is_captive() {
        r.forces.iter().map(|q| q.key()).collect()
    } else {
        r.measured.iter().map(|q| q.key()).collect()
    };
    for k in c.noise.keys() {
        if !channels.contains(&k.as_str()) {
            add(
                &format!("noise.{k}"),
                format!(
                    "a {} candidate of the {} model does not measure {k}: it measures {}{}",
                    kind_name(c.kind),
                    r.model,
                    channels.join(", "),
                    crate::base::suggest::did_you_mean(k, channels.iter().copied())
                ),
            );
        }
    }
    out
}

/// Refuses `--target` names given twice or empty, and `--verify K --replicas N` beyond
/// [`MAX_VERIFY`] candidates or [`MAX_REPLICAS`] replicas in all.
pub fn check_settings(targets: &[String], verify: usize, replicas: usize) -> Result<()> {
    for (j, t) in targets.iter().enumerate() {
        if t.trim().is_empty() {
            return Err(Error::Usage(
                "--target: an empty name (a comma too many?): name coefficients, e.g. \
                 --target Nrd,Yvd"
                    .into(),
            ));
        }
        if targets[..j].contains(t) {
            return Err(Error::Usage(format!(
                "--target: {t} is named twice: name each coefficient once (a target given \
                 twice makes every candidate's D score -inf)"
            )));
        }
    }
    if verify > MAX_VERIFY {
        return Err(Error::Usage(format!(
            "--verify {verify}: at most {MAX_VERIFY} candidates are verified (the ranked \
             table's top)"
        )));
    }
    if verify * replicas > MAX_REPLICAS {
        return Err(Error::Usage(format!(
            "--verify {verify} --replicas {replicas} asks for {} replicas, each identified \
             again: at most {MAX_REPLICAS} in all (fewer replicas, or fewer candidates verified)",
            verify * replicas
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problems(text: &str) -> String {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.toml");
        std::fs::write(&path, text).unwrap();
        read(&path)
            .map(|_| String::new())
            .unwrap_or_else(|e| e.to_string())
    }

    #[test]
    fn a_bad_candidate_file_names_the_line() {
        let e = problems("[[candidate]]\nname = \"a\"\nkind = \"pmm_roll\"\n");
        assert!(e.contains(":3") && e.contains("candidate[0].kind"), "{e}");
        let e = problems("[[candidate]]\nname = \"a\"\nkind = \"pmm_yaw\"\n");
        assert!(e.contains("amplitude"), "{e}");
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.toml");
        std::fs::write(
            &path,
            "[[candidate]]\nname = \"a\"\nkind = \"static\"\ndrift_deg = 5\ncost = 3\n",
        )
        .unwrap();
        let c = read(&path).unwrap();
        assert_eq!((c[0].drift_deg, c[0].cost), (5.0, 3.0));
    }

    #[test]
    fn absurd_values_are_refused_with_the_key_and_the_unit() {
        let one = |body: &str| problems(&format!("[[candidate]]\nname = \"x\"\n{body}\n"));
        let e = one("kind = \"static\"\nspeed = 1e6");
        assert!(e.contains("candidate[0].speed") && e.contains("m/s"), "{e}");
        let e = one("kind = \"pmm_yaw\"\namplitude = 10.0\nfrequency_hz = 1000.0\ndt_s = 0.01");
        assert!(e.contains("Nyquist") && e.contains("frequency_hz"), "{e}");
        let e = one("kind = \"turn\"\nrudder_deg = 95.0");
        assert!(e.contains("rudder_deg") && e.contains("95 deg"), "{e}");
        let e = one("kind = \"static\"\ndrift_deg = 5.0\nnoise = { fz = 1.0, mzz = 0.1 }");
        assert!(
            e.contains("noise.mzz") && e.contains("did you mean 'mz'"),
            "{e}"
        );
        let e = one("kind = \"static\"\ndt_s = 1e-6");
        assert!(e.contains("1e7 samples"), "{e}");
        let e = one("kind = \"turn\"\nrudder_deg = 10.0\nduration_s = 1e9");
        assert!(e.contains("duration_s") && e.contains("1e9 s"), "{e}");
        let e = one("kind = \"static\"\ndrift_deg = 5.0\nfrequency_hz = 2.0");
        assert!(e.contains("not used by a static candidate"), "{e}");
        let e = one("kind = \"static\"\nspeeed = 2.0");
        assert!(e.contains("did you mean"), "{e}");
    }

    #[test]
    fn targets_and_verification_are_bounded() {
        let t = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let e = check_settings(&t(&["Nrd", "Nrd"]), 0, 50).unwrap_err();
        assert!(e.to_string().contains("Nrd is named twice"), "{e}");
        assert!(check_settings(&t(&["Nrd", ""]), 0, 50).is_err());
        let e = check_settings(&[], 20, 10_000).unwrap_err().to_string();
        assert!(e.contains("200000 replicas") && e.contains("10000"), "{e}");
        assert!(check_settings(&t(&["Nrd"]), 3, 50).is_ok());
    }
}
