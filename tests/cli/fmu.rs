//! `mbfx fmu`: the FMU holds its four parts (the description, the library, the dataset
//! and the settings) with the interface asked for, and every bad input (no PINPUT, an
//! unknown name, an unwritable destination, no library, a dataset with errors) is a
//! message and exit 1 with nothing written. The library here is a stand-in file: what
//! it does inside an importer is tests/python/test_fmu.py's job.

use super::scratch_dir;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::Command;

const PLANT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/fmu_plant.adm");

/// The stand-in library's bytes.
const LIBRARY: &[u8] = b"\x7fELF stand-in for libmbfx_fmi.so";

/// Runs `mbfx fmu ARGS` with the stand-in library; exit code and stderr.
fn fmu(dir: &Path, args: &[&str]) -> (i32, String) {
    let library = dir.join("libmbfx_fmi.so");
    std::fs::write(&library, LIBRARY).expect("write the stand-in library");
    fmu_with(Some(&library), args)
}

fn fmu_with(library: Option<&Path>, args: &[&str]) -> (i32, String) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_mbfx"));
    command.arg("fmu").args(args).env_remove("MBFX_FMI_LIBRARY");
    if let Some(l) = library {
        command.env("MBFX_FMI_LIBRARY", l);
    }
    let out = command.output().expect("start mbfx");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{stderr}");
    (out.status.code().unwrap_or(-1), stderr)
}

/// The files of the zip at `path`, by name.
fn entries(path: &Path) -> Vec<(String, Vec<u8>)> {
    let file = std::fs::File::open(path).expect("the FMU");
    let mut zip = zip::ZipArchive::new(file).expect("a zip");
    (0..zip.len())
        .map(|i| {
            let mut f = zip.by_index(i).expect("an entry");
            let mut bytes = Vec::new();
            f.read_to_end(&mut bytes).expect("read an entry");
            (f.name().expect("a UTF-8 name").to_string(), bytes)
        })
        .collect()
}

fn text_of<'a>(files: &'a [(String, Vec<u8>)], name: &str) -> &'a str {
    let (_, bytes) = files
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("{name} missing"));
    std::str::from_utf8(bytes).expect("text")
}

fn path_text(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 path")
}

#[test]
fn the_fmu_holds_its_parts_with_the_plant_statements_as_interface() {
    let dir = scratch_dir("fmu");
    let out = dir.join("plant.fmu");
    let (code, stderr) = fmu(&dir, &[PLANT, "-o", path_text(&out), "--end", "2"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("inputs u; outputs y, v"), "{stderr}");
    let files = entries(&out);
    let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "modelDescription.xml",
            "binaries/linux64/plant.so",
            "resources/model.adm",
            "resources/settings.toml"
        ]
    );
    assert_eq!(files[1].1, LIBRARY);
    assert_eq!(
        text_of(&files, "resources/model.adm"),
        std::fs::read_to_string(PLANT).expect("the plant")
    );
    let xml = text_of(&files, "modelDescription.xml");
    for want in [
        r#"fmiVersion="2.0""#,
        r#"<CoSimulation modelIdentifier="plant" canHandleVariableCommunicationStepSize="true""#,
        r#"<ScalarVariable name="u" valueReference="0" description="VARIABLE/1" causality="input" variability="continuous">"#,
        r#"<Real start="0.0" unit="newton"/>"#,
        r#"<ScalarVariable name="y" valueReference="1" description="VARIABLE/2" causality="output""#,
        r#"<Real unit="meter"/>"#,
        r#"<Real unit="meter/second"/>"#,
        r#"<Unit name="newton"><BaseUnit kg="1" m="1" s="-2"/></Unit>"#,
        r#"<DefaultExperiment startTime="0" stopTime="2.0"/>"#,
    ] {
        assert!(xml.contains(want), "{want} missing from\n{xml}");
    }
    let settings = text_of(&files, "resources/settings.toml");
    let guid = xml
        .split(r#"guid=""#)
        .nth(1)
        .and_then(|s| s.split('"').next())
        .expect("a guid");
    assert!(
        settings.contains(&format!("guid = \"{guid}\"")),
        "{settings}"
    );
    // Nothing but the FMU is left in the folder (the temporary file was renamed).
    let mut left: Vec<String> = std::fs::read_dir(&dir)
        .expect("the folder")
        .map(|e| {
            e.expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    left.sort();
    assert_eq!(left, ["libmbfx_fmi.so", "plant.fmu"]);
}

#[test]
fn named_inputs_and_outputs_replace_the_plant_statements() {
    let dir = scratch_dir("fmu");
    let out = dir.join("other.fmu");
    let (code, stderr) = fmu(
        &dir,
        &[
            PLANT,
            "--inputs",
            "VARIABLE/1",
            "--outputs",
            "3,Y",
            "-o",
            path_text(&out),
        ],
    );
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("inputs u; outputs v, y"), "{stderr}");
    let files = entries(&out);
    assert!(files.iter().any(|(n, _)| n == "binaries/linux64/other.so"));
    let xml = text_of(&files, "modelDescription.xml");
    assert!(
        xml.contains(r#"name="v" valueReference="1""#)
            && xml.contains(r#"name="y" valueReference="2""#),
        "{xml}"
    );
}

/// A dataset without PINPUT and POUTPUT.
fn bare_plant(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(PLANT).expect("the plant");
    let bare: String = text
        .lines()
        .filter(|l| !l.starts_with("PINPUT") && !l.starts_with("POUTPUT"))
        .map(|l| format!("{l}\n"))
        .collect();
    let path = dir.join("bare.adm");
    std::fs::write(&path, bare).expect("write the dataset");
    path
}

#[test]
fn bad_input_is_a_message_and_exit_1_with_nothing_written() {
    let dir = scratch_dir("fmu");
    let out = dir.join("plant.fmu");
    // An FMU already there stays as it was when an export fails.
    std::fs::write(&out, b"an earlier FMU").expect("write");
    let bare = bare_plant(&dir);
    let broken = dir.join("broken.adm");
    std::fs::write(
        &broken,
        std::fs::read_to_string(PLANT).expect("the plant").replace(
            "SFORCE/2, TRANSLATION, I = 20, J = 12",
            "SFORCE/2, TRANSLATION, I = 99, J = 12",
        ),
    )
    .expect("write");
    let o = path_text(&out);
    let nowhere = dir.join("no/such/folder/p.fmu");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec![PLANT, "--inputs", "w", "-o", o], "`w` is not a VARIABLE of the dataset; it has u (VARIABLE/1), y (VARIABLE/2), v (VARIABLE/3)"),
        (vec![PLANT, "--outputs", "VARIABLE/7", "-o", o], "`VARIABLE/7` is not a VARIABLE"),
        (vec![path_text(&bare), "-o", o], "the dataset has no PINPUT: name the inputs with --inputs"),
        (vec![path_text(&bare), "--inputs", "u", "-o", o], "the dataset has no POUTPUT: name the outputs with --outputs"),
        (vec![PLANT, "--inputs", "u", "--outputs", "u,y", "-o", o], "VARIABLE/1 is both an input and an output"),
        (vec![path_text(&broken), "-o", o], "has errors: no FMU written"),
        (vec![PLANT, "--inputs", "v", "--outputs", "y", "-o", o], "input v cannot be set: VARIABLE/3 is not an input"),
        (vec![PLANT, "--error", "0", "-o", o], "--error 0 must be a positive number"),
        (vec![PLANT, "-o", path_text(&nowhere)], "cannot write"),
    ];
    for (args, want) in &cases {
        let (code, stderr) = fmu(&dir, args);
        assert_eq!(code, 1, "{args:?}: {stderr}");
        assert!(stderr.contains(want), "{args:?}: {want:?} not in\n{stderr}");
        assert_eq!(
            std::fs::read(&out).expect("the earlier FMU"),
            b"an earlier FMU"
        );
    }
    let (code, stderr) = fmu_with(Some(&dir.join("missing.so")), &[PLANT, "-o", o]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("cannot read the FMU's library"), "{stderr}");
    let mut left: Vec<String> = std::fs::read_dir(&dir)
        .expect("the folder")
        .map(|e| {
            e.expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    left.sort();
    assert_eq!(
        left,
        ["bare.adm", "broken.adm", "libmbfx_fmi.so", "plant.fmu"]
    );
}
