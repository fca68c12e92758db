//! Every fixture under tests/fixtures/formats/: detected format, column names, units, rows,
//! a few cells in SI, the time column, metadata, restarts and angle unwrapping.

use hydroid::io::formats::{self, detect::detect, Format, FormatChoice, ReadOptions};
use hydroid::io::table::Table;
use std::f64::consts::PI;
use std::path::PathBuf;

fn path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/formats")
        .join(name)
}

/// Reads a fixture with detection, checking that `detect` agrees with `read`.
fn read(name: &str, format: Format) -> Table {
    let p = path(name);
    assert_eq!(detect(&p).unwrap(), format, "{name}");
    let t = formats::read(&p, FormatChoice::Auto, &ReadOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(t.format, format);
    assert_eq!(t.lines.len(), t.rows());
    for c in &t.columns {
        assert_eq!(c.values.len(), t.rows(), "{name}: column {}", c.name);
    }
    t
}

fn col<'a>(t: &'a Table, name: &str) -> &'a [f64] {
    let i = t
        .column_index(name)
        .unwrap_or_else(|| panic!("no column {name} in {:?}", t.names()));
    &t.columns[i].values
}

fn unit(t: &Table, name: &str) -> Option<String> {
    let i = t.column_index(name).unwrap();
    t.columns[i].unit.as_ref().map(|u| u.text.clone())
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs().max(1.0)
}

#[test]
fn openfoam_legacy_force_coeffs() {
    let t = read(
        "openfoam_legacy_forceCoeffs.dat",
        Format::OpenFoamForceCoeffs,
    );
    assert_eq!(t.names(), ["Time", "Cm", "Cd", "Cl", "Cl(f)", "Cl(r)"]);
    assert_eq!(t.rows(), 4);
    assert_eq!(t.lines, [10, 11, 12, 13]);
    assert_eq!(t.time, Some(0));
    assert_eq!(unit(&t, "Time").as_deref(), Some("s"));
    assert_eq!(
        t.columns[2].unit.as_ref().map(|u| u.dim),
        Some([0, 0, 0, 0])
    );
    assert_eq!(col(&t, "Time")[0], 0.0022);
    assert_eq!(col(&t, "Cd")[0], 1.451809236110e+03);
    assert_eq!(col(&t, "Cl(r)")[3], -3.420120467466e-04);
    assert_eq!(t.meta("magUInf"), Some("1.000000000000e+00"));
    assert_eq!(
        t.meta("CofR"),
        Some("(0.000000000000e+00 0.000000000000e+00 0.000000000000e+00)")
    );
    assert_eq!(t.meta("title"), Some("Force coefficients"));
}

#[test]
fn openfoam_org12_force_coeffs() {
    let t = read(
        "openfoam_org12_forceCoeffs.dat",
        Format::OpenFoamForceCoeffs,
    );
    assert_eq!(t.rows(), 1);
    assert_eq!(t.lines, [10]);
    assert_eq!(t.meta("magUInf"), Some("2.00000000e+01"));
    assert_eq!(t.meta("lRef"), Some("2.50000000e-01"));
    assert_eq!(t.meta("Aref"), Some("7.50000000e-01"));
    assert_eq!(
        t.meta("liftDir"),
        Some("(0.00000000e+00 0.00000000e+00 1.00000000e+00)")
    );
}

#[test]
fn openfoam_esi_coefficient() {
    let t = read("openfoam_esi_coefficient.dat", Format::OpenFoamCoefficient);
    assert_eq!(
        t.names(),
        [
            "Time", "Cd", "Cs", "Cl", "CmRoll", "CmPitch", "CmYaw", "Cd(f)", "Cd(r)", "Cs(f)",
            "Cs(r)", "Cl(f)", "Cl(r)"
        ]
    );
    assert_eq!(t.rows(), 3);
    assert_eq!(col(&t, "Cs")[0], -1.101286e-19);
    assert_eq!(col(&t, "CmYaw")[2], 4.536726e-01);
    assert_eq!(
        t.meta("sideDir"),
        Some("(0.000000e+00 0.000000e+00 -1.000000e+00)")
    );
    assert_eq!(
        t.meta("CofR"),
        Some("(2.500000e-01 0.000000e+00 0.000000e+00)")
    );
}

#[test]
fn openfoam_esi_force_and_moment() {
    let f = read("openfoam_esi_v2212_force.dat", Format::OpenFoamForce);
    let m = read("openfoam_esi_v2212_moment.dat", Format::OpenFoamForce);
    for t in [&f, &m] {
        assert_eq!(t.columns.len(), 10);
        assert_eq!(t.names()[1..4], ["total_x", "total_y", "total_z"]);
        assert_eq!(t.names()[9], "viscous_z");
        assert_eq!(t.rows(), 3);
        assert_eq!(t.time, Some(0));
    }
    assert_eq!(
        f.columns[1].unit.as_ref().map(|u| u.dim),
        Some([1, 1, -2, 0])
    );
    assert_eq!(
        m.columns[1].unit.as_ref().map(|u| u.dim),
        Some([1, 2, -2, 0])
    );
    assert_eq!(col(&f, "total_x")[0], -7.014619e+03);
    assert_eq!(col(&m, "viscous_z")[2], -7.787680e+00);
    assert_eq!(
        f.meta("CofR"),
        Some("(2.929541e+00 0.000000e+00 2.000000e-01)")
    );
}

#[test]
fn openfoam_legacy_forces_three_groups() {
    let t = read("openfoam_legacy_forces.dat", Format::OpenFoamForcesLegacy);
    // Time + 2 groups x (3 parts + total) x 3 axes
    assert_eq!(t.columns.len(), 25);
    assert_eq!(
        t.names()[1..4],
        ["force_pressure_x", "force_pressure_y", "force_pressure_z"]
    );
    assert_eq!(
        t.names()[10..13],
        ["force_total_x", "force_total_y", "force_total_z"]
    );
    assert_eq!(
        t.names()[22..25],
        ["moment_total_x", "moment_total_y", "moment_total_z"]
    );
    assert_eq!(t.rows(), 3);
    assert_eq!(t.lines, [4, 5, 6]);
    assert_eq!(col(&t, "force_pressure_x")[0], 3.297788e+02);
    assert_eq!(col(&t, "force_viscous_x")[0], 6.854738e-01);
    assert_eq!(col(&t, "moment_pressure_z")[0], 1.741291e+03);
    assert!(close(
        col(&t, "force_total_x")[0],
        3.297788e+02 + 6.854738e-01
    ));
    assert!(close(
        col(&t, "moment_total_y")[1],
        1.309891e+02 + 1.071861e+00
    ));
    assert_eq!(unit(&t, "moment_total_z").as_deref(), Some("N m"));
    assert_eq!(unit(&t, "force_porous_y").as_deref(), Some("N"));
}

#[test]
fn openfoam_org10_forces_two_groups() {
    let t = read("openfoam_org10_forces.dat", Format::OpenFoamForcesLegacy);
    assert_eq!(t.columns.len(), 1 + 2 * 3 * 3);
    assert!(t.column_index("force_porous_x").is_none());
    assert_eq!(col(&t, "Time"), [0.0, 0.01, 0.02]);
    assert_eq!(col(&t, "force_pressure_y")[0], -6.950796e+06);
    assert_eq!(col(&t, "moment_viscous_z")[1], 1.512104e-02);
    assert!(close(
        col(&t, "moment_total_x")[1],
        1.848375e+05 + -5.911308e-04
    ));
}

#[test]
fn openfoam_restart_keeps_the_last_rows() {
    let t = read(
        "openfoam_forceCoeffs_restart.dat",
        Format::OpenFoamForceCoeffs,
    );
    assert_eq!(col(&t, "Time"), [0.1, 0.2, 0.3, 0.4]);
    assert_eq!(col(&t, "Cd"), [0.50, 0.61, 0.62, 0.63]);
    assert_eq!(t.lines, [6, 9, 10, 11]);
    assert_eq!(t.warnings.len(), 1, "{:?}", t.warnings);
    assert!(
        t.warnings[0].contains("2 repeated time stamps"),
        "{:?}",
        t.warnings
    );
    assert!(t.warnings[0].contains("line 7"), "{:?}", t.warnings);
    assert_eq!(t.meta("Aref"), Some("0.5"));
}

#[test]
fn sixdof_in_degrees_becomes_radians() {
    let t = read("sixDoFRigidBodyState_degrees.dat", Format::OpenFoamSixDof);
    assert_eq!(t.columns.len(), 16);
    assert_eq!(
        t.names()[1..10],
        [
            "centreOfRotation_x",
            "centreOfRotation_y",
            "centreOfRotation_z",
            "centreOfMass_x",
            "centreOfMass_y",
            "centreOfMass_z",
            "roll",
            "pitch",
            "yaw"
        ]
    );
    assert_eq!(t.meta("Angle Units"), Some("degrees"));
    assert_eq!(unit(&t, "yaw").as_deref(), Some("deg"));
    assert_eq!(unit(&t, "omega_z").as_deref(), Some("deg/s"));
    assert_eq!(unit(&t, "velocity_x").as_deref(), Some("m/s"));
    // 170, 175, -179, -174 deg, as written: only the record unwraps an attitude history
    let yaw: Vec<f64> = col(&t, "yaw").iter().map(|r| r.to_degrees()).collect();
    for (got, want) in yaw.iter().zip([170.0, 175.0, -179.0, -174.0]) {
        assert!((got - want).abs() < 1e-9, "{yaw:?}");
    }
    assert!(close(col(&t, "omega_z")[2], 12.0 * PI / 180.0));
    assert!(close(col(&t, "pitch")[2], -0.2 * PI / 180.0));
    assert_eq!(col(&t, "centreOfMass_z")[0], 0.1);
    assert_eq!(col(&t, "velocity_y")[2], 0.15);
}

#[test]
fn sixdof_in_radians() {
    let t = read("sixDoFRigidBodyState_radians.dat", Format::OpenFoamSixDof);
    assert_eq!(unit(&t, "roll").as_deref(), Some("rad"));
    assert_eq!(unit(&t, "omega_x").as_deref(), Some("rad/s"));
    let yaw = col(&t, "yaw");
    assert_eq!(yaw[..2], [3.0, 3.1]);
    assert!(close(yaw[2], -3.1), "as written: {yaw:?}");
    assert!(t.warnings.is_empty(), "{:?}", t.warnings);
}

#[test]
fn fluent_report_with_iterations() {
    let t = read("fluent_rfile_iteration.out", Format::Fluent);
    assert_eq!(t.names(), ["Iteration", "drag"]);
    assert_eq!(t.time, None);
    assert_eq!(t.rows(), 5);
    assert_eq!(t.lines[0], 4);
    assert_eq!(col(&t, "drag")[0], 0.3308057);
    assert_eq!(t.meta("title"), Some("drag-rfile"));
}

#[test]
fn fluent_report_names_come_from_the_parenthesised_line() {
    let t = read("fluent_rfile_timestep.out", Format::Fluent);
    assert_eq!(t.names(), ["Time Step", "vazao-mass-porta", "flow-time"]);
    assert_eq!(t.time, Some(2));
    assert_eq!(unit(&t, "flow-time").as_deref(), Some("s"));
    assert_eq!(col(&t, "flow-time"), [0.0, 0.1, 0.2, 0.3, 0.4]);
    assert_eq!(col(&t, "vazao-mass-porta")[0], 0.02090708516238086);
}

#[test]
fn fluent_two_line_history_with_crlf() {
    let t = read("fluent_history_flowtime", Format::Fluent);
    assert_eq!(t.names(), ["Flow Time", "cd"]);
    assert_eq!(t.time, Some(0));
    assert_eq!(t.lines, [3, 4, 5, 6, 7, 8]);
    assert_eq!(col(&t, "cd")[5], 8.88566e-03);
    assert_eq!(t.meta("title"), Some("Drag Convergence"));
    let t = read("fluent_report_flowtime_crlf.out", Format::Fluent);
    assert_eq!(t.names(), ["flow-time", "fy", "mz"]);
    assert_eq!(col(&t, "mz"), [2.0, 2.1, 2.2]);
}

#[test]
fn starccm_table_export() {
    let t = read("starccm_table_export.csv", Format::StarCcm);
    assert_eq!(
        t.names(),
        [
            "Position[X]",
            "Position[Y]",
            "Position[Z]",
            "Electric Current Density: Magnitude",
            "Temperature",
            "X",
            "Y",
            "Z"
        ]
    );
    assert_eq!(t.rows(), 2);
    assert_eq!(unit(&t, "Position[X]").as_deref(), Some("m"));
    // A/m^2 and K are real units hydroid does not convert: kept as written, with a warning.
    assert_eq!(unit(&t, "Temperature"), None);
    assert_eq!(t.columns[4].header, "Temperature (K)");
    assert_eq!(t.warnings.len(), 2, "{:?}", t.warnings);
    // the text of the cells, parsed exactly
    let exact = |s: &str| s.parse::<f64>().unwrap();
    assert_eq!(col(&t, "Temperature")[0], exact("308.51127939212103"));
    assert_eq!(col(&t, "Position[Z]")[1], exact("0.00038209495269981301"));
    assert_eq!(t.time, None);
}

#[test]
fn starccm_monitor_export() {
    let t = read("starccm_monitor.csv", Format::StarCcm);
    assert_eq!(t.time, Some(1));
    assert_eq!(t.columns[1].name, "Physical Time: Physical Time");
    assert_eq!(unit(&t, "Moment 1 Monitor: Moment").as_deref(), Some("N-m"));
    let rot: Vec<f64> = col(&t, "rotation Monitor: Expression")
        .iter()
        .map(|r| r.to_degrees())
        .collect();
    for (got, want) in rot.iter().zip([176.0, 179.0, -178.0, -175.0]) {
        assert!((got - want).abs() < 1e-9, "{rot:?}");
    }
    assert_eq!(col(&t, "Iteration"), [100.0, 200.0, 300.0, 400.0]);
}

#[test]
fn cfx_monitor_export() {
    let t = read("cfx_monitor.csv", Format::Cfx);
    assert_eq!(
        t.names(),
        [
            "Time",
            "Velocity u",
            "Velocity v",
            "Heading",
            "Angular Velocity r",
            "Monitor Point: Fy",
            "Monitor Point: Mz"
        ]
    );
    assert_eq!(t.columns[1].header, "Velocity u [ m s^-1 ]");
    assert_eq!(unit(&t, "Velocity u").as_deref(), Some("m s^-1"));
    assert_eq!(unit(&t, "Monitor Point: Mz").as_deref(), Some("N m"));
    assert_eq!(t.time, Some(0));
    assert_eq!(t.lines, [5, 6, 7, 8, 9]);
    let heading: Vec<f64> = col(&t, "Heading").iter().map(|r| r.to_degrees()).collect();
    for (got, want) in heading.iter().zip([170.0, 175.0, 179.5, -176.0, -171.5]) {
        assert!((got - want).abs() < 1e-9, "{heading:?}");
    }
    assert!(close(col(&t, "Angular Velocity r")[2], 9.0 * PI / 180.0));
    assert_eq!(col(&t, "Monitor Point: Fy")[0], -12.5);
    assert_eq!(
        t.meta("title"),
        Some("Monitor data exported from CFX-Solver run spheroid_turn_001.res")
    );
}

#[test]
fn cfx_post_table_with_sections() {
    let t = read("cfx_post_table.csv", Format::Cfx);
    assert_eq!(t.names(), ["X", "Y", "Z", "Pressure", "Temperature"]);
    assert_eq!(t.meta("Name"), Some("Polyline 1"));
    // kPa becomes Pa
    assert!(close(col(&t, "Pressure")[0], 101_325.0));
    assert_eq!(t.time, None);
}

#[test]
fn generic_comma_with_title_comments_and_units() {
    let t = read("generic_comma.csv", Format::Delimited);
    assert_eq!(t.names(), ["time", "x", "heading", "rudder", "Fy", "Cl(r)"]);
    assert_eq!(unit(&t, "x").as_deref(), Some("m"));
    assert_eq!(
        unit(&t, "Cl(r)"),
        None,
        "Cl(r) is a name, not Cl in revolutions"
    );
    assert_eq!(t.rows(), 4);
    assert_eq!(t.lines, [5, 6, 7, 9]);
    assert!(close(col(&t, "rudder")[1], 5.0 * PI / 180.0));
    assert_eq!(col(&t, "Fy")[3], -3.75);
    assert_eq!(t.meta("title"), Some("Towing tank run 12 - KCS 1/75 model"));
    assert_eq!(t.meta("date"), Some("2024-03-14"));
    assert_eq!(t.time, Some(0));
}

#[test]
fn generic_semicolons_with_decimal_commas() {
    let t = read("generic_semicolon_decimal_comma.csv", Format::Delimited);
    assert_eq!(t.names(), ["t", "u", "yaw"]);
    assert_eq!(col(&t, "u"), [1.25, 1.5, 1.75]);
    assert_eq!(col(&t, "t"), [0.0, 0.1, 0.2]);
    assert!(close(col(&t, "yaw")[0], 10.5 * PI / 180.0));
}

#[test]
fn generic_tabs_with_an_empty_cell() {
    let t = read("generic_tab.tsv", Format::Delimited);
    assert_eq!(t.names(), ["time", "u", "v", "r"]);
    assert_eq!(t.lines, [3, 4, 5, 7]);
    assert!(col(&t, "v")[1].is_nan());
    assert_eq!(t.missing, [(1, 2)]);
    assert_eq!(col(&t, "r")[3], 0.03);
    assert_eq!(t.meta("comment"), Some("free-running test, rudder step"));
}

#[test]
fn generic_whitespace_with_a_commented_header() {
    let t = read("generic_whitespace.dat", Format::Delimited);
    assert_eq!(t.names(), ["t", "u", "v", "r"]);
    assert_eq!(t.time, Some(0));
    assert_eq!(col(&t, "r"), [0.0, 0.001, -2.0e-3, 1.5e-3]);
    assert_eq!(t.lines, [3, 4, 5, 6]);
}

#[test]
fn generic_without_header_uses_configured_or_default_names() {
    let t = read("generic_noheader.csv", Format::Delimited);
    assert_eq!(t.names(), ["col1", "col2", "col3"]);
    assert_eq!(t.lines, [1, 2, 3, 4]);
    assert_eq!(t.time, None);
    let names = ReadOptions {
        names: Some(vec!["time".into(), "u".into(), "v".into()]),
        ..Default::default()
    };
    let t = formats::read(&path("generic_noheader.csv"), FormatChoice::Auto, &names).unwrap();
    assert_eq!(t.names(), ["time", "u", "v"]);
    assert_eq!(col(&t, "v")[3], 2.3);
    let wrong = ReadOptions {
        names: Some(vec!["time".into(), "u".into()]),
        ..Default::default()
    };
    let e = formats::read(&path("generic_noheader.csv"), FormatChoice::Auto, &wrong)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("2 column names") && e.contains("3 columns"),
        "{e}"
    );
}

#[test]
fn generic_latin1_with_cr_line_ends() {
    // `Heading (°)` in Latin-1, old Mac line ends, semicolons.
    let t = read("generic_latin1_cr.csv", Format::Delimited);
    assert_eq!(t.names(), ["time", "Heading"]);
    assert_eq!(t.columns[1].header, "Heading (°)");
    assert_eq!(t.lines, [2, 3, 4]);
    let deg: Vec<f64> = col(&t, "Heading").iter().map(|r| r.to_degrees()).collect();
    for (got, want) in deg.iter().zip([179.0, -179.0, -170.0]) {
        assert!((got - want).abs() < 1e-9, "{deg:?}");
    }
}

#[test]
fn generic_restart_keeps_the_last_row_of_each_time_and_warns() {
    let t = read("generic_restart.csv", Format::Delimited);
    assert_eq!(col(&t, "time"), [0.0, 0.1, 0.2, 0.3, 0.4]);
    assert_eq!(col(&t, "u"), [1.00, 1.01, 2.02, 2.03, 2.04]);
    assert_eq!(t.lines, [2, 3, 6, 7, 8]);
    assert!(
        t.warnings.iter().any(|w| w.contains("repeated")),
        "{:?}",
        t.warnings
    );
}

#[test]
fn generic_missing_cells_are_nan_and_recorded() {
    let t = read("generic_missing.csv", Format::Delimited);
    assert_eq!(t.missing, [(1, 1), (2, 2)]);
    assert!(col(&t, "u")[1].is_nan() && col(&t, "v")[2].is_nan());
    assert_eq!(col(&t, "u")[2], 1.2);
}

#[test]
fn raw_read_keeps_file_values_and_every_row() {
    let t = formats::read_raw(
        &path("generic_restart.csv"),
        FormatChoice::Auto,
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(t.rows(), 7);
    let t = formats::read_raw(
        &path("cfx_monitor.csv"),
        FormatChoice::Auto,
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(col(&t, "Heading")[3], -176.0);
}

#[test]
fn a_fixed_format_overrides_detection() {
    // A CFX file read as the generic reader: same numbers, units still understood.
    let t = formats::read(
        &path("cfx_monitor.csv"),
        FormatChoice::Fixed(Format::Delimited),
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(t.format, Format::Delimited);
    assert_eq!(t.rows(), 5);
    // Fluent read as forceCoeffs is an error naming the file, not a panic.
    let e = formats::read(
        &path("fluent_rfile_iteration.out"),
        FormatChoice::Fixed(Format::OpenFoamForceCoeffs),
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("fluent_rfile_iteration.out"), "{e}");
}

#[test]
fn the_synthetic_exports_of_hydroid_simulate_read_back() {
    // cfd_exports/ holds what `hydroid simulate` writes in CFX and STAR-CCM+ layouts, and the
    // NPS AUV II helix as OpenFOAM sixDoFRigidBodyState output (docs/simulate.md).
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cfd_exports");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return;
    };
    for e in entries {
        let p = e.unwrap().path();
        // .hydroid-exports.json: simulate's record of the exports it wrote (docs/outputs.md)
        if p.file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with('.'))
        {
            continue;
        }
        let t = formats::read(&p, FormatChoice::Auto, &ReadOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(
            matches!(
                t.format,
                Format::Cfx
                    | Format::StarCcm
                    | Format::OpenFoamSixDof
                    | Format::OpenFoamForcesLegacy
            ),
            "{}",
            p.display()
        );
        assert!(t.rows() > 10, "{}", p.display());
        assert!(t.warnings.is_empty(), "{}: {:?}", p.display(), t.warnings);
        for c in &t.columns {
            assert!(c.unit.is_some(), "{}: {} has no unit", p.display(), c.name);
        }
    }
}

#[test]
fn every_fixture_is_covered() {
    let dir = path("");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let this = include_str!("formats.rs");
    for n in names {
        assert!(
            this.contains(&format!("\"{n}\"")),
            "fixture {n} has no test"
        );
    }
}

/// A blank-separated header whose units the blanks split off (`time (s)  u (m/s)`, `u [ m
/// s^-1 ]`) is the header, with its units, not a title; a line above the data that reads
/// like a header but does not fit the rows is kept as a title with a warning naming it.
#[test]
fn a_blank_separated_header_with_spaced_units_is_the_header() {
    let dir = tempfile::tempdir().unwrap();
    let rows = "0.0 1.0 0.5\n0.1 1.1 0.6\n0.2 1.2 0.7\n";
    for (name, head) in [
        ("round.txt", "time (s)  u (m/s)  r (deg/s)"),
        ("square.txt", "time [ s ]  u [ m s^-1 ]  r [ deg s^-1 ]"),
        (
            "commented.txt",
            "# time [ s ]  u [ m s^-1 ]  r [ deg s^-1 ]",
        ),
        ("mixed.txt", "time (s)\tu\tr (deg/s)"),
        ("one_unit.txt", "time   u (m/s)   r"),
    ] {
        let p = dir.path().join(name);
        std::fs::write(&p, format!("{head}\n{rows}")).unwrap();
        let t = formats::read(&p, FormatChoice::Auto, &ReadOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(t.names(), ["time", "u", "r"], "{name}");
        assert_eq!(t.time, Some(0), "{name}");
        assert!(t.warnings.is_empty(), "{name}: {:?}", t.warnings);
        if name != "one_unit.txt" {
            let r = col(&t, "r");
            assert!((r[0] - 0.5f64.to_radians()).abs() < 1e-12, "{name}: {r:?}");
        }
    }
    for (name, head) in [
        ("four_for_three.txt", "t u v w"),
        (
            "units_four_for_three.txt",
            "time (s)  u (m/s)  r (deg/s)  x (m)",
        ),
    ] {
        let p = dir.path().join(name);
        std::fs::write(&p, format!("{head}\n{rows}")).unwrap();
        let t = formats::read(&p, FormatChoice::Auto, &ReadOptions::default()).unwrap();
        assert_eq!(t.names(), ["col1", "col2", "col3"], "{name}");
        let w = t.warnings.join("\n");
        assert!(
            w.contains("line 1")
                && w.contains("reads like a header of 4 names")
                && w.contains("have 3 values"),
            "{name}: {w}"
        );
    }
}
