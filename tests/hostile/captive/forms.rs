//! Other forms of captive data: the prime-system table of tests/fixtures/captive, the
//! spheroid's PMM force files with their prescribed motion (configs/spheroid_joint.toml), and
//! polars with as many points as constants.

use super::*;

/// The prime-system table of tests/fixtures/captive, copied into the case's folder.
fn prime(name: &str, sets: &[&str], expect: Expect) -> Case {
    check_with(name, "prime/prime_table.toml", sets, expect).setup(|dir: &Path| {
        let from = crate::common::root().join("tests/fixtures/captive");
        std::fs::create_dir_all(dir.join("prime")).unwrap();
        for f in ["prime_table.toml", "kvlcc2_prime_table.csv"] {
            std::fs::copy(from.join(f), dir.join("prime").join(f)).unwrap();
        }
    })
}

#[test]
fn mistakes_of_a_prime_table_are_named() {
    let cases = vec![
        prime("the prime table as it is", &[], Expect::Quiet),
        prime(
            "prime length in mm",
            &["captive.prime={length=\"7000 m\",area=\"3.22 m^2\"}"],
            refused(&[
                "captive.prime.length = 7000 m is 1000 times vehicle.length",
                "length in mm",
            ]),
        ),
        prime(
            "prime length in cm",
            &["captive.prime={length=\"700 m\",area=\"3.22 m^2\"}"],
            refused(&["100.0 times vehicle.length", "length in cm"]),
        ),
        prime(
            "prime length given in mm with its unit",
            &["captive.prime={length=\"7000 mm\",area=\"3.22 m^2\"}"],
            Expect::Quiet,
        ),
        prime(
            "L^2 where the table is on L d",
            &["captive.prime={length=\"7 m\",area=\"49 m^2\"}"],
            refused(&[
                "normalised on L d (the draught) = 3.220 m^2",
                "captive.prime.area = 49",
            ]),
        ),
        prime(
            "the displacement's area where the table is on L d",
            &["captive.prime={length=\"7 m\",area=\"2.2 m^2\"}"],
            warned(&[
                "normalised on L d (the draught) = 3.220 m^2",
                "captive.prime.area = 2.200 m^2",
            ]),
        ),
        prime(
            "y' and n' swapped",
            &[
                "captive.runs[0].columns.y_prime=\"N'\"",
                "captive.runs[0].columns.n_prime=\"Y'\"",
            ],
            refused(&[
                "fy and mz look swapped",
                "columns.y_prime",
                "columns.n_prime",
            ]),
        ),
        prime(
            "speed read as km/h",
            &["captive.runs[0].columns.speed={column=\"U\",unit=\"km/h\"}"],
            refused(&["m/s read as km/h", "columns.speed"]),
        ),
        prime(
            "drift in degrees read as radians",
            &["captive.runs[0].columns.drift={column=\"beta\",unit=\"rad\"}"],
            refused(&[
                "drift angle looks like degrees read as radians",
                "columns.drift",
            ]),
        ),
        prime(
            "drift of the other sign",
            &["captive.runs[0].columns.drift={column=\"beta\",scale=-1}"],
            refused(&["v has the opposite sign convention", "columns.drift"]),
        ),
        prime(
            "r' of the other sign",
            &["captive.runs[0].columns.r_prime={column=\"r'\",scale=-1}"],
            refused(&["r has the opposite sign convention", "columns.r_prime"]),
        ),
        prime(
            "n' of the other sign",
            &["captive.runs[0].columns.n_prime={column=\"N'\",scale=-1}"],
            refused(&["mz has the opposite sign convention", "columns.n_prime"]),
        ),
        prime(
            "rudder of the other sign",
            &["captive.runs[0].columns.rudder={column=\"delta\",scale=-1}"],
            refused(&["rudder angle has the opposite sign convention"]),
        ),
        prime(
            "propeller read as rpm",
            &["captive.runs[0].columns.rpm={column=\"n\",unit=\"rpm\"}"],
            refused(&["rev/s (rps) read as rpm"]),
        ),
    ];
    let n = run_table("captive (prime table)", cases);
    println!("{n} cases");
}

/// `hydroid check` of the spheroid's joint example (its PMM runs) with `--set` values.
fn pmm(name: &str, sets: &[&str], expect: Expect) -> Case {
    check_with(name, "configs/spheroid_joint.toml", sets, expect)
}

/// The PMM runs' forces mistaken.
fn pmm_cases() -> Vec<Case> {
    vec![
        pmm("the PMM runs as they are", &[], Expect::Quiet),
        pmm(
            "pure sway fy of the other sign",
            &["captive.runs[0].columns.fy={column=\"force_total_y\",scale=-1}"],
            refused(&["run 'pure sway'", "fy has the opposite sign convention"]),
        ),
        pmm(
            "pure yaw mz of the other sign",
            &["captive.runs[1].columns.mz={column=\"moment_total_z\",scale=-1}"],
            refused(&["run 'pure yaw'", "mz has the opposite sign convention"]),
        ),
        pmm(
            "pure yaw fy and mz swapped",
            &[
                "captive.runs[1].columns.fy={column=\"moment_total_z\",unit=\"N\"}",
                "captive.runs[1].columns.mz={column=\"force_total_y\",unit=\"N m\"}",
            ],
            refused(&["run 'pure yaw'", "fy and mz look swapped"]),
        ),
        pmm(
            "pure sway forces read as kN",
            &[
                "captive.runs[0].columns.fy={column=\"force_total_y\",unit=\"kN\"}",
                "captive.runs[0].columns.mz={column=\"moment_total_z\",unit=\"kN m\"}",
            ],
            refused(&["run 'pure sway'", "N read as kN"]),
        ),
        pmm(
            "pure sway in kgf",
            &[
                "captive.runs[0].columns.fy={column=\"force_total_y\",unit=\"kgf\"}",
                "captive.runs[0].columns.mz={column=\"moment_total_z\",unit=\"kgf m\"}",
            ],
            refused(&["run 'pure sway'", "N read as kgf"]),
        ),
    ]
}

/// The prescribed motion of the PMM runs mistaken.
fn pmm_motion_cases() -> Vec<Case> {
    vec![
        pmm(
            "pure sway amplitude twice",
            &["captive.oscillations.\"pure sway\".amplitude={v=\"0.5 m/s\"}"],
            warned(&["run 'pure sway'", "motion amplitude"]),
        ),
        pmm(
            "pure yaw amplitude in rad/s",
            &["captive.oscillations.\"pure yaw\".amplitude={r=\"15 rad/s\"}"],
            warned(&[
                "run 'pure yaw'",
                "stated motion amplitude (15.00) is likely wrong",
                "rad/s read as deg/s",
            ]),
        ),
        pmm(
            "towing speed twice",
            &["captive.runs[0].constants={u=\"4 m/s\",thrust=\"0 N\"}"],
            warned(&[
                "run 'pure sway'",
                "towing speed gives a Froude number",
                "1.166",
                "(the model's example: 0.9218)",
            ]),
        ),
        pmm(
            "pure yaw mz in kN m",
            &["captive.runs[1].columns.mz={column=\"moment_total_z\",unit=\"kN m\"}"],
            refused(&["run 'pure yaw'", "N m read as kN m"]),
        ),
        pmm(
            "both runs' fy of the other sign",
            &[
                "captive.runs[0].columns.fy={column=\"force_total_y\",scale=-1}",
                "captive.runs[1].columns.fy={column=\"force_total_y\",scale=-1}",
            ],
            refused(&[
                "run 'pure sway'",
                "run 'pure yaw'",
                "fy has the opposite sign convention",
            ]),
        ),
        pmm(
            "pure sway of the other sign",
            &["captive.oscillations.\"pure sway\".amplitude={v=\"-0.25 m/s\"}"],
            refused(&[
                "fy has the opposite sign convention",
                "the prescribed motion has the opposite sign",
                "captive.oscillations.\"pure sway\"",
            ]),
        ),
        pmm(
            "pure sway phase off by 180 deg",
            &["captive.oscillations.\"pure sway\".phase=\"180 deg\""],
            refused(&[
                "mz has the opposite sign convention",
                "a phase off by 180 deg",
            ]),
        ),
        pmm(
            "pure yaw phase given as 90 deg (a sway displacement's)",
            &["captive.oscillations.\"pure yaw\".phase=\"90 deg\""],
            warned(&[
                "run 'pure yaw'",
                "a negative added mass",
                "the stated phase is off by 90 or 180 deg",
            ]),
        ),
    ]
}

#[test]
fn mistakes_of_pmm_force_files_are_named() {
    let mut cases = pmm_cases();
    cases.extend(pmm_motion_cases());
    let n = run_table("captive (PMM)", cases);
    println!("{n} cases");
}

/// `hydroid run` of the spheroid's polar alone on the first `n` points of its sweep at one
/// speed.
fn polar(n: usize, expect: Expect) -> Case {
    Case::new(
        &format!("a {n}-point polar"),
        "run configs/spheroid.toml --out out/p --set surge.enabled=false --set hekf.enabled=false --set output.plots=false",
        expect,
    )
    .setup(edit("cfd_exports/polar_sweep.csv", move |t| {
        let keep: Vec<Vec<String>> = t
            .rows
            .iter()
            .filter(|r| r[1].parse::<f64>().unwrap() == 2.0)
            .step_by(3)
            .take(n)
            .cloned()
            .collect();
        t.rows = keep;
    }))
}

#[test]
fn a_polar_with_as_many_points_as_constants_says_its_sigmas_are_undetermined() {
    run_table(
        "polar (few points)",
        vec![
            polar(
                3,
                warned(&[
                    "the drag fit",
                    "has 3 points for its free constants",
                    "the sigmas of Xuu, Xuv, Xvv, Yvv, Yuvd are undetermined",
                ]),
            ),
            polar(5, Expect::Quiet),
        ],
    );
}
