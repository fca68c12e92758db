//! Identification accuracy of hydroid's `spheroid3` model on data it did not make (issue 22):
//! the spheroid generator of tests/independent/spheroid.rs (Rasekh & Mahdi 2020 eq. 2-4 as
//! ../shared/docs/spheroid-hekf.md reads them, the bounded truth; own RK4 at 1 ms; the paper's
//! manoeuvre exported every 0.01 s like the CFD run, heading wrapped in degrees, with a CFD
//! monitor's noise), identified by `hydroid run` (as a library) with a configuration like
//! the bundled configs/spheroid.toml: the paper's six HEKF coefficients, the polar and surge
//! coefficients held at their true values (given in [coefficients] instead of the polar and
//! surge stages, so that only the HEKF is judged), hydroid's default tuning.

use crate::independent;

use independent::accuracy::identify;
use independent::spheroid::{self, Spheroid};

/// Measured: every estimate within 2 sigma of the truth, worst |z| 1.62 (Yrr +1.45 %); Yvd
/// +0.03 % (z -0.69), Nrd +0.27 % (z -0.71), Nvv +0.08 %, Nrr -0.00 %; Yrd (truth 0) flagged
/// as not determined. (When the test was written, before the noise model came from the
/// data: 2 of 6, with sigmas up to 5 times smaller; a record.) Asserted: all determined ones
/// within 2 sigma, and docs/validation.md's numbers at their printed digits.
#[test]
fn paper_manoeuvre_identifies_the_six_coefficients() {
    let body = Spheroid::bounded_truth();
    let run = spheroid::paper_manoeuvre(&body, 2020);
    let dir = tempfile::tempdir().unwrap();
    run.log.write_csv(dir.path(), "turn.csv");
    let config = format!(
        "title = \"spheroid: the paper's manoeuvre, independently generated\"\n\
         [vehicle]\nname = \"6:1 prolate spheroid\"\nmass = {m}\nlength = 1.2\ndiameter = 0.2\n\
         izz = {izz}\nreference_area = 0.0314159265\nreference_length = 1.0\n\
         [fluid]\nrho = 1025.0\nmu = 0.0009\n\
         [coefficients]\nXud = {xud}\nXuu = {xuu}\nXuv = {xuv}\nXvv = {xvv}\nYvv = {yvv}\n\
         Yuvd = {yuvd}\nYuvl = {yuvl}\nNuvl = {nuvl}\n\
         [hekf]\nmodel = \"spheroid3\"\npreset = \"hydroid\"\n\
         estimate = [\"Yvd\", \"Yrd\", \"Nrd\", \"Nvv\", \"Nrr\", \"Yrr\"]\n\
         [[hekf.runs]]\nname = \"paper manoeuvre\"\nfile = \"turn.csv\"\n\
         constants = {{ thrust = \"22 N\" }}\n[hekf.runs.columns]\ntime = \"Time\"\n\
         x = \"Position X\"\ny = \"Position Y\"\nyaw = \"Heading\"\nu = \"Velocity u\"\n\
         v = \"Velocity v\"\nr = \"Yaw Rate\"\n",
        m = body.mass,
        izz = body.izz,
        xud = body.xud,
        xuu = body.xuu,
        xuv = body.xuv,
        xvv = body.xvv,
        yvv = body.yvv,
        yuvd = body.yuvd,
        yuvl = body.yuvl,
        nuvl = body.nuvl,
    );
    let path = dir.path().join("spheroid.toml");
    std::fs::write(&path, config).unwrap();
    let o = identify(&path, &spheroid::paper_six_truth(&body));
    println!("{}", o.table());
    for w in &o.warnings {
        println!("warning: {w}");
    }
    o.assert_undetermined_flagged();
    assert_eq!(o.within_two_sigma(), (6, 6), "{}", o.table());
    // docs/validation.md: "worst z 1.62 (Yrr +1.45 %); Yvd +0.03 %, Nrd +0.27 %; Yrd (truth
    // 0) flagged"
    let worst = o
        .determined()
        .max_by(|a, b| a.z.abs().total_cmp(&b.z.abs()))
        .unwrap();
    let error = |n: &str| format!("{n} {:+.2} %", o.row(n).error_percent());
    assert_eq!(
        format!(
            "worst z {:.2} ({}); {}, {}; Yrd flagged {}",
            worst.z.abs(),
            error(&worst.name),
            error("Yvd"),
            error("Nrd"),
            o.row("Yrd").flagged
        ),
        "worst z 1.62 (Yrr +1.45 %); Yvd +0.03 %, Nrd +0.27 %; Yrd flagged true",
        "{}",
        o.table()
    );
}
