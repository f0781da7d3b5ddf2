//! Settings against a small dataset: each kind of edit, and each refusal at its setting.

use super::Settings;
use crate::diag::Code;
use crate::model::reader::read_model;

const DATASET: &str = "\
Slider
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/11, PART = 1
PART/2, MASS = 2.5, CM = 21, IP = 0.1, 0.1, 0.1
MARKER/21, PART = 2, QP = 0.3, 0, 0
JOINT/1, TRANSLATIONAL, I = 21, J = 11
SFORCE/1, TRANSLATION, I = 21, J = 11
, FUNCTION = -2000*(DX(21, 11) - 0.25)
, + IMPACT(DX(21, 11), VX(21, 11), 0.05, 1E6, 1.5, 200, 0.002)
ACCGRAV/JGRAV = -9.80665
END
";

fn applied(settings: &[&str]) -> String {
    let s = Settings::parse(settings).expect("settings parse");
    s.apply(DATASET).expect("settings apply")
}

fn refused(settings: &[&str]) -> Vec<(Code, String, String)> {
    let s = match Settings::parse(settings) {
        Ok(s) => s,
        Err((text, diags)) => {
            return diags
                .into_iter()
                .map(|d| (d.code, d.message, text[d.span].to_string()))
                .collect()
        }
    };
    let diags = s.apply(DATASET).expect_err("refused");
    diags
        .into_iter()
        .map(|d| (d.code, d.message, s.text()[d.span].to_string()))
        .collect()
}

#[test]
fn a_written_value_is_replaced_in_place() {
    let text = applied(&["PART/2.MASS=1.5"]);
    assert!(text.contains("PART/2, MASS=1.5, CM = 21"), "{text}");
    let read = read_model(&text);
    assert!(!read.has_errors());
    assert_eq!(text.lines().count(), DATASET.lines().count());
}

#[test]
fn an_expression_over_continuation_lines_is_replaced_whole() {
    let text = applied(&["SFORCE/1.FUNCTION=IMPACT(DX(21,11),VX(21,11),0.05,1E5,1.5,50,0.1)"]);
    assert!(!text.contains("-2000"), "{text}");
    assert!(
        text.contains("FUNCTION=IMPACT(DX(21,11),VX(21,11),0.05,1E5,1.5,50,0.1)"),
        "{text}"
    );
    assert!(!read_model(&text).has_errors());
}

#[test]
fn abbreviations_and_singletons_and_missing_fields() {
    // FUN abbreviates FUNCTION (written as the setting spells it); ACCGRAV has no id;
    // IP is added where it is not written.
    let text = applied(&["sfo/1.fun=5", "ACCGRAV.JGRAV=-1.62", "PART/2.CM=21"]);
    assert!(text.contains("FUN=5"), "{text}");
    assert!(!read_model(&text).has_errors());
    assert!(text.contains("JGRAV=-1.62"), "{text}");
    let text = applied(&["ACCGRAV.KGRAV=-1"]);
    assert!(text.contains("JGRAV = -9.80665, KGRAV=-1"), "{text}");
    assert!(!read_model(&text).has_errors());
}

#[test]
fn every_refusal_names_the_statement_at_the_setting() {
    let cases: &[(&str, &str, &str)] = &[
        (
            "SPRINGDAMPER/1.K=2E4",
            "the dataset has no SPRINGDAMPER/1",
            "SPRINGDAMPER/1",
        ),
        ("PART/9.MASS=1", "the dataset has no PART/9", "PART/9"),
        (
            "PART/2.COLOR=RED",
            "PART/2 takes no field COLOR that mbfx reads",
            "COLOR",
        ),
        (
            "PART/2.MASS=heavy",
            "PART/2.MASS: MASS: expected a number",
            "heavy",
        ),
        (
            "SFORCE/1.FUNCTION=DX(99, 11)",
            "SFORCE/1.FUNCTION: MARKER/99 is not defined",
            "99",
        ),
        ("PART/2.MASS", "no `=`", "PART/2.MASS"),
        ("PART/2.MASS=", "no value", "="),
        ("PART/2=1", "no `.FIELD`", "PART/2"),
        (
            "WIDGET/1.A=1",
            "no dataset statement is called `WIDGET`",
            "WIDGET/1",
        ),
        ("PART.MASS=1", "PART needs an id", "PART"),
        ("PART/x.MASS=1", "`x` is not a statement id", "PART/x"),
    ];
    for (setting, message, at) in cases {
        let got = refused(&[setting]);
        assert_eq!(got.len(), 1, "{setting}: {got:?}");
        let (code, msg, span) = &got[0];
        assert_eq!(*code, Code::BadSetting, "{setting}");
        assert!(msg.contains(message), "{setting}: {msg}");
        assert_eq!(span, at, "{setting}: {msg}");
    }
}

#[test]
fn a_misspelt_field_is_refused_naming_the_nearest() {
    // Issue 43 §3: MASSS was taken as the MASS it starts with, QPX as QP. A field longer
    // than the argument, or a typo of one, is refused at the field with the argument
    // the statement writes.
    let cases: &[(&str, &str, &str)] = &[
        ("PART/2.MASSS=1.5", "PART/2 takes no field MASSS", "MASS"),
        ("MARKER/21.QPX=0,0,0", "MARKER/21 takes no field QPX", "QP"),
        (
            "SFORCE/1.FUNCTON=5",
            "SFORCE/1 takes no field FUNCTON",
            "FUNCTION",
        ),
        ("PART/2.MAS=1.5", "", ""),
    ];
    for (setting, message, nearest) in cases {
        let field = setting
            .split_once('.')
            .unwrap()
            .1
            .split_once('=')
            .unwrap()
            .0;
        if message.is_empty() {
            // A true abbreviation is still taken, written as the setting spells it.
            assert!(applied(&[setting]).contains("MAS=1.5"), "{setting}");
            continue;
        }
        let got = refused(&[setting]);
        assert_eq!(got.len(), 1, "{setting}: {got:?}");
        let (code, msg, span) = &got[0];
        assert_eq!(*code, Code::BadSetting, "{setting}");
        assert!(msg.contains(message), "{setting}: {msg}");
        assert!(
            msg.ends_with(&format!("did you mean {nearest}?")),
            "{setting}: {msg}"
        );
        assert_eq!(span, field, "{setting}: {msg}");
    }
}

#[test]
fn a_field_set_twice_is_refused_at_the_second() {
    let got = refused(&["PART/2.MASS=1", "PART/2.MASS=2"]);
    assert_eq!(got.len(), 1, "{got:?}");
    assert!(got[0].1.contains("set twice"), "{got:?}");
}

#[test]
fn a_missing_field_added_twice_is_refused_at_the_second() {
    // Neither field is written on its marker; both settings would add it.
    for pair in [
        ["MARKER/11.QP=0,0,0", "MARKER/11.QP=1,0,0"],
        ["MARKER/21.REULER=0,0,0", "MARKER/21.REU=1,0,0"],
    ] {
        let got = refused(&pair);
        assert_eq!(got.len(), 1, "{pair:?}: {got:?}");
        assert!(got[0].1.contains("set twice"), "{pair:?}: {got:?}");
        assert_eq!(
            got[0].2,
            pair[1]
                .split_once('.')
                .unwrap()
                .1
                .split_once('=')
                .unwrap()
                .0
        );
    }
}

#[test]
fn no_settings_leave_the_text_alone() {
    let s = Settings::parse::<&str>(&[]).expect("empty");
    assert!(s.is_empty());
    assert_eq!(s.apply(DATASET).expect("no-op"), DATASET);
}
