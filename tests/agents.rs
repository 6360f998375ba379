//! The agent table: every agent declared once, and no front end typing an agent's name.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::agent::mfec::Embedding;
use sec_playground::agent::mfec::MfecConfig;
use sec_playground::agent::{AgentInfo, AGENTS};
use sec_playground::experiment::settings::{self, page_agents};
use sec_playground::experiment::RunConfig;
use std::path::Path;

#[test]
fn every_kind_has_one_row_and_the_settings_follow_the_capabilities() {
    let keys: Vec<&str> = AGENTS.iter().map(|a| a.key).collect();
    let mut unique = keys.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), keys.len(), "keys are unique: {keys:?}");
    // Every kind of the table (not a list here, which a new agent would leave behind) has a row
    // for either MFEC embedding.
    for kind in AGENTS.iter().map(|a| a.kind) {
        for e in [Embedding::Autoencoder, Embedding::RandomProjection] {
            assert_eq!(AgentInfo::of(kind, e).kind, kind);
        }
    }
    assert_eq!(AgentInfo::find("mfec-xx").unwrap_err().field, "agent");
    // The page offers the agents it can run; the agent setting round-trips through the table.
    assert_eq!(
        page_agents(),
        keys.iter().copied().filter(|k| !AgentInfo::find(k).unwrap().native_only).collect::<Vec<_>>()
    );
    for key in page_agents() {
        let (mut cfg, mut seed) = settings::defaults();
        settings::apply(&mut cfg, &mut seed, "agent", key).unwrap();
        let row = AgentInfo::find(key).unwrap();
        assert_eq!(AgentInfo::of(cfg.kind, cfg.section::<MfecConfig>().embedding).key, key);
        assert_eq!(settings::to_settings(&cfg, seed)["agent"], key);
        assert!(cfg.validate().is_ok());
        // A setting applies to an agent exactly when its capabilities say so.
        for p in settings::params() {
            let applies = p.agents.is_empty() || p.agents.contains(&key);
            if ["alpha", "m", "bias"].contains(&p.key) {
                assert_eq!(applies, row.has_memory, "{} for {key}", p.key);
            }
            if p.key == "perception" {
                assert_eq!(
                    applies,
                    row.reads == sec_playground::agent::controller::Input::Embedding,
                    "perception for {key}"
                );
            }
        }
    }
    assert!(
        settings::apply(&mut RunConfig::default(), &mut 1, "agent", "dqn").is_err(),
        "native agents are not the page's"
    );
    let json = serde_json::to_value(AGENTS).unwrap();
    let sec = &json[0];
    assert_eq!(
        (sec["key"].as_str(), sec["hasMemory"].as_bool(), sec["unbiasedLabel"].as_str()),
        (Some("sec"), Some(true), Some("NSEC"))
    );
    assert_eq!(
        (json[2]["kind"].as_str(), json[2]["mfecEmbedding"].as_str()),
        (Some("mfec"), Some("random-projection"))
    );
}

/// Files under `dir` (recursively) ending in `ext`.
fn files(dir: &Path, ext: &str, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files(&path, ext, out);
        } else if path.extension().is_some_and(|e| e == ext) {
            out.push(path);
        }
    }
}

#[test]
fn no_front_end_types_an_agent_name() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut paths = Vec::new();
    files(&root.join("www"), "js", &mut paths);
    files(&root.join("crates/sec-py/python"), "py", &mut paths);
    // The experiment presets still name their arms' agents; they move into the core next
    // (issue 34, item 5), and leave this list then.
    let pending = ["presets.js"];
    paths.retain(|p| !pending.iter().any(|name| p.ends_with(name)));
    assert!(paths.len() > 10, "the front ends are where they were: {paths:?}");
    let mut found = Vec::new();
    for path in &paths {
        let text = std::fs::read_to_string(path).unwrap();
        for a in AGENTS {
            for quote in ['\'', '"', '`'] {
                let quoted = format!("{quote}{}{quote}", a.key);
                if text.contains(&quoted) {
                    found.push(format!("{}: {quoted}", path.strip_prefix(root).unwrap().display()));
                }
            }
        }
    }
    assert!(found.is_empty(), "agent names typed outside the agent table: {found:?}");
}

/// DQN's and ERLAM's sections belong to `crates/sec-dqn`, which this build does not link: the
/// core keeps them as a native run's configuration wrote them, refuses a section that is not an
/// object, writes none of its own nor any in another agent's run, and two configurations that
/// differ only in another agent's section make the same run.
#[test]
fn a_native_agents_section_is_kept_as_written_without_its_crate() {
    let text = r#"{"kind":"dqn","dqn":{"gamma":0.5,"batchSize":7},"erlam":{"nodes":40}}"#;
    let cfg = RunConfig::from_json(text).unwrap();
    let back: serde_json::Value = serde_json::to_value(&cfg).unwrap();
    assert_eq!(back["dqn"], serde_json::json!({"gamma": 0.5, "batchSize": 7}));
    assert_eq!(back["erlam"], serde_json::json!({"nodes": 40}));
    assert_eq!(RunConfig::from_value(back).unwrap(), cfg);

    let e = RunConfig::from_json(r#"{"dqn": 5}"#).unwrap_err();
    assert_eq!(e.field, "dqn", "{e}");
    let fresh = serde_json::to_value(RunConfig::default()).unwrap();
    assert!(fresh.get("dqn").is_none() && fresh.get("erlam").is_none(), "{fresh}");
    assert!(fresh.get("agent").is_some() && fresh.get("mfec").is_some(), "{fresh}");

    let sec = RunConfig::from_json(r#"{"dqn":{"gamma":0.5}}"#).unwrap();
    assert!(sec.same_run(&RunConfig::default()), "a SEC run does not read DQN's section");
    assert_ne!(sec, RunConfig::default(), "though the configuration holds it");
    assert!(serde_json::to_value(&sec).unwrap().get("dqn").is_none(), "nor write it");
    assert!(!cfg.same_run(&RunConfig { kind: cfg.kind, ..RunConfig::default() }), "a DQN run does");

    let mut set = RunConfig { kind: sec_playground::agent::AgentKind::Erlam, ..RunConfig::default() };
    set.sections.set_field("erlam", "nodes", 5000.into()).unwrap();
    assert_eq!(serde_json::to_value(&set).unwrap()["erlam"], serde_json::json!({"nodes": 5000}));
    assert_eq!(set.sections.set_field("nobody", "x", 1.into()).unwrap_err().field, "nobody");
}
