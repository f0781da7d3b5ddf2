//! Replays the fuzz seed corpora (`fuzz/corpus/<target>/`) through the fuzz targets' own
//! checking code, so stable `cargo test` covers what `cargo fuzz` would start from. Each
//! seed also yields a fixed set of deterministic mutations (byte flips, insertions of
//! dictionary tokens, deletions, truncations, duplications, splices with other seeds).
//! A missing or empty corpus folder fails the test: nothing passes silently.
//!
//! `check_cli` runs the whole `mbfx check` command; here it runs the `mbfx` binary (its
//! output captured, not printed), so it gets few mutations: each costs a process.

#[path = "../fuzz/fuzz_targets/spans.rs"]
mod spans;

#[path = "../fuzz/fuzz_targets/parse_check_body.rs"]
mod parse_check;

#[path = "../fuzz/fuzz_targets/interp_vs_jit_body.rs"]
mod interp_vs_jit;

#[path = "../fuzz/fuzz_targets/adm_check_body.rs"]
mod adm_check;

#[path = "../fuzz/fuzz_targets/check_cli_body.rs"]
mod check_cli;

#[path = "../fuzz/fuzz_targets/capi_sequences_body.rs"]
mod capi_sequences;

use std::path::{Path, PathBuf};

/// How one corpus folder is replayed.
struct Target {
    check: fn(&[u8]),
    /// The libFuzzer dictionary its mutations insert tokens from (`fuzz/<dict>.dict`).
    dict: &'static str,
    /// Mutations replayed per seed.
    mutations: usize,
    /// Mutations per seed larger than [`LARGE_SEED`] bytes: the 1000-deep parentheses of
    /// spec case I9 cost milliseconds per parse once mutated (error recovery over a deep
    /// parser stack), so they get fewer.
    mutations_large: usize,
}

const LARGE_SEED: usize = 512;

/// The replay of each fuzz target, by corpus folder name.
fn target(name: &str) -> Option<Target> {
    let t = |check, dict, mutations, mutations_large| Target {
        check,
        dict,
        mutations,
        mutations_large,
    };
    match name {
        "parse_check" => Some(t(parse_check::check_bytes, "parse_check", 300, 30)),
        "interp_vs_jit" => Some(t(interp_vs_jit::check_bytes, "interp_vs_jit", 300, 30)),
        // A dataset read, built, assembled and analysed: tens of microseconds each.
        "adm_check" => Some(t(adm_check::check_bytes, "adm_check", 40, 40)),
        "check_cli" => Some(t(check_cli_binary, "adm_check", 2, 2)),
        // A few compiles (some JIT) and evaluations per sequence: about a millisecond.
        "capi_sequences" => Some(t(capi_sequences::check_bytes, "capi_sequences", 300, 300)),
        _ => None,
    }
}

/// The `check_cli` checks with the command run as a process of the `mbfx` binary.
fn check_cli_binary(data: &[u8]) {
    check_cli::check_with(data, |args| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_mbfx"))
            .args(&args[1..])
            .output()
            .unwrap_or_else(|e| panic!("cannot run mbfx: {e}"));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        let code = out.status.code().unwrap_or(-1);
        // A check that ran to its end says so in a summary line.
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            code != 0 || stdout.contains(" errors, "),
            "{args:?}: exit 0 without a summary: {stdout}"
        );
        code
    });
}

fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz")
}

/// Every file of one corpus folder, sorted by name (so mutations are reproducible).
fn seeds(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let entries = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    let mut out: Vec<(String, Vec<u8>)> = entries
        .map(|e| {
            e.unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
                .path()
        })
        .filter(|p| p.is_file())
        .map(|p| {
            let bytes = std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            (
                p.file_name()
                    .unwrap_or_default()
                    .to_string_lossy()
                    .into_owned(),
                bytes,
            )
        })
        .collect();
    out.sort();
    out
}

/// Tokens of a libFuzzer dictionary (`"..."` lines with `\\`, `\"` and `\xNN` escapes).
fn dictionary(path: &Path) -> Vec<Vec<u8>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut tokens = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let quoted = line
            .find('"')
            .and_then(|a| line.rfind('"').filter(|&b| b > a).map(|b| &line[a + 1..b]));
        let Some(body) = quoted else {
            panic!(
                "{}:{}: not a dictionary entry: {line}",
                path.display(),
                n + 1
            );
        };
        let b = body.as_bytes();
        let mut tok = Vec::new();
        let mut i = 0;
        while i < b.len() {
            match (b[i], b.get(i + 1)) {
                (b'\\', Some(b'\\' | b'"')) => {
                    tok.push(b[i + 1]);
                    i += 2;
                }
                (b'\\', Some(b'x')) => {
                    let hex = body
                        .get(i + 2..i + 4)
                        .and_then(|h| u8::from_str_radix(h, 16).ok());
                    let Some(byte) = hex else {
                        panic!("{}:{}: bad \\x escape: {line}", path.display(), n + 1);
                    };
                    tok.push(byte);
                    i += 4;
                }
                (b'\\', _) => panic!("{}:{}: bad escape: {line}", path.display(), n + 1),
                (c, _) => {
                    tok.push(c);
                    i += 1;
                }
            }
        }
        assert!(!tok.is_empty(), "{}:{}: empty entry", path.display(), n + 1);
        tokens.push(tok);
    }
    tokens
}

/// SplitMix64: a small fixed-seed generator, so every run replays the same mutations.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (`n > 0`).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Applies one to four random edits to `input`.
fn mutate(input: &[u8], rng: &mut Rng, dict: &[Vec<u8>], others: &[(String, Vec<u8>)]) -> Vec<u8> {
    const BYTES: &[u8] = b"0123456789.+-*/%()[],:! \nEeDdxvtIF\\\0\xff";
    let mut out = input.to_vec();
    for _ in 0..1 + rng.below(4) {
        let len = out.len();
        let at = rng.below(len + 1);
        match rng.below(8) {
            0 if len > 0 => {
                let i = rng.below(len);
                out[i] ^= 1 << rng.below(8);
            }
            1 if len > 0 => {
                let i = rng.below(len);
                out[i] = BYTES[rng.below(BYTES.len())];
            }
            2 => out.insert(at, BYTES[rng.below(BYTES.len())]),
            3 => {
                let tok = &dict[rng.below(dict.len())];
                out.splice(at..at, tok.iter().copied());
            }
            4 if len > 0 => {
                let end = (at + 1 + rng.below(8)).min(len);
                out.drain(at.min(end)..end);
            }
            5 => out.truncate(at),
            6 if len > 0 => {
                let start = rng.below(len);
                let end = (start + 1 + rng.below(16)).min(len);
                let piece = out[start..end].to_vec();
                let to = rng.below(out.len() + 1);
                out.splice(to..to, piece);
            }
            _ => {
                let other = &others[rng.below(others.len())].1;
                let cut = rng.below(other.len() + 1);
                out.truncate(at);
                out.extend_from_slice(&other[cut..]);
            }
        }
    }
    out
}

/// Runs `check` on `input`, naming the input when it panics.
fn replay(check: fn(&[u8]), input: &[u8], what: &str) {
    if std::panic::catch_unwind(|| check(input)).is_err() {
        panic!(
            "fuzz check failed on {what}: {:?} (bytes {input:?})",
            String::from_utf8_lossy(input)
        );
    }
}

#[test]
fn seed_corpora_and_mutations_pass_the_fuzz_checks() {
    let root = fuzz_dir().join("corpus");
    let dirs = std::fs::read_dir(&root).unwrap_or_else(|e| panic!("{}: {e}", root.display()));
    let mut dirs: Vec<PathBuf> = dirs
        .map(|e| {
            e.unwrap_or_else(|e| panic!("{}: {e}", root.display()))
                .path()
        })
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    let names: Vec<String> = dirs
        .iter()
        .map(|d| {
            d.file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    for expected in [
        "adm_check",
        "capi_sequences",
        "check_cli",
        "interp_vs_jit",
        "parse_check",
    ] {
        assert!(
            names.iter().any(|n| n == expected),
            "no fuzz/corpus/{expected} in {}: {names:?}",
            root.display()
        );
    }
    for (dir, name) in dirs.iter().zip(&names) {
        let t = target(name)
            .unwrap_or_else(|| panic!("fuzz/corpus/{name}: no replay for this target here"));
        let dict_path = fuzz_dir().join(format!("{}.dict", t.dict));
        let dict = dictionary(&dict_path);
        assert!(
            dict.len() > 100,
            "{}: only {} entries",
            dict_path.display(),
            dict.len()
        );
        let seeds = seeds(dir);
        assert!(!seeds.is_empty(), "{}: no seed files", dir.display());
        let mut rng = Rng(0x6d62_6678_5eed_0001);
        for (file, bytes) in &seeds {
            replay(t.check, bytes, &format!("fuzz/corpus/{name}/{file}"));
            let count = if bytes.len() > LARGE_SEED {
                t.mutations_large
            } else {
                t.mutations
            };
            for m in 0..count {
                let input = mutate(bytes, &mut rng, &dict, &seeds);
                replay(t.check, &input, &format!("mutation {m} of {name}/{file}"));
            }
        }
    }
}

#[test]
fn mutations_are_deterministic() {
    let dict = vec![b"SIN(".to_vec()];
    let others = vec![("a".to_string(), b"1+2".to_vec())];
    let run = || {
        let mut rng = Rng(7);
        (0..50)
            .map(|_| mutate(b"STEP(t,0,0,1,5)", &mut rng, &dict, &others))
            .collect::<Vec<_>>()
    };
    assert_eq!(run(), run());
}

/// A campaign of `capi_sequences` without libFuzzer or a sanitizer, for a machine where
/// the AddressSanitizer build is out of reach: `MBFX_FUZZ_RUNS` sequences (default 10⁶),
/// each a random walk of mutations from a seed (restarted every 64 steps), printing the
/// count and the time. Run: `MBFX_FUZZ_RUNS=1000000 cargo test --release --test
/// fuzz_seeds -- --ignored --nocapture`.
#[test]
#[ignore = "a campaign of minutes: run it by hand (docs/testing.md)"]
fn capi_sequences_campaign() {
    let runs: usize = std::env::var("MBFX_FUZZ_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1_000_000);
    let dict = dictionary(&fuzz_dir().join("capi_sequences.dict"));
    let seeds = seeds(&fuzz_dir().join("corpus").join("capi_sequences"));
    let mut rng = Rng(0x6d62_6678_ca91_0002);
    let start = std::time::Instant::now();
    let mut input = Vec::new();
    for run in 0..runs {
        if run % 64 == 0 {
            input = seeds[rng.below(seeds.len())].1.clone();
        }
        input = mutate(&input, &mut rng, &dict, &seeds);
        input.truncate(1024);
        replay(
            capi_sequences::check_bytes,
            &input,
            &format!("campaign run {run}"),
        );
        if (run + 1) % 100_000 == 0 {
            println!("{} sequences in {:.0?}", run + 1, start.elapsed());
        }
    }
    println!("{runs} sequences in {:.1?}", start.elapsed());
}
