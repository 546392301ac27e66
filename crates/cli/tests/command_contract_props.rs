//! Every command on mutated inputs keeps the exit-code contract (issue 33): 0 done, 1 bad input,
//! 2 no plan / not valid, 64 usage; never a panic; exit 1 prints one `error:` line and writes
//! nothing; every plan file written follows `docs/plan.schema.json`.
//!
//! `PREGRASP_CONTRACT_CASES` sets the number of cases (default 48; docs/hardening.md quotes a
//! longer run).

mod common;

use std::path::Path;
use std::sync::OnceLock;

use common::mutate::{mutate_plan, mutate_scene};
use common::pregrasp;
use proptest::prelude::*;
use proptest::sample::Index;
use serde_json::Value;

/// A folder with the example scenes and meshes and a plan of the chair side, made once and
/// copied for every case.
fn template() -> &'static tempfile::TempDir {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        assert!(pregrasp(dir.path(), &["example", "write", "."])
            .status
            .success());
        let out = pregrasp(
            dir.path(),
            &["plan", "chair_side.toml", "-o", "plan.json", "--quiet"],
        );
        assert_eq!(out.status.code(), Some(0));
        dir
    })
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}

fn listing(dir: &Path) -> Vec<(String, u64)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            let meta = std::fs::metadata(&p).unwrap();
            if meta.is_dir() {
                stack.push(p.clone());
            }
            let modified = meta
                .modified()
                .ok()
                .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
                .map_or(0, |d| d.as_nanos() as u64);
            out.push((p.strip_prefix(dir).unwrap().display().to_string(), modified));
        }
    }
    out.sort();
    out
}

fn validator() -> &'static jsonschema::Validator {
    static V: OnceLock<jsonschema::Validator> = OnceLock::new();
    V.get_or_init(|| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/plan.schema.json");
        let schema: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        jsonschema::validator_for(&schema).unwrap()
    })
}

/// The commands, each with the inputs it reads mutated. `{scene}` / `{plan}` stand for the
/// mutated files; the outputs that are plan files are listed after `|`.
const COMMANDS: [(&str, &[&str]); 10] = [
    ("plan {scene} -o out.json --html out.html --quiet", &["out.json"]),
    ("axes {scene}", &[]),
    (
        "robustness {scene} --samples 1 --pos-mm 2 --json r.json --svg r.svg --write-plan rp.json",
        &["rp.json"],
    ),
    ("check {plan}", &[]),
    ("export {plan} -o ex", &[]),
    ("physics {plan}", &[]),
    ("view {plan} -o v.html", &[]),
    (
        "replan {plan} --scene chair_side.toml --object-pose 0.6881,0.4466,0.001,0,0,-0.9989,0.0471 -o re.json",
        &["re.json"],
    ),
    ("batch scenes -o bout", &["bout/chair_side.plan.json"]),
    ("plan {scene} -o out.json --max-plans {n}", &["out.json"]),
];

/// Numbers for the one numeric argument: some in range, some not a count at all.
const NUMBERS: [&str; 6] = ["1", "3", "0", "-1", "1e9", "x"];

fn run_case(command: usize, line: Index, kind: u8, value: Index, cut: Index, n: Index) {
    let dir = tempfile::tempdir().unwrap();
    copy_dir(template().path(), dir.path());
    let ex = pregrasp_examples::by_name("chair_side").unwrap();
    let scene_text = mutate_scene(&ex.scene_toml, line, kind, value, cut);
    std::fs::write(dir.path().join("mutated.toml"), &scene_text).unwrap();
    let plan: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("plan.json")).unwrap())
            .unwrap();
    std::fs::write(
        dir.path().join("mutated.json"),
        mutate_plan(&plan, line, kind, value),
    )
    .unwrap();
    std::fs::create_dir(dir.path().join("scenes")).unwrap();
    std::fs::write(dir.path().join("scenes/chair_side.toml"), &scene_text).unwrap();
    copy_dir(
        &dir.path().join("meshes"),
        &dir.path().join("scenes/meshes"),
    );

    let (template_args, plan_outputs) = COMMANDS[command];
    let args: Vec<String> = template_args
        .split(' ')
        .map(|a| {
            a.replace("{scene}", "mutated.toml")
                .replace("{plan}", "mutated.json")
                .replace("{n}", NUMBERS[n.index(NUMBERS.len())])
        })
        .collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let before = listing(dir.path());
    let out = pregrasp(dir.path(), &args);
    let code = out.status.code();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    assert!(
        matches!(code, Some(0 | 1 | 2 | 64)),
        "{args:?}: {code:?} {stderr}"
    );
    match code {
        Some(1) => {
            let errors = stderr.lines().filter(|l| l.starts_with("error:")).count();
            assert_eq!(errors, 1, "{args:?}: {stderr}");
            assert_eq!(
                listing(dir.path()),
                before,
                "{args:?} wrote on bad input: {stderr}"
            );
        }
        Some(64) => assert_eq!(listing(dir.path()), before, "{args:?}"),
        _ => {
            for name in plan_outputs {
                let path = dir.path().join(name);
                if let Ok(text) = std::fs::read_to_string(&path) {
                    let plan: Value = serde_json::from_str(&text).unwrap();
                    let errors: Vec<String> = validator()
                        .iter_errors(&plan)
                        .map(|e| e.to_string())
                        .collect();
                    assert!(errors.is_empty(), "{args:?}: {name}: {errors:?}");
                }
            }
        }
    }
}

fn cases() -> u32 {
    std::env::var("PREGRASP_CONTRACT_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(48)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    #[test]
    fn every_command_keeps_the_exit_code_contract_on_mutated_inputs(
        command in 0..COMMANDS.len(),
        line in any::<Index>(), kind in any::<u8>(), value in any::<Index>(),
        cut in any::<Index>(), n in any::<Index>()
    ) {
        run_case(command, line, kind, value, cut, n);
    }
}
