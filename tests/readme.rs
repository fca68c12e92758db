//! README.md's example table and its claim, from the run it describes: `hydroid run
//! configs/spheroid.toml` (the set-up's first command). Every number of the table's rows is
//! checked against results.json's comparison to the digits the README prints, and the sentence
//! under it ("within 2.3 sigma of the truth ...") against the truth the README lists.

use crate::common;

use serde_json::Value;

/// The README's text.
fn readme() -> String {
    std::fs::read_to_string(common::root().join("README.md")).unwrap()
}

/// Half a unit of the last printed digit of `s` (a number as the README prints it).
fn half_digit(s: &str) -> f64 {
    let decimals = s.split_once('.').map_or(0, |(_, d)| d.len());
    0.5 * 10f64.powi(-(decimals as i32))
}

/// `printed` (a README cell: a number, "-" or "12.3 %") against `actual`: equal to its printed
/// digits, or both absent.
fn agrees(printed: &str, actual: Option<f64>, what: &str) {
    let p = printed.trim().trim_end_matches('%').trim();
    match (p, actual) {
        ("-", None) => {}
        ("-", Some(a)) => panic!("{what}: README prints '-', the run gives {a}"),
        (p, Some(a)) => {
            let v: f64 = p.parse().unwrap_or_else(|_| panic!("{what}: '{p}'"));
            // a sigma or value printed to its digits: rounding, plus a hair for the binary form
            assert!(
                (v - a).abs() <= half_digit(p) * (1.0 + 1e-9),
                "{what}: README prints {p}, the run gives {a}"
            );
        }
        (p, None) => panic!("{what}: README prints {p}, the run gives none"),
    }
}

/// The table under "Part of the table the first command prints": rows of cells.
fn table(text: &str) -> Vec<Vec<String>> {
    let start = text
        .find("Part of the table the first")
        .expect("the README's example table");
    text[start..]
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .skip(2) // header and rule
        .map(|l| {
            l.trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_string())
                .collect()
        })
        .collect()
}

/// The truth the README lists: "(truth: Xud -1.164, Yvd -23.626, ...)".
fn truth(text: &str) -> Vec<(String, f64)> {
    let start = text.find("(truth: ").expect("the README's truth list") + "(truth: ".len();
    let end = start + text[start..].find(')').unwrap();
    text[start..end]
        .split(", ")
        .map(|p| {
            let (n, v) = p.split_once(' ').unwrap();
            (n.to_string(), v.trim().parse().unwrap())
        })
        .collect()
}

#[test]
fn the_example_table_and_its_claim_are_what_the_example_gives() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = common::run_config(&common::root().join("configs/spheroid.toml"), &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o.stderr));
    let r = common::json(&out.join("results.json"));
    let rows = r["comparison"].as_array().unwrap();
    let row = |name: &str| -> &Value {
        rows.iter()
            .find(|c| c["name"] == name)
            .unwrap_or_else(|| panic!("{name} not in the comparison"))
    };
    let text = readme();
    let cells = table(&text);
    assert!(cells.len() >= 8, "{cells:?}");
    for c in &cells {
        let [name, value, unit, source, fossen, vs_fossen, paper, vs_paper] = &c[..] else {
            panic!("a README row of 8 cells: {c:?}");
        };
        let x = row(name);
        let (v, s) = value.split_once(" ± ").expect("value ± sigma");
        agrees(v, x["value"].as_f64(), &format!("{name} value"));
        agrees(s, x["sigma"].as_f64(), &format!("{name} sigma"));
        assert_eq!(x["unit"], unit.as_str(), "{name}");
        assert_eq!(x["source"], source.as_str(), "{name}");
        agrees(fossen, x["analytic"].as_f64(), &format!("{name} Fossen"));
        agrees(
            vs_fossen,
            x["error_vs_analytic_pct"].as_f64(),
            &format!("{name} vs Fossen"),
        );
        agrees(paper, x["reference"].as_f64(), &format!("{name} paper"));
        agrees(
            vs_paper,
            x["error_vs_reference_pct"].as_f64(),
            &format!("{name} vs paper"),
        );
    }
    // "Every estimate lies within 2.3 sigma of the truth (Yvd 2.3, Xud 2.0, the others within 1"
    assert!(text.contains("within 2.3 sigma of the truth (Yvd 2.3, Xud 2.0, the others within 1"));
    for (name, t) in truth(&text) {
        let x = row(&name);
        let z = (x["value"].as_f64().unwrap() - t) / x["sigma"].as_f64().unwrap();
        match name.as_str() {
            "Yvd" => assert!((z.abs() - 2.3).abs() <= 0.05, "{name}: z {z}"),
            "Xud" => assert!((z.abs() - 2.0).abs() <= 0.05, "{name}: z {z}"),
            _ => assert!(z.abs() <= 1.0, "{name}: z {z}"),
        }
    }
}
