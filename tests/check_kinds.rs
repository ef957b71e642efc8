//! `mechgen check` names how each block is solved: the default file's mechanisms and the
//! fixtures built from one-loop groups have no Newton block (issue 11), the dyad-driven six-bar
//! keeps its one 4×4 Newton block, and the scenes fixture's geared chain is Newton after a dyad.

use std::process::Command;

/// The `blocks:` line of each mechanism `mechgen check` prints for `file` (the compiled-in file
/// for `None`), as (name, blocks).
fn blocks(file: Option<&str>) -> Vec<(String, String)> {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_mechgen"));
    cmd.current_dir(env!("CARGO_MANIFEST_DIR")).arg("check");
    if let Some(f) = file {
        cmd.args(["--file", f]);
    }
    let out = cmd.output().expect("run mechgen");
    assert!(
        out.status.success(),
        "{file:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).expect("utf-8");
    let mut got = Vec::new();
    let mut name = None;
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("mechanism ") {
            name = rest.split(':').next().map(str::to_string);
        } else if let Some(rest) = line.trim_start().strip_prefix("blocks:") {
            got.push((name.take().expect("a name first"), rest.trim().to_string()));
        }
    }
    got
}

fn assert_blocks(file: Option<&str>, expected: &[(&str, &str)]) {
    let got = blocks(file);
    let expected: Vec<(String, String)> = expected
        .iter()
        .map(|(n, b)| (n.to_string(), b.to_string()))
        .collect();
    assert_eq!(got, expected, "{file:?}");
}

const RRR: &str = "2x2 [q2, q3] closed form (RRR)";
const SLIDER: &str = "1x1 [q2] closed form (one angle) -> 1x1 [sC] closed form (one length)";
const SHAPER: &str = "2x2 [s3, q3] closed form (RPR) -> 1x1 [q4] closed form (one angle) \
                      -> 1x1 [sE] closed form (one length)";
const SIXBAR_G: &str = "4x4 [q1, q2, q3, q5] newton";

#[test]
fn default_file_block_kinds() {
    assert_blocks(
        None,
        &[
            (
                "sixbar",
                "2x2 [q2, q3] closed form (RRR) -> 2x2 [q5, q6] closed form (RRR)",
            ),
            ("shaper", SHAPER),
            ("four_bar", RRR),
            ("slider_crank", SLIDER),
            ("rocker_four_bar", RRR),
            ("sixbar_g", SIXBAR_G),
        ],
    );
}

#[test]
fn fixture_block_kinds() {
    let slider_b = "1x1 [q2] closed form (one angle) -> 1x1 [sB] closed form (one length)";
    let plain = "1x1 [b] closed form (one angle) -> 1x1 [s] closed form (one length)";
    assert_blocks(
        Some("tests/fixtures/actuator.toml"),
        &[("actuator", "2x2 [qa, qr] closed form (RRR)")],
    );
    assert_blocks(
        Some("tests/fixtures/dyad_driven.toml"),
        &[("sixbar_g", SIXBAR_G)],
    );
    assert_blocks(
        Some("tests/fixtures/param_exprs.toml"),
        &[("derived_slider", slider_b)],
    );
    assert_blocks(
        Some("tests/fixtures/scenes.toml"),
        &[
            ("actuator", "2x2 [qa, qr] closed form (RRR)"),
            (
                "coupler_slider",
                "2x2 [q2, q3] closed form (RRR) -> 1x1 [qc] closed form (one angle) \
                 -> 1x1 [sx] closed form (one length)",
            ),
            // The gear term e(2*q6) is no closed-form kind: Newton after a dyad.
            (
                "geared_chain",
                "2x2 [q2, q3] closed form (RRR) -> 2x2 [q5, q6] newton",
            ),
        ],
    );
    assert_blocks(
        Some("tests/fixtures/wide_scale.toml"),
        &[("wide_four_bar", RRR)],
    );
    let mut names = vec![("sweep", slider_b)];
    for n in [
        "report",
        "generic",
        "runtime",
        "generated",
        "mechgen",
        "tick",
    ] {
        names.push((n, plain));
    }
    assert_blocks(Some("tests/fixtures/module_names.toml"), &names);
    // Every fixture is listed above: a new one must say its kinds.
    let mut files: Vec<String> =
        std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures"))
            .expect("fixtures")
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .filter(|n| n.ends_with(".toml"))
            .collect();
    files.sort();
    assert_eq!(
        files,
        [
            "actuator.toml",
            "dyad_driven.toml",
            "module_names.toml",
            "param_exprs.toml",
            "scenes.toml",
            "wide_scale.toml"
        ]
    );
}
