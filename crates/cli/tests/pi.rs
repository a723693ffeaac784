//! `mcrender pi` as a user meets it: the lecture's table, the variance columns with
//! `--trials`, JSON, and exit code 2 with a clear message for input that measures nothing.

use std::process::{Command, Output};

fn mcrender(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mcrender"))
        .args(args)
        .output()
        .expect("mcrender runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn table_has_one_row_per_n_with_estimate_and_error() {
    let o = mcrender(&["pi", "--samples", "1,10,100,1000,10000"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 6, "{out}");
    assert!(lines[0].contains("N") && lines[0].contains("estimate of pi") && lines[0].contains("|error|"));
    for (line, n) in lines[1..].iter().zip([1u64, 10, 100, 1000, 10000]) {
        let cols: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(cols.len(), 3, "{line}");
        assert_eq!(cols[0].parse::<u64>().unwrap(), n);
        let estimate: f64 = cols[1].parse().unwrap();
        let error: f64 = cols[2].parse().unwrap();
        assert!((0.0..=4.0).contains(&estimate), "{line}");
        assert!((error - (estimate - std::f64::consts::PI).abs()).abs() < 2e-6, "{line}");
    }
}

#[test]
fn trials_add_mean_variance_and_a_nearly_constant_variance_times_n() {
    let o = mcrender(&["pi", "--samples", "100,1000,10000", "--trials", "400", "--seed", "5"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 5, "{out}");
    assert!(
        lines[0].contains("mean of 400") && lines[0].contains("variance x N"),
        "{out}"
    );
    for line in &lines[1..4] {
        let cols: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(cols.len(), 6, "{line}");
        let n: f64 = cols[0].parse().unwrap();
        let variance: f64 = cols[4].parse().unwrap();
        let vn: f64 = cols[5].parse().unwrap();
        assert!((variance * n / vn - 1.0).abs() < 2e-3, "{line}");
        assert!(
            (2.0..3.4).contains(&vn),
            "variance x N = {vn} is far from pi (4 - pi): {line}"
        );
    }
    assert!(lines[4].contains("pi (4 - pi) = 2.6968"), "{out}");
    // The seed fixes the table.
    let again = mcrender(&["pi", "--samples", "100,1000,10000", "--trials", "400", "--seed", "5"]);
    assert_eq!(out, stdout(&again));
}

#[test]
fn json_gives_the_same_rows() {
    let o = mcrender(&["pi", "--samples", "10,1000", "--trials", "3", "--json", "--seed", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("valid JSON");
    assert_eq!(v["seed"], 2);
    assert_eq!(v["trials"], 3);
    assert!((v["exact_variance_times_n"].as_f64().unwrap() - 2.6968).abs() < 1e-4);
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    for (row, n) in rows.iter().zip([10.0, 1000.0]) {
        assert_eq!(row["samples"].as_f64(), Some(n));
        let estimate = row["estimate"].as_f64().unwrap();
        assert!((row["abs_error"].as_f64().unwrap() - (estimate - std::f64::consts::PI).abs()).abs() < 1e-12);
        let vn = row["variance_times_n"].as_f64().unwrap();
        assert!((row["variance"].as_f64().unwrap() * n - vn).abs() < 1e-9 * vn.max(1.0));
        assert!(row["mean"].is_number());
    }
    // Without trials the rows carry no variance.
    let o = mcrender(&["pi", "--samples", "10", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("valid JSON");
    assert!(v["trials"].is_null() && v["rows"][0]["variance"].is_null(), "{v}");
}

#[test]
fn plot_option_writes_a_png() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pi.png");
    let o = mcrender(&[
        "pi",
        "--samples",
        "10,100,1000",
        "--trials",
        "50",
        "--plot",
        path.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&path).expect("a valid PNG").to_rgb8();
    assert_eq!(img.dimensions(), (800, 600));
    let o = mcrender(&[
        "pi",
        "--samples",
        "10",
        "--plot",
        dir.path().join("pi.jpg").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("expected extension png"), "{}", stderr(&o));
    assert!(
        stdout(&o).is_empty(),
        "the table was printed before the bad plot name was noticed"
    );
}

#[test]
fn bad_input_exits_with_code_2_and_says_why() {
    for (args, message) in [
        (&["pi", "--samples", "0"][..], "at least 1"),
        (&["pi", "--samples", "10,abc"][..], "positive whole number"),
        (&["pi", "--trials", "1"][..], "at least 2 trials"),
    ] {
        let o = mcrender(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(message), "{args:?}: {}", stderr(&o));
        assert!(stdout(&o).is_empty(), "{args:?} printed a table");
    }
}
