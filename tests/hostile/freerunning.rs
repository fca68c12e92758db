//! Free-running logs as a careless user gives them (issue 48, item 5): the advice must name
//! the right cause. A full-scale log without its Froude scaling (not "rps read as rpm"), a
//! model-scale log for a full-scale vehicle, a heading offset (a rotation of the track: not
//! "u and v swapped"), a wrong heading column (not blamed on r), in several strengths, on
//! the bundled KVLCC2 turns (configs/ship_kvlcc2.toml, `hydroid check`: the checks `run`
//! makes before the filter); the classic mistakes named before stay named; sound variations
//! (columns shuffled, units in the header, a log scaled correctly) stay quiet.

use super::captive::{check_with, edit, Table};
use super::{refused, run_table, Case, Expect};

const CONFIG: &str = "configs/ship_kvlcc2.toml";
const TURN: &str = "cfd_exports/kvlcc2_turn35.csv";
const PORT: &str = "cfd_exports/kvlcc2_turn35_port.csv";
const ZIGZAG: &str = "cfd_exports/kvlcc2_zigzag20.csv";

/// Columns of the KVLCC2 logs: time, x, y, heading, u, v, yaw rate, rudder, propeller.
const TIME: usize = 0;
const X: usize = 1;
const Y: usize = 2;
const HEADING: usize = 3;
const U: usize = 4;
const V: usize = 5;
const R: usize = 6;
const RUDDER: usize = 7;
const PROPELLER: usize = 8;

/// `hydroid check` of the KVLCC2 example with `--set` values.
fn check(name: &str, sets: &[String], expect: Expect) -> Case {
    check_with(name, CONFIG, sets, expect)
}

fn sets(s: &[&str]) -> Vec<String> {
    s.iter().map(|x| x.to_string()).collect()
}

/// A log Froude-scaled from the model to full scale with `lambda` (lengths by lambda, times
/// and speeds by sqrt(lambda), rates and the propeller speed by 1 / sqrt(lambda); ITTC
/// 7.5-02-06-01), its headers unchanged.
fn full_scale(lambda: f64) -> impl Fn(&mut Table) + Send + Sync + 'static {
    move |t: &mut Table| {
        let s = lambda.sqrt();
        t.scale(&[TIME, U, V], s);
        t.scale(&[X, Y], lambda);
        t.scale(&[R, PROPELLER], 1.0 / s);
    }
}

/// The heading turned by `deg` (a rotation of the track against the heading).
fn heading_offset(deg: f64) -> impl Fn(&mut Table) + Send + Sync + 'static {
    move |t: &mut Table| t.map(HEADING, |v, _| v + deg)
}

/// The `--set` values that make the example's vehicle full scale with `lambda`: masses by
/// lambda^3, lengths by lambda, areas by lambda^2, the yaw inertia by lambda^5.
fn full_scale_vehicle(lambda: f64) -> Vec<String> {
    let l = |v: f64| format!("\"{} m\"", v * lambda);
    vec![
        format!("vehicle.mass={}", 3270.0 * lambda.powi(3)),
        format!("vehicle.length={}", 7.0 * lambda),
        format!("vehicle.izz={}", 10218.75 * lambda.powi(5)),
        format!("vehicle.reference_area={}", 3.22 * lambda * lambda),
        format!("vehicle.reference_length={}", 7.0 * lambda),
        format!("vehicle.particulars.draught={}", l(0.46)),
        format!("vehicle.particulars.x_g={}", l(0.25)),
        format!("vehicle.particulars.propeller_diameter={}", l(0.216)),
        format!("vehicle.particulars.propeller_x={}", l(-3.36)),
        format!(
            "vehicle.particulars.rudder_area=\"{} m^2\"",
            0.0539 * lambda * lambda
        ),
        format!("vehicle.particulars.rudder_height={}", l(0.345)),
        format!("vehicle.particulars.rudder_x={}", l(-3.5)),
    ]
}

fn scale_cases() -> Vec<Case> {
    let full = |w: &[&str]| {
        let mut words = vec![
            "full-scale test read for the model-scale vehicle",
            "froude = { lambda =",
            "to = \"model\"",
            "Froude number",
        ];
        words.extend(w);
        refused(&words)
    };
    let mut cases = Vec::new();
    for lambda in [15.0, 25.0, 45.7, 60.0, 100.0] {
        cases.push(
            check(
                &format!("a full-scale log, lambda {lambda}"),
                &[],
                full(&["35 deg starboard turn"]),
            )
            .setup(edit(TURN, full_scale(lambda))),
        );
    }
    cases.extend([
        check(
            "every log at full scale",
            &[],
            full(&["35 deg port turn", "20/20 zig-zag"]),
        )
        .setup(|d: &std::path::Path| {
            for f in [TURN, PORT, ZIGZAG] {
                edit(f, full_scale(45.7))(d);
            }
        }),
        check("the zig-zag at full scale", &[], full(&["20/20 zig-zag"]))
            .setup(edit(ZIGZAG, full_scale(45.7))),
        check(
            "a full-scale log after the wrong advice (rpm read as rps)",
            &sets(&["hekf.runs[0].columns.rpm={column=\"propeller\",unit=\"rps\"}"]),
            full(&[]),
        )
        .setup(edit(TURN, full_scale(45.7))),
        check(
            "a full-scale log with its Froude scaling",
            &sets(&["hekf.runs[0].froude={lambda=45.7,to=\"model\"}"]),
            Expect::Quiet,
        )
        .setup(edit(TURN, full_scale(45.7))),
        check(
            "a full-scale log with the wrong lambda",
            &sets(&["hekf.runs[0].froude={lambda=4.57,to=\"model\"}"]),
            full(&[]),
        )
        .setup(edit(TURN, full_scale(45.7))),
        check(
            "a model log scaled the wrong way",
            &sets(&["hekf.runs[0].froude={lambda=45.7,to=\"full\"}"]),
            full(&[]),
        ),
        check(
            "a model-scale log for the full-scale ship",
            &full_scale_vehicle(45.7),
            refused(&[
                "model test read for the full-scale vehicle",
                "to = \"full\"",
            ]),
        ),
        check(
            "full-scale logs for the full-scale ship",
            &full_scale_vehicle(45.7),
            Expect::Quiet,
        )
        .setup(|d: &std::path::Path| {
            for f in [TURN, PORT, ZIGZAG] {
                edit(f, full_scale(45.7))(d);
            }
        }),
    ]);
    cases
}

fn heading_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for deg in [30.0, 45.0, 90.0, -90.0, 135.0, -150.0] {
        cases.push(
            check(
                &format!("a heading offset by {deg} deg"),
                &[],
                refused(&[
                    "heading seems offset by",
                    "check which axis the heading is measured from",
                ]),
            )
            .setup(edit(TURN, heading_offset(deg))),
        );
    }
    cases.extend([
        check(
            "the zig-zag's heading offset by 90 deg",
            &[],
            refused(&["run '20/20 zig-zag'", "heading seems offset by"]),
        )
        .setup(edit(ZIGZAG, heading_offset(90.0))),
        check(
            "the port turn's heading offset by -60 deg",
            &[],
            refused(&["run '35 deg port turn'", "heading seems offset by"]),
        )
        .setup(edit(PORT, heading_offset(-60.0))),
        check(
            "u and v swapped",
            &sets(&[
                "hekf.runs[0].columns.u=\"v\"",
                "hekf.runs[0].columns.v=\"u\"",
            ]),
            refused(&["u and v look swapped"]),
        ),
        check(
            "u and v swapped in the file",
            &[],
            refused(&["u and v look swapped"]),
        )
        .setup(edit(TURN, |t| {
            for r in &mut t.rows {
                r.swap(U, V);
            }
        })),
        check(
            "yaw mapped to the rudder column",
            &sets(&["hekf.runs[0].columns.yaw={column=\"rudder\",unit=\"deg\"}"]),
            refused(&["column mapped to yaw is not the heading", "integral of r"]),
        ),
        check(
            "yaw mapped to a roll column",
            &sets(&["hekf.runs[0].columns.yaw={column=\"roll\",unit=\"deg\"}"]),
            refused(&["column mapped to yaw is not the heading"]),
        )
        .setup(edit(TURN, |t| {
            t.head.push("\"roll\"".into());
            for (k, r) in t.rows.iter_mut().enumerate() {
                r.push(format!("{:e}", 3.0 * (0.4 * k as f64 * 0.1).sin()));
            }
        })),
        check(
            "yaw mapped to the zig-zag's heading",
            &sets(&["hekf.runs[0].columns.yaw={column=\"other heading\",unit=\"deg\"}"]),
            refused(&["column mapped to yaw is not the heading"]),
        )
        .setup(|d: &std::path::Path| {
            let other = Table::read(&d.join(ZIGZAG));
            edit(TURN, move |t| {
                t.head.push("\"other heading\"".into());
                let last = other.rows.len() - 1;
                for (k, r) in t.rows.iter_mut().enumerate() {
                    r.push(other.rows[k.min(last)][HEADING].clone());
                }
            })(d)
        }),
        check(
            "r mapped to a roll column",
            &sets(&["hekf.runs[0].columns.r={column=\"roll\",unit=\"deg/s\"}"]),
            refused(&["is not the yaw rate"]),
        )
        .setup(edit(TURN, |t| {
            t.head.push("\"roll\"".into());
            for (k, r) in t.rows.iter_mut().enumerate() {
                r.push(format!("{:e}", 3.0 * (0.4 * k as f64 * 0.1).sin()));
            }
        })),
        check(
            "r mapped to the rudder column",
            &sets(&["hekf.runs[0].columns.r={column=\"rudder\",unit=\"deg/s\"}"]),
            refused(&["is not the yaw rate"]),
        ),
    ]);
    cases
}

fn classic_cases() -> Vec<Case> {
    vec![
        check(
            "rudder read as radians",
            &sets(&["hekf.runs[0].columns.rudder={column=\"rudder\",unit=\"rad\"}"]),
            refused(&["degrees read as radians", "unit = \"deg\""]),
        ),
        check(
            "rudder of the other sign",
            &sets(&["hekf.runs[0].columns.rudder={column=\"rudder\",scale=-1}"]),
            refused(&["rudder", "scale = -1"]),
        ),
        check(
            "rpm read as rps",
            &sets(&["hekf.runs[0].columns.rpm={column=\"propeller\",unit=\"rps\"}"]),
            refused(&["rpm read as rev/s", "unit = \"rpm\""]),
        ),
        check(
            "rps under an rpm label",
            &[],
            refused(&["rev/s (rps) read as rpm", "unit = \"rps\""]),
        )
        .setup(edit(TURN, |t| t.scale(&[PROPELLER], 1.0 / 60.0))),
        check(
            "positions read as km",
            &sets(&[
                "hekf.runs[0].columns.x={column=\"x\",unit=\"km\"}",
                "hekf.runs[0].columns.y={column=\"y\",unit=\"km\"}",
            ]),
            refused(&["metres read as kilometres"]),
        ),
        check(
            "time in minutes",
            &[],
            refused(&["minutes read as seconds"]),
        )
        .setup(edit(TURN, |t| t.scale(&[TIME], 1.0 / 60.0))),
        check("velocities in km/h", &[], refused(&["km/h read as m/s"]))
            .setup(edit(TURN, |t| t.scale(&[U, V], 3.6))),
        check("velocities in knots", &[], refused(&["knots read as m/s"]))
            .setup(edit(TURN, |t| t.scale(&[U, V], 3600.0 / 1852.0))),
        check(
            "yaw rate in rad/s under a deg/s label",
            &[],
            refused(&["yaw rate"]),
        )
        .setup(edit(TURN, |t| t.scale(&[R], std::f64::consts::PI / 180.0))),
        check(
            "body velocities declared earth-frame",
            &sets(&["hekf.runs[0].velocity_frame=\"earth\""]),
            refused(&["declares them earth-frame"]),
        ),
        check(
            "sway velocity of the other sign",
            &[],
            refused(&["sway velocity has the opposite sign convention"]),
        )
        .setup(edit(TURN, |t| t.scale(&[V], -1.0))),
        check(
            "heading of the other sign",
            &[],
            refused(&["opposite sign"]),
        )
        .setup(edit(TURN, |t| t.scale(&[HEADING], -1.0))),
        check(
            "rudder radians under a degree label",
            &[],
            refused(&["radians read as degrees"]),
        )
        .setup(edit(TURN, |t| {
            t.scale(&[RUDDER], std::f64::consts::PI / 180.0)
        })),
    ]
}

fn sound_cases() -> Vec<Case> {
    vec![
        check("the example as it is", &[], Expect::Quiet),
        check("columns in reverse order", &[], Expect::Quiet)
            .setup(edit(TURN, |t| t.reorder(&[8, 7, 6, 5, 4, 3, 2, 1, 0]))),
        check("columns shuffled", &[], Expect::Quiet)
            .setup(edit(TURN, |t| t.reorder(&[4, 0, 3, 8, 1, 6, 2, 7, 5]))),
        check("velocities in km/h with their unit", &[], Expect::Quiet).setup(edit(TURN, |t| {
            t.scale(&[U, V], 3.6);
            t.rename(U, "u (km/h)");
            t.rename(V, "v (km/h)");
        })),
        check("heading in radians with its unit", &[], Expect::Quiet).setup(edit(TURN, |t| {
            t.scale(&[HEADING], std::f64::consts::PI / 180.0);
            t.rename(HEADING, "heading (rad)");
        })),
        check("positions in km with their unit", &[], Expect::Quiet).setup(edit(TURN, |t| {
            t.scale(&[X, Y], 1e-3);
            t.rename(X, "x (km)");
            t.rename(Y, "y (km)");
        })),
        check("propeller in rps with its unit", &[], Expect::Quiet).setup(edit(TURN, |t| {
            t.scale(&[PROPELLER], 1.0 / 60.0);
            t.rename(PROPELLER, "propeller (rps)");
        })),
        check(
            "velocities in knots given as such",
            &sets(&[
                "hekf.runs[0].columns.u={column=\"u\",unit=\"kn\"}",
                "hekf.runs[0].columns.v={column=\"v\",unit=\"kn\"}",
            ]),
            Expect::Quiet,
        )
        .setup(edit(TURN, |t| {
            t.scale(&[U, V], 3600.0 / 1852.0);
            t.rename(U, "u");
            t.rename(V, "v");
        })),
        check(
            "a rudder positive to port flipped in the map",
            &sets(&["hekf.runs[0].columns.rudder={column=\"rudder\",scale=-1}"]),
            Expect::Quiet,
        )
        .setup(edit(TURN, |t| t.scale(&[RUDDER], -1.0))),
        check("a heading in compass degrees 0..360", &[], Expect::Quiet)
            .setup(edit(TURN, |t| t.map(HEADING, |v, _| v.rem_euclid(360.0)))),
        check("half the samples", &[], Expect::Quiet).setup(edit(TURN, |t| {
            t.rows = t.rows.iter().step_by(2).cloned().collect()
        })),
    ]
}

#[test]
fn free_running_advice_names_the_right_cause() {
    let mut cases = scale_cases();
    cases.extend(heading_cases());
    cases.extend(classic_cases());
    cases.extend(sound_cases());
    let n = run_table("freerunning (KVLCC2 logs)", cases);
    println!("{n} cases");
    assert!(n >= 45, "{n} cases");
}
