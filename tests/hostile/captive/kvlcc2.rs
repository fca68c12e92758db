//! The classic mistakes of the bundled KVLCC2 captive table (cfd_exports/kvlcc2_captive.csv
//! with configs/ship_captive.toml): units, signs, swapped columns, the moment's centre, alone
//! and in pairs; copies, noise and text columns; and the sound variations that stay quiet.

use super::*;

/// N per kgf: a force in kgf read as N is this times the true one.
const KGF: f64 = 1.0 / 9.80665;

/// The propeller speed's and the rudder angle's units and sign.
fn units_cases() -> Vec<Case> {
    vec![
        set(
            "rpm read as rps",
            &["captive.runs[0].columns.rpm={column=\"propeller\",unit=\"rps\"}"],
            refused(&[
                "rpm read as rev/s",
                "captive.runs[0].columns.rpm",
                "unit = \"rpm\"",
                "advance ratio",
            ]),
        ),
        table(
            "rps under an rpm label",
            &[],
            |t| t.scale(&[PROPELLER], 1.0 / 60.0),
            refused(&["rev/s (rps) read as rpm", "unit = \"rps\"", "columns.rpm"]),
        ),
        table(
            "rps with its unit in the header",
            &[],
            |t| {
                t.scale(&[PROPELLER], 1.0 / 60.0);
                t.rename(PROPELLER, "propeller (rps)");
            },
            Expect::Quiet,
        ),
        table(
            "rudder sign flipped in the file",
            &[],
            |t| t.scale(&[RUDDER], -1.0),
            refused(&[
                "rudder angle has the opposite sign convention",
                "give `scale = -1`",
                "columns.rudder",
                // the numbers docs/stages.md quotes
                "fy correlation 0.92",
                "mz correlation 0.85",
                "corrected fy correlation 1.00",
            ]),
        ),
        set(
            "rudder scale -1 given wrongly",
            &["captive.runs[0].columns.rudder={column=\"rudder\",scale=-1}"],
            refused(&[
                "rudder angle has the opposite sign convention",
                "remove `scale = -1`",
            ]),
        ),
        set(
            "rudder degrees read as radians",
            &["captive.runs[0].columns.rudder={column=\"rudder\",unit=\"rad\"}"],
            refused(&[
                "degrees read as radians",
                "unit = \"deg\"",
                "columns.rudder",
            ]),
        ),
        table(
            "rudder radians under a degree label",
            &[],
            |t| t.scale(&[RUDDER], 1.0 / DEG),
            refused(&[
                "radians read as degrees",
                "unit = \"rad\"",
                "rudder angles up to",
            ]),
        ),
        table(
            "rudder radians with their unit",
            &[],
            |t| {
                t.scale(&[RUDDER], 1.0 / DEG);
                t.rename(RUDDER, "rudder (rad)");
            },
            Expect::Quiet,
        ),
    ]
}

/// The velocities' units.
fn velocity_cases() -> Vec<Case> {
    vec![
        table(
            "velocities in km/h",
            &[],
            |t| t.scale(&[U, V], 3.6),
            refused(&[
                "km/h read as m/s",
                "unit = \"km/h\"",
                "columns.u",
                "columns.v",
            ]),
        ),
        table(
            "velocities in cm/s",
            &[],
            |t| t.scale(&[U, V], 100.0),
            refused(&["cm/s read as m/s", "unit = \"cm/s\""]),
        ),
        table(
            "velocities in mm/s",
            &[],
            |t| t.scale(&[U, V], 1000.0),
            refused(&["mm/s read as m/s", "unit = \"mm/s\""]),
        ),
        table(
            "velocities in knots",
            &[],
            |t| t.scale(&[U, V], 3600.0 / 1852.0),
            refused(&["knots read as m/s", "unit = \"kn\""]),
        ),
        set(
            "velocities read as km/h",
            &[
                "captive.runs[0].columns.u={column=\"u\",unit=\"km/h\"}",
                "captive.runs[0].columns.v={column=\"v\",unit=\"km/h\"}",
            ],
            refused(&["m/s read as km/h", "unit = \"m/s\""]),
        ),
        table(
            "velocities in km/h with their unit",
            &[],
            |t| {
                t.scale(&[U, V], 3.6);
                t.rename(U, "u (km/h)");
                t.rename(V, "v (km/h)");
            },
            Expect::Quiet,
        ),
    ]
}

/// The forces' and the yaw rate's units.
fn force_and_rate_cases() -> Vec<Case> {
    vec![
        table(
            "forces in kgf",
            &[],
            |t| t.scale(&FORCES, 1.0 / 9.80665),
            refused(&[
                "kgf read as N",
                "kgf m read as N m",
                "columns.fy",
                "columns.mz",
            ]),
        ),
        table(
            "forces in kN",
            &[],
            |t| t.scale(&FORCES, 1e-3),
            refused(&["kN read as N", "kN m read as N m", "unit = \"kN\""]),
        ),
        table(
            "forces in lbf",
            &[],
            |t| {
                t.scale(&[FX, FY], 1.0 / 4.448_221_615);
                t.scale(&[MZ], 1.0 / 1.355_817_948);
            },
            refused(&["lbf read as N", "lbf ft read as N m"]),
        ),
        set(
            "forces read as kN",
            &[
                "captive.runs[0].columns.fx={column=\"Fx\",unit=\"kN\"}",
                "captive.runs[0].columns.fy={column=\"Fy\",unit=\"kN\"}",
                "captive.runs[0].columns.mz={column=\"Mz\",unit=\"kN m\"}",
            ],
            refused(&["N read as kN", "columns.fy"]),
        ),
        table(
            "only the moment in kgf m",
            &[],
            |t| t.scale(&[MZ], 1.0 / 9.80665),
            refused(&["columns.mz looks like kgf m read as N m"]),
        ),
        table(
            "only the sway force in kN",
            &[],
            |t| t.scale(&[FY], 1e-3),
            refused(&["columns.fy looks like kN read as N"]),
        ),
        table(
            "forces in kN with their units",
            &[],
            |t| {
                t.scale(&FORCES, 1e-3);
                t.rename(FX, "Fx (kN)");
                t.rename(FY, "Fy (kN)");
                t.rename(MZ, "Mz (kN m)");
            },
            Expect::Quiet,
        ),
        table(
            "yaw rate in rad/s under a deg/s label",
            &[],
            |t| t.scale(&[R], 1.0 / DEG),
            refused(&["rad/s read as deg/s", "unit = \"rad/s\"", "columns.r"]),
        ),
        set(
            "yaw rate read as rad/s",
            &["captive.runs[0].columns.r={column=\"yaw rate\",unit=\"rad/s\"}"],
            refused(&["deg/s read as rad/s", "unit = \"deg/s\""]),
        ),
        table(
            "yaw rate in rad/s with its unit",
            &[],
            |t| {
                t.scale(&[R], 1.0 / DEG);
                t.rename(R, "yaw rate (rad/s)");
            },
            Expect::Quiet,
        ),
    ]
}

/// Swapped force columns and sign conventions.
fn sign_and_column_cases() -> Vec<Case> {
    vec![
        set(
            "fy and mz swapped in the map",
            &[
                "captive.runs[0].columns.fy=\"Mz\"",
                "captive.runs[0].columns.mz=\"Fy\"",
            ],
            refused(&["column 8 'Mz'", "does not fit fy"]),
        ),
        set(
            "fy and mz swapped in the map, units given",
            &[
                "captive.runs[0].columns.fy={column=\"Mz\",unit=\"N\"}",
                "captive.runs[0].columns.mz={column=\"Fy\",unit=\"N m\"}",
            ],
            refused(&[
                "fy and mz look swapped",
                "captive.runs[0].columns.fy",
                "captive.runs[0].columns.mz",
            ]),
        ),
        table(
            "fy and mz swapped in the file",
            &[],
            |t| {
                for r in &mut t.rows {
                    r.swap(FY, MZ);
                }
            },
            refused(&[
                "fy and mz look swapped",
                "fy correlation 0.08",
                "mz correlation 0.08",
            ]),
        ),
        table(
            "fy and mz swapped, in kgf",
            &[],
            |t| {
                t.scale(&FORCES, 1.0 / 9.80665);
                for r in &mut t.rows {
                    r.swap(FY, MZ);
                }
            },
            refused(&["fy and mz look swapped", "kgf"]),
        ),
        table(
            "fy sign flipped",
            &[],
            |t| t.scale(&[FY], -1.0),
            refused(&["fy has the opposite sign convention", "columns.fy"]),
        ),
        table(
            "mz sign flipped",
            &[],
            |t| t.scale(&[MZ], -1.0),
            refused(&["mz has the opposite sign convention", "columns.mz"]),
        ),
        table(
            "fy and mz signs flipped",
            &[],
            |t| t.scale(&[FY, MZ], -1.0),
            refused(&[
                "fy has the opposite sign convention",
                "mz has the opposite sign convention",
            ]),
        ),
        set(
            "fy scale -1 given wrongly",
            &["captive.runs[0].columns.fy={column=\"Fy\",scale=-1}"],
            refused(&["fy has the opposite sign convention", "remove `scale = -1`"]),
        ),
        table(
            "v sign flipped",
            &[],
            |t| t.scale(&[V], -1.0),
            refused(&["v has the opposite sign convention", "columns.v"]),
        ),
        table(
            "r sign flipped",
            &[],
            |t| t.scale(&[R], -1.0),
            refused(&["r has the opposite sign convention", "columns.r"]),
        ),
    ]
}

/// The moment taken about another point than midship.
fn centre_cases() -> Vec<Case> {
    vec![
        table(
            "moment about the rudder stock",
            &[],
            about(-3.5),
            refused(&[
                "yaw moment looks taken about a point",
                "aft of the model's origin",
                "x = -3.502 m, -0.5002 L, at the rudder stock",
            ]),
        ),
        table(
            "moment about a point 2 m aft",
            &[],
            about(-2.0),
            refused(&[
                "yaw moment looks taken about a point",
                "aft of the model's origin",
            ]),
        ),
        table(
            "moment about a point 2 m forward",
            &[],
            about(2.0),
            refused(&[
                "yaw moment looks taken about a point",
                "forward of the model's origin",
            ]),
        ),
        table(
            "moment about the bow",
            &[],
            about(3.5),
            refused(&["yaw moment looks taken about a point", "forward"]),
        ),
    ]
}

/// Two mistakes at once.
fn pair_cases() -> Vec<Case> {
    vec![
        table(
            "rudder sign and kgf",
            &[],
            |t| {
                t.scale(&[RUDDER], -1.0);
                t.scale(&FORCES, 1.0 / 9.80665);
            },
            refused(&[
                "rudder angle has the opposite sign convention",
                "kgf read as N",
            ]),
        ),
        table(
            "km/h and fy sign",
            &[],
            |t| {
                t.scale(&[U, V], 3.6);
                t.scale(&[FY], -1.0);
            },
            refused(&["km/h read as m/s", "fy has the opposite sign convention"]),
        ),
        table(
            "km/h and rudder sign",
            &[],
            |t| {
                t.scale(&[U, V], 3.6);
                t.scale(&[RUDDER], -1.0);
            },
            refused(&[
                "km/h read as m/s",
                "rudder angle has the opposite sign convention",
            ]),
        ),
        table(
            "rps label and kN",
            &[],
            |t| {
                t.scale(&[PROPELLER], 1.0 / 60.0);
                t.scale(&FORCES, 1e-3);
            },
            refused(&["rev/s (rps) read as rpm", "kN read as N"]),
        ),
        table(
            "rudder sign and the rudder stock",
            &[],
            |t| {
                t.scale(&[RUDDER], -1.0);
                about(-3.5)(t);
            },
            refused(&[
                "rudder angle has the opposite sign convention",
                "rudder stock",
            ]),
        ),
        table(
            "cm/s and mz sign",
            &[],
            |t| {
                t.scale(&[U, V], 100.0);
                t.scale(&[MZ], -1.0);
            },
            refused(&["cm/s read as m/s", "mz has the opposite sign convention"]),
        ),
        table(
            "r in rad/s and kgf",
            &[],
            |t| {
                t.scale(&[R], 1.0 / DEG);
                t.scale(&FORCES, 1.0 / 9.80665);
            },
            refused(&["rad/s read as deg/s", "kgf read as N"]),
        ),
        table(
            "a rudder sign with checks = warn",
            &["captive.checks=\"warn\""],
            |t| t.scale(&[RUDDER], -1.0),
            warned(&["rudder angle has the opposite sign convention"]),
        ),
    ]
}

/// More strengths and combinations of the mistakes above.
fn combination_cases() -> Vec<Case> {
    vec![
        table(
            "moment a quarter length aft",
            &[],
            about(-1.75),
            refused(&[
                "yaw moment looks taken about a point",
                "aft of the model's origin",
            ]),
        ),
        table(
            "moment 3 m forward",
            &[],
            about(3.0),
            refused(&[
                "yaw moment looks taken about a point",
                "forward of the model's origin",
            ]),
        ),
        table(
            "moment about the rudder stock, in kgf m",
            &[],
            |t| {
                about(-3.5)(t);
                t.scale(&FORCES, KGF);
            },
            refused(&["rudder stock", "kgf"]),
        ),
        table(
            "km/h and kgf",
            &[],
            |t| {
                t.scale(&[U, V], 3.6);
                t.scale(&FORCES, KGF);
            },
            refused(&["km/h read as m/s", "kgf read as N"]),
        ),
        table(
            "rudder radians and fy sign",
            &[],
            |t| {
                t.scale(&[RUDDER], 1.0 / DEG);
                t.scale(&[FY], -1.0);
            },
            refused(&[
                "radians read as degrees",
                "fy has the opposite sign convention",
            ]),
        ),
        table(
            "rps label and rudder sign",
            &[],
            |t| {
                t.scale(&[PROPELLER], 1.0 / 60.0);
                t.scale(&[RUDDER], -1.0);
            },
            refused(&[
                "rev/s (rps) read as rpm",
                "rudder angle has the opposite sign convention",
            ]),
        ),
    ]
}

/// Further pairs of mistakes.
fn more_combination_cases() -> Vec<Case> {
    vec![
        table(
            "rows written twice and a rudder sign",
            &[],
            |t| {
                t.rows = t.rows.iter().flat_map(|r| [r.clone(), r.clone()]).collect();
                t.scale(&[RUDDER], -1.0);
            },
            refused(&["rudder angle has the opposite sign convention"]),
        ),
        table(
            "fy and mz swapped and v sign",
            &[],
            |t| {
                for r in &mut t.rows {
                    r.swap(FY, MZ);
                }
                t.scale(&[V], -1.0);
            },
            refused(&[
                "fy and mz look swapped",
                "v has the opposite sign convention",
            ]),
        ),
        table(
            "mm/s and kN",
            &[],
            |t| {
                t.scale(&[U, V], 1000.0);
                t.scale(&FORCES, 1e-3);
            },
            refused(&["mm/s read as m/s", "kN read as N"]),
        ),
        table(
            "knots and the rudder sign",
            &[],
            |t| {
                t.scale(&[U, V], 3600.0 / 1852.0);
                t.scale(&[RUDDER], -1.0);
            },
            refused(&[
                "knots read as m/s",
                "rudder angle has the opposite sign convention",
            ]),
        ),
        table(
            "forces and moment in kN, Mz sign",
            &[],
            |t| {
                t.scale(&FORCES, 1e-3);
                t.scale(&[MZ], -1.0);
            },
            refused(&["kN read as N", "mz has the opposite sign convention"]),
        ),
        table(
            "r sign and kgf",
            &[],
            |t| {
                t.scale(&[R], -1.0);
                t.scale(&FORCES, KGF);
            },
            refused(&["r has the opposite sign convention", "kgf read as N"]),
        ),
    ]
}

/// Rows written more than once and forces of noise.
fn structure_cases() -> Vec<Case> {
    vec![
        table(
            "every row written twice",
            &[],
            |t| {
                t.rows = t.rows.iter().flat_map(|r| [r.clone(), r.clone()]).collect();
            },
            warned(&[
                "84 of the 168 rows repeat an earlier row",
                "lines 3 = 2",
                "left out of the fit",
            ]),
        ),
        table(
            "every row written three times",
            &[],
            |t| {
                t.rows = t
                    .rows
                    .iter()
                    .flat_map(|r| [r.clone(), r.clone(), r.clone()])
                    .collect();
            },
            warned(&["168 of the 252 rows repeat an earlier row"]),
        ),
        table(
            "a block pasted again",
            &[],
            |t| {
                let block: Vec<Vec<String>> = t.rows[..50].to_vec();
                t.rows.extend(block);
            },
            warned(&["50 of the 134 rows repeat an earlier row", "lines 86 = 2"]),
        ),
        table(
            "the table written twice, rows reversed",
            &[],
            |t| {
                let mut copy = t.rows.clone();
                copy.reverse();
                t.rows.extend(copy);
            },
            warned(&["84 of the 168 rows repeat"]),
        ),
        table(
            "forces of pure noise",
            &[],
            noise(&FORCES),
            warned(&["do not respond to the motion", "fy (F =", "mz (F ="]),
        ),
        table(
            "sway force of pure noise",
            &[],
            noise(&[FY]),
            warned(&["fy (F =", "does not respond to the motion"]),
        ),
        table(
            "yaw moment of pure noise",
            &[],
            noise(&[MZ]),
            warned(&["mz (F =", "does not respond to the motion"]),
        ),
    ]
}

/// Text columns, no forward speed, one column mapped twice.
fn text_and_column_cases() -> Vec<Case> {
    vec![
        table(
            "a text column at the end",
            &[],
            |t| {
                t.head.push("\"test type\"".into());
                for (k, r) in t.rows.iter_mut().enumerate() {
                    r.push(
                        if k % 2 == 0 {
                            "drift angle"
                        } else {
                            "rudder angle"
                        }
                        .into(),
                    );
                }
            },
            refused(&[
                "column 9 'test type'",
                "84 rows (from line 2)",
                "'drift angle', 'rudder angle'",
                "delete the text column",
                "map the numeric columns",
            ]),
        ),
        table(
            "a text column in the middle",
            &[],
            |t| {
                t.head.insert(2, "\"series\"".into());
                for r in &mut t.rows {
                    r.insert(2, "static drift".into());
                }
            },
            refused(&["column 3 'series'", "delete the text column"]),
        ),
        table(
            "two text columns",
            &[],
            |t| {
                t.head.push("\"test\"".into());
                t.head.push("\"remark\"".into());
                for r in &mut t.rows {
                    r.push("captive".into());
                    r.push("ok".into());
                }
            },
            refused(&[
                "columns of text",
                "column 9 'test'",
                "column 10 'remark'",
                "delete the text columns",
            ]),
        ),
        table(
            "no forward speed",
            &[],
            |t| t.scale(&[U], 0.0),
            refused(&["forward speed u is 0 on every row"]),
        ),
        set(
            "fy and mz on one column",
            &["captive.runs[0].columns.mz={column=\"Fy\",unit=\"N m\"}"],
            refused(&["fy, mz hold identical values", "check the run's `columns`"]),
        ),
    ]
}

/// Sound variations: must stay quiet.
fn sound_cases() -> Vec<Case> {
    vec![
        set("the example as it is", &[], Expect::Quiet),
        table(
            "columns in reverse order",
            &[],
            |t| t.reorder(&[7, 6, 5, 4, 3, 2, 1, 0]),
            Expect::Quiet,
        ),
        table(
            "columns shuffled",
            &[],
            |t| t.reorder(&[5, 0, 7, 2, 4, 1, 6, 3]),
            Expect::Quiet,
        ),
        table(
            "rows in reverse order",
            &[],
            |t| t.rows.reverse(),
            Expect::Quiet,
        ),
        table(
            "rows sorted by rudder angle",
            &[],
            |t| {
                t.rows.sort_by(|a, b| {
                    a[RUDDER]
                        .parse::<f64>()
                        .unwrap()
                        .total_cmp(&b[RUDDER].parse().unwrap())
                });
            },
            Expect::Quiet,
        ),
        table(
            "every third row left out",
            &[],
            |t| {
                t.rows = t
                    .rows
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| k % 3 != 0)
                    .map(|(_, r)| r.clone())
                    .collect();
            },
            Expect::Quiet,
        ),
        table(
            "an unmapped run-number column",
            &[],
            |t| {
                t.head.insert(0, "\"run\"".into());
                for (k, r) in t.rows.iter_mut().enumerate() {
                    r.insert(0, format!("{}", 300 + k));
                }
            },
            Expect::Quiet,
        ),
        table(
            "a rudder positive to port, flipped in the map",
            &["captive.runs[0].columns.rudder={column=\"rudder\",scale=-1}"],
            |t| t.scale(&[RUDDER], -1.0),
            Expect::Quiet,
        ),
        table(
            "mz positive to port, flipped in the map",
            &["captive.runs[0].columns.mz={column=\"Mz\",scale=-1}"],
            |t| t.scale(&[MZ], -1.0),
            Expect::Quiet,
        ),
        table(
            "moment in kN m given as such",
            &["captive.runs[0].columns.mz={column=\"Mz\",unit=\"kN m\"}"],
            |t| t.scale(&[MZ], 1e-3),
            Expect::Quiet,
        ),
    ]
}

#[test]
fn classic_mistakes_of_a_captive_table_are_named() {
    let mut cases = units_cases();
    for more in [
        velocity_cases,
        force_and_rate_cases,
        sign_and_column_cases,
        centre_cases,
        pair_cases,
        combination_cases,
        more_combination_cases,
        structure_cases,
        text_and_column_cases,
        sound_cases,
    ] {
        cases.extend(more());
    }
    let n = run_table("captive (KVLCC2 table)", cases);
    println!("{n} cases");
    assert!(n >= 80, "{n} cases");
}
