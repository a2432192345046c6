//! The documentation cannot drift from the code: every field the scene parser accepts and
//! every allowed value of every option is in `docs/scenes.md`, every flag of every command
//! is in `docs/cli.md`, and every `impact ...` command quoted in a fenced code block of the
//! README or `docs/` parses with the real command line (clap, run as `impact <args> --help`:
//! each argument before `--help` is parsed and its value validated, nothing is run).
use impact_core::interior::InteriorRule;
use impact_core::options::*;
use impact_core::scene::{
    BoundarySpec, DgmpmSpec, Domain, EdgeSpec, FemSpec, InitialSpec, LineSpec, MaterialSpec,
    MetricsSpec, MpmSpec, PlaneWaveKind, PlaneWaveSpec, SidesSpec, StandingWaveSpec, TimeSpec,
};
use impact_core::Scene;
use serde::de::{self, Deserialize, Visitor};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A deserializer that only records the field names a derived `Deserialize` asks for
/// (`deserialize_struct`'s `fields`), then stops: the parser's own list of accepted keys.
struct FieldNames(Vec<&'static str>);

#[derive(Debug)]
struct Stop;
impl std::fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("field names recorded")
    }
}
impl std::error::Error for Stop {}
impl de::Error for Stop {
    fn custom<T: std::fmt::Display>(_: T) -> Self {
        Stop
    }
}

impl<'de> de::Deserializer<'de> for &mut FieldNames {
    type Error = Stop;
    fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Stop> {
        Err(Stop)
    }
    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        fields: &'static [&'static str],
        _: V,
    ) -> Result<V::Value, Stop> {
        self.0.extend_from_slice(fields);
        Err(Stop)
    }
    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
        ignored_any
    }
}

/// The keys the scene parser accepts for `T`.
fn fields<T: for<'de> Deserialize<'de>>() -> Vec<&'static str> {
    let mut names = FieldNames(Vec::new());
    let _ = T::deserialize(&mut names);
    names.0
}

/// The section of `doc` under the heading that names `type_name` in backticks, up to the
/// next heading.
fn section<'a>(doc: &'a str, type_name: &str) -> &'a str {
    let tag = format!("(`{type_name}`)");
    let start = doc
        .find(&format!("{tag}\n"))
        .unwrap_or_else(|| panic!("docs/scenes.md has no heading ending in {tag}"));
    let body = &doc[start..];
    let end = body[1..].find("\n#").map_or(body.len(), |i| i + 1);
    &body[..end]
}

/// Every struct of the scene file, by its Rust name, with the keys its parser accepts.
fn scene_tables() -> Vec<(&'static str, Vec<&'static str>)> {
    vec![
        ("Scene", fields::<Scene>()),
        ("Domain", fields::<Domain>()),
        ("MaterialSpec", fields::<MaterialSpec>()),
        ("BoundarySpec", fields::<BoundarySpec>()),
        ("SidesSpec", fields::<SidesSpec>()),
        ("EdgeSpec", fields::<EdgeSpec>()),
        ("TimeSpec", fields::<TimeSpec>()),
        ("InitialSpec", fields::<InitialSpec>()),
        ("StandingWaveSpec", fields::<StandingWaveSpec>()),
        ("PlaneWaveSpec", fields::<PlaneWaveSpec>()),
        ("DgmpmSpec", fields::<DgmpmSpec>()),
        ("MpmSpec", fields::<MpmSpec>()),
        ("FemSpec", fields::<FemSpec>()),
        ("MetricsSpec", fields::<MetricsSpec>()),
        ("LineSpec", fields::<LineSpec>()),
    ]
}

/// Every option enum, by its Rust name, with its allowed names.
fn option_names() -> Vec<(&'static str, &'static [&'static str])> {
    vec![
        ("MethodKind", MethodKind::NAMES),
        ("Integrator", Integrator::NAMES),
        ("PointUpdate", PointUpdate::NAMES),
        ("TransverseFlux", TransverseFlux::NAMES),
        ("RiemannSolver", RiemannSolver::NAMES),
        ("WaveLimiter", WaveLimiter::NAMES),
        ("SchemeOrder", SchemeOrder::NAMES),
        ("StressUpdate", StressUpdate::NAMES),
        ("MpmFrame", MpmFrame::NAMES),
        ("MpmShape", MpmShape::NAMES),
        ("MpmTransfer", MpmTransfer::NAMES),
        ("LoadDirection", LoadDirection::NAMES),
        ("MaterialModel", MaterialModel::NAMES),
        ("EdgeKind", EdgeKind::NAMES),
        ("LoadShape", LoadShape::NAMES),
        ("LayoutKind", LayoutKind::NAMES),
        ("SegmentCover", SegmentCover::NAMES),
        ("EdgeTreatment", EdgeTreatment::NAMES),
        ("InteriorRule", InteriorRule::NAMES),
        ("PlaneWaveKind", PlaneWaveKind::NAMES),
    ]
}

/// Every `.rs` file under `dir`.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The names of the items following `marker` in impact-core's sources: the structs after
/// `#[serde(deny_unknown_fields)]`, the enums opened by `option_enum! {`.
fn declared_after(marker: &str, keyword: &str) -> Vec<String> {
    let mut files = Vec::new();
    rust_files(&root().join("crates/impact-core/src"), &mut files);
    let mut names = Vec::new();
    for file in files {
        let text = read(&file);
        let mut rest = text.as_str();
        while let Some(i) = rest.find(marker) {
            rest = &rest[i + marker.len()..];
            let item = rest
                .lines()
                .map(str::trim)
                .find(|l| !l.is_empty() && !l.starts_with("///") && !l.starts_with("#["))
                .unwrap_or("");
            let item = item.strip_prefix(keyword).unwrap_or(item);
            let name: String = item
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            names.push(name);
        }
    }
    names
}

#[test]
fn every_scene_table_and_option_of_the_code_is_listed_here() {
    let tables: Vec<&str> = scene_tables().iter().map(|t| t.0).collect();
    for name in declared_after("#[serde(deny_unknown_fields)]", "pub struct ") {
        assert!(
            tables.contains(&name.as_str()),
            "scene table {name} is parsed but not in tests/docs.rs's list (nor, likely, in docs/scenes.md)"
        );
    }
    let options: Vec<&str> = option_names().iter().map(|o| o.0).collect();
    for name in declared_after("option_enum! {", "") {
        assert!(
            options.contains(&name.as_str()),
            "option {name} is declared but not in tests/docs.rs's list (nor, likely, in docs/scenes.md)"
        );
    }
}

#[test]
fn docs_scenes_holds_every_field_the_parser_accepts() {
    let doc = read(&root().join("docs/scenes.md"));
    for (type_name, keys) in scene_tables() {
        assert!(!keys.is_empty(), "{type_name}: no fields recorded");
        let text = section(&doc, type_name);
        let documented: Vec<&str> = text
            .lines()
            .filter_map(|l| l.strip_prefix("| `"))
            .filter_map(|l| l.split('`').next())
            .collect();
        for key in &keys {
            assert!(
                documented.contains(key),
                "docs/scenes.md, section ({type_name}): field `{key}` is accepted by the parser but has no row"
            );
        }
        for row in &documented {
            assert!(
                keys.contains(row),
                "docs/scenes.md, section ({type_name}): `{row}` is documented but the parser refuses it (accepted: {keys:?})"
            );
        }
    }
}

#[test]
fn docs_scenes_lists_exactly_the_allowed_values_of_every_option() {
    let doc = read(&root().join("docs/scenes.md"));
    for (type_name, names) in option_names() {
        let prefix = format!("| `{type_name}` |");
        let row = doc
            .lines()
            .find(|l| l.starts_with(&prefix))
            .unwrap_or_else(|| panic!("docs/scenes.md has no row `{prefix}`"));
        let values = row.split('|').nth(2).unwrap();
        // the backticked values, in order
        let listed: Vec<String> = values
            .split('`')
            .skip(1)
            .step_by(2)
            .map(|v| v.trim_matches('"').to_string())
            .collect();
        assert_eq!(
            listed, names,
            "docs/scenes.md: the allowed values of {type_name}"
        );
    }
}

/// The commands quoted in fenced code blocks of a Markdown text: lines starting with
/// `impact `, `$ impact ` or `cargo run --release ... -- `, joined over `\` continuations,
/// without trailing `#` comments; each as its arguments after the program name.
fn quoted_commands(markdown: &str) -> Vec<(String, Vec<String>)> {
    let mut commands = Vec::new();
    let mut in_fence = false;
    let mut pending = String::new();
    for line in markdown.lines() {
        if line.trim_start().starts_with("```") {
            in_fence = !in_fence;
            continue;
        }
        if !in_fence {
            continue;
        }
        let line = if pending.is_empty() {
            line.trim()
        } else {
            line
        };
        pending.push_str(line.trim());
        if pending.ends_with('\\') {
            pending.pop();
            pending.push(' ');
            continue;
        }
        let full = std::mem::take(&mut pending);
        let text = full.strip_prefix("$ ").unwrap_or(&full);
        let args = if let Some(rest) = text.strip_prefix("impact ") {
            rest.to_string()
        } else if text.starts_with("cargo run --release") && text.contains(" -- ") {
            text.split_once(" -- ").unwrap().1.to_string()
        } else {
            continue;
        };
        let args = args.split(" #").next().unwrap().trim().to_string();
        // the first shell word boundary: a pipe or a redirect ends the command
        let args = args.split(" | ").next().unwrap().trim().to_string();
        commands.push((text.to_string(), split_words(&args)));
    }
    commands
}

/// Shell words: spaces split, single and double quotes group.
fn split_words(text: &str) -> Vec<String> {
    let mut words = Vec::new();
    let mut word = String::new();
    let mut quote = None;
    let mut any = false;
    for c in text.chars() {
        match (quote, c) {
            (None, '"' | '\'') => {
                quote = Some(c);
                any = true;
            }
            (Some(q), c) if c == q => quote = None,
            (None, ' ') => {
                if any {
                    words.push(std::mem::take(&mut word));
                    any = false;
                }
            }
            _ => {
                word.push(c);
                any = true;
            }
        }
    }
    if any {
        words.push(word);
    }
    words
}

fn markdown_files() -> Vec<PathBuf> {
    let mut files = vec![root().join("README.md"), root().join("BENCHMARKS.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    files
}

fn impact_help(args: &[String]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_impact"))
        .args(args)
        .arg("--help")
        .output()
        .unwrap()
}

#[test]
fn every_command_quoted_in_the_docs_parses() {
    let mut count = 0;
    let mut failures = Vec::new();
    for file in markdown_files() {
        for (line, args) in quoted_commands(&read(&file)) {
            // placeholders (`<scene>`, `<m>`) stand for a value the reader supplies
            if args.iter().any(|a| a.contains('<')) {
                continue;
            }
            count += 1;
            let o = impact_help(&args);
            if !o.status.success() {
                failures.push(format!(
                    "{}: `{line}`:\n{}",
                    file.strip_prefix(root()).unwrap().display(),
                    String::from_utf8_lossy(&o.stderr)
                ));
            }
        }
    }
    assert!(count > 50, "only {count} commands found in the docs");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn quoted_commands_are_read_as_a_shell_would() {
    let md = "```sh\nimpact run bar --out \"a b\"   # note\n$ impact check plate \\\n    --quiet\ncargo run --release --features hdf5 -- run plate\nls\n```\nimpact outside\n";
    let got: Vec<Vec<String>> = quoted_commands(md).into_iter().map(|c| c.1).collect();
    assert_eq!(
        got,
        vec![
            vec!["run", "bar", "--out", "a b"],
            vec!["check", "plate", "--quiet"],
            vec!["run", "plate"],
        ]
    );
    // a bad flag or value is caught by the same route the docs' commands take
    for bad in [
        &["run", "bar", "--integrator", "rk9"][..],
        &["run", "bar", "--no-such-flag"],
    ] {
        let args: Vec<String> = bad.iter().map(|s| s.to_string()).collect();
        assert!(!impact_help(&args).status.success(), "{bad:?} parsed");
    }
}

/// The subcommands listed under `Commands:` in a help text.
fn subcommands(help: &str) -> Vec<String> {
    help.split("Commands:")
        .nth(1)
        .map(|s| {
            s.lines()
                .skip(1)
                .take_while(|l| l.starts_with("  "))
                .filter_map(|l| l.split_whitespace().next())
                .filter(|c| *c != "help")
                .map(str::to_string)
                .collect()
        })
        .unwrap_or_default()
}

#[test]
fn docs_cli_names_every_flag_of_every_command() {
    let doc = read(&root().join("docs/cli.md"));
    let help = |args: &[String]| String::from_utf8_lossy(&impact_help(args).stdout).into_owned();
    let mut queue: Vec<Vec<String>> = vec![vec![]];
    let mut missing = Vec::new();
    let mut seen = 0;
    while let Some(path) = queue.pop() {
        let text = help(&path);
        for sub in subcommands(&text) {
            let mut next = path.clone();
            next.push(sub);
            queue.push(next);
        }
        if path.is_empty() {
            continue;
        }
        let command = format!("impact {}", path.join(" "));
        assert!(
            doc.contains(&command),
            "docs/cli.md never names `{command}`"
        );
        seen += 1;
        for word in text.split(|c: char| !(c.is_alphanumeric() || c == '-')) {
            let Some(flag) = word.strip_prefix("--") else {
                continue;
            };
            if flag.is_empty() || flag == "help" || flag == "version" {
                continue;
            }
            if !doc.contains(&format!("--{flag}")) {
                missing.push(format!("{command} --{flag}"));
            }
        }
    }
    assert!(seen >= 6, "only {seen} commands found in `impact --help`");
    missing.sort();
    missing.dedup();
    assert!(
        missing.is_empty(),
        "flags missing from docs/cli.md: {missing:?}"
    );
}

/// Every test file runs: with `autotests = false` (each crate's integration tests are one
/// binary, `tests/integration.rs`) a file under a crate's `tests/` that is neither a `mod`
/// of that binary nor a `[[test]]` target of the crate's Cargo.toml would build and run
/// nowhere, silently.
#[test]
fn every_test_file_is_a_module_or_a_target() {
    let crates = std::fs::read_dir(root().join("crates")).unwrap();
    let dirs = std::iter::once(root()).chain(crates.map(|entry| entry.unwrap().path()));
    let mut missing = Vec::new();
    for dir in dirs {
        let tests = dir.join("tests");
        let Ok(files) = std::fs::read_dir(&tests) else {
            continue;
        };
        let manifest = read(&dir.join("Cargo.toml"));
        let harness = std::fs::read_to_string(tests.join("integration.rs")).unwrap_or_default();
        for file in files {
            let path = file.unwrap().path();
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let stem = path.file_stem().unwrap().to_str().unwrap().to_string();
            let auto = !manifest.contains("autotests = false");
            let target = manifest.contains(&format!("path = \"tests/{stem}.rs\""));
            let module = harness.lines().any(|l| l.trim() == format!("mod {stem};"));
            if !(auto || target || module) {
                missing.push(path.display().to_string());
            }
        }
    }
    assert!(
        missing.is_empty(),
        "test files that run nowhere (add `mod <file>;` to tests/integration.rs): {missing:?}"
    );
}
