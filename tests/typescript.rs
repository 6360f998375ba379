//! The page's TypeScript declarations (`src/web/types.d.ts`, and each agent section's, declared
//! by its agent and merged into `RunConfig`: wasm-bindgen appends them all to the package's .d.ts)
//! hold every field the core hands to JS: each interface is checked against what the core
//! serialises (a configuration with every optional part present, the agent, task and settings
//! tables, an episode's metrics), and every choice's options against the settings table. A field
//! or option added to the core without its declaration is listed by name.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::agent::{AgentInfo, AGENTS};
use sec_playground::arena::TASKS;
use sec_playground::experiment::settings::{params, Kind};
use sec_playground::experiment::{Run, RunConfig};
use sec_playground::render::Surface;
use serde_json::Value;

const TYPES: &str = include_str!("../src/web/types.d.ts");

/// Every declaration the package's .d.ts gets: the adapter's file and each agent section's.
fn sources() -> Vec<&'static str> {
    let mut all = vec![TYPES];
    all.extend(AgentInfo::sections().map(|s| s.typescript));
    all
}

/// The bodies of every `export interface name { ... }` in `text`.
fn blocks(text: &str, name: &str) -> Vec<String> {
    let head = format!("export interface {name} {{");
    let mut out = Vec::new();
    for (at, _) in text.match_indices(&head) {
        let start = at + head.len();
        let mut depth = 1;
        let end = text[start..]
            .char_indices()
            .find(|&(_, c)| {
                depth += (c == '{') as i32 - (c == '}') as i32;
                depth == 0
            })
            .unwrap_or_else(|| panic!("interface {name} is not closed"))
            .0;
        out.push(text[start..start + end].to_string());
    }
    out
}

/// The body of the interface `name`, its declarations merged as TypeScript merges them.
fn interface(name: &str) -> String {
    let all: Vec<String> = sources().iter().flat_map(|t| blocks(t, name)).collect();
    assert!(!all.is_empty(), "no declaration of interface {name}");
    all.join("\n")
}

/// Whether `body` declares the field `key` (`key:` or `key?:`), outside comments.
fn declares(body: &str, key: &str) -> bool {
    let code: String = body
        .lines()
        .map(|l| l.split("/**").next().unwrap_or(""))
        .filter(|l| !l.trim_start().starts_with('*'))
        .collect::<Vec<_>>()
        .join("\n");
    code.match_indices(key).any(|(i, _)| {
        let before = code[..i].chars().last();
        let after = &code[i + key.len()..];
        !before.is_some_and(|c| c.is_alphanumeric() || c == '_') && (after.starts_with(':') || after.starts_with("?:"))
    })
}

/// Every key of `value`'s objects, with its path.
fn keys(value: &Value, path: &str, out: &mut Vec<(String, String)>) {
    if let Value::Object(map) = value {
        for (k, v) in map {
            let p = if path.is_empty() { k.clone() } else { format!("{path}.{k}") };
            out.push((p.clone(), k.clone()));
            keys(v, &p, out);
        }
    }
}

fn missing(name: &str, value: &Value) -> Vec<String> {
    let body = &interface(name);
    let mut all = Vec::new();
    keys(value, "", &mut all);
    all.into_iter().filter(|(_, k)| !declares(body, k)).map(|(p, _)| format!("{name}.{p}")).collect()
}

#[test]
fn every_field_the_core_hands_to_js_is_declared() {
    // Every optional part present: the textured surface (left out of the JSON when flat), a
    // scale override, an arena file (left out when absent; not validated here).
    let cfg = RunConfig {
        surface: Surface::Textured,
        embedding_scale: Some(2.0),
        arena: Some("arenas: {}".into()),
        ..RunConfig::default()
    };
    let cfg_json = serde_json::to_value(&cfg).unwrap();
    let mut run =
        Run::new(RunConfig { task: "object-permanence".into(), t: Some(50), ..RunConfig::default() }, 1).unwrap();
    let metrics = serde_json::to_value(run.episode()).unwrap();
    let mut gaps = Vec::new();
    gaps.extend(missing("RunConfig", &cfg_json));
    gaps.extend(missing("EpisodeMetrics", &metrics));
    for a in AGENTS {
        gaps.extend(missing("AgentInfo", &serde_json::to_value(a).unwrap()));
    }
    for t in &TASKS {
        gaps.extend(missing("TaskInfo", &serde_json::to_value(t).unwrap()));
    }
    for p in params() {
        gaps.extend(missing("Param", &serde_json::to_value(&p).unwrap()));
    }
    gaps.sort();
    gaps.dedup();
    assert!(gaps.is_empty(), "src/web/types.d.ts does not declare:\n{}", gaps.join("\n"));
}

#[test]
fn every_option_and_group_of_the_settings_is_in_the_declarations() {
    let run_config = interface("RunConfig");
    let param = interface("Param");
    let mut gaps = Vec::new();
    for p in params() {
        if !param.contains(&format!("\"{}\"", p.group)) {
            gaps.push(format!("Param.group \"{}\" (of {})", p.group, p.key));
        }
        let Kind::Choice { options } = &p.kind else { continue };
        // The task and agent choices are names from tables (strings); the others are enums.
        if ["task", "agent"].contains(&p.key) {
            continue;
        }
        for o in options {
            if !run_config.contains(&format!("\"{o}\"")) {
                gaps.push(format!("RunConfig: option \"{o}\" of {}", p.key));
            }
        }
    }
    for a in AGENTS {
        let reads = serde_json::to_value(a.reads).unwrap();
        if !interface("AgentInfo").contains(&reads.to_string()) {
            gaps.push(format!("AgentInfo.reads {reads}"));
        }
    }
    assert!(gaps.is_empty(), "src/web/types.d.ts does not declare:\n{}", gaps.join("\n"));
}

#[test]
fn each_agent_section_declares_itself_under_its_key() {
    for spec in AgentInfo::sections() {
        if (spec.default)().to_value().is_null() {
            // A native agent's (`SectionSpec::native`): never written here, so never declared.
            assert_eq!(spec.typescript, "", "{}", spec.key);
            continue;
        }
        let decl = blocks(spec.typescript, "RunConfig");
        assert_eq!(decl.len(), 1, "{}: one `export interface RunConfig {{ ... }}`", spec.key);
        assert!(declares(&decl[0], spec.key), "{}'s declaration is under its key", spec.key);
        assert!(blocks(TYPES, "RunConfig").iter().all(|b| !declares(b, spec.key)), "{} is declared once", spec.key);
    }
}

#[test]
fn the_check_sees_a_missing_field() {
    assert!(declares("  a?: number; bc: string;", "bc") && declares("a?: number", "a"));
    assert!(!declares("  abc?: number; /** b: x */", "b"));
    let v = serde_json::json!({"task": 1, "notDeclared": {"inner": 2}});
    assert_eq!(missing("RunConfig", &v), ["RunConfig.notDeclared", "RunConfig.notDeclared.inner"]);
}
