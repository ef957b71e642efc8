//! Runs the simulator and holds every cell of its output to the closed-form reference it carries
//! (`reference/ticks.csv`, mpmath at 40 digits, `reference/make_reference.py`).

use std::process::Command;

fn table(text: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header = lines
        .next()
        .expect("header")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|c| c.parse().expect("a number")).collect())
        .collect();
    (header, rows)
}

#[test]
fn output_agrees_with_the_reference() {
    let out = Command::new(env!("CARGO_BIN_EXE_simulator"))
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (header, rows) = table(&String::from_utf8(out.stdout).expect("utf-8"));
    let reference = concat!(env!("CARGO_MANIFEST_DIR"), "/reference/ticks.csv");
    let (want_header, want) = table(&std::fs::read_to_string(reference).expect("reference"));
    assert_eq!(header, want_header);
    assert_eq!(rows.len(), 101);
    assert_eq!(rows.len(), want.len());
    let mut worst = 0.0f64;
    for (i, (row, want)) in rows.iter().zip(&want).enumerate() {
        for (c, (&got, &w)) in row.iter().zip(want).enumerate() {
            // Relative to the column's scale (rates reach 4, accelerations 25).
            let err = (got - w).abs() / (1.0 + w.abs());
            worst = worst.max(err);
            assert!(err <= 1e-11, "row {i}, {}: {got} against {w}", header[c]);
        }
    }
    assert!(worst > 0.0, "the comparison compared something");
}
