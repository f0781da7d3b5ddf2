//! `mbfx run --set`: a set value gives the run of the dataset edited by hand; a setting
//! that does not apply stops before any row with E0611 at the setting.

use super::{mbfx, scratch_file};

const SLIDER: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/slider.adm");

#[test]
fn a_set_value_runs_as_the_dataset_edited_by_hand() {
    let text = std::fs::read_to_string(SLIDER).expect("slider");
    let edited = text
        .replace("PART/2, MASS = 2.5,", "PART/2, MASS = 5,")
        .replace("- 15*VR(22, 11)", "- 40*VR(22, 11)");
    assert_ne!(edited, text);
    let by_hand = scratch_file("slider_by_hand.adm", edited.as_bytes());
    let common = ["--end", "0.5", "--probe", "x=DX(22, 11)"];
    let want = mbfx(&[&["run", by_hand.to_str().expect("utf-8 path")], &common[..]].concat());
    let got = mbfx(
        &[
            &["run", SLIDER][..],
            &common[..],
            &[
                "--set",
                "PART/2.MASS=5",
                "--set",
                "SFORCE/1.FUNCTION=-2000*(DM(22, 11) - 0.25) - 40*VR(22, 11) + IMPACT(DX(22, 11), VX(22, 11), 0.05, 1E6, 1.5, 200, 0.002)",
            ],
        ]
        .concat(),
    );
    assert_eq!(want.code, 0, "{}", want.describe());
    assert_eq!(got.code, 0, "{}", got.describe());
    assert_eq!(got.stdout, want.stdout);
    let plain = mbfx(&[&["run", SLIDER][..], &common[..]].concat());
    assert_ne!(plain.stdout, got.stdout, "the settings changed nothing");
}

#[test]
fn a_setting_that_does_not_apply_stops_the_run_at_the_setting() {
    for (setting, message, caret_column) in [
        (
            "SPRINGDAMPER/1.K=2E4",
            "the dataset has no SPRINGDAMPER/1",
            1,
        ),
        ("PART/2.COLOR=3", "PART/2 takes no field COLOR", 8),
        ("PART/2.MASS=heavy", "expected a number", 13),
        (
            "SFORCE/1.FUNCTION=DX(22, 99)",
            "MARKER/99 is not defined",
            26,
        ),
        ("PART/2.MASS", "no `=`", 1),
    ] {
        let run = mbfx(&[
            "run", SLIDER, "--end", "0.5", "--color", "never", "--set", setting,
        ]);
        assert_eq!(run.code, 1, "{setting}: {}", run.describe());
        assert!(run.stdout.is_empty(), "{setting}: rows were written");
        assert!(
            run.stderr.contains("[E0611] Error"),
            "{setting}: {}",
            run.stderr
        );
        assert!(run.stderr.contains(message), "{setting}: {}", run.stderr);
        let place = format!("--set:1:{caret_column} ]");
        assert!(
            run.stderr.contains(&place),
            "{setting}: no {place} in {}",
            run.stderr
        );
    }
}
