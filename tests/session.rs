//! The core's session layer, which the page, Python and the CLI are adapters over: one parser of
//! a RunConfig, stepping that gives the run's own log, views and explanations that add up.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::agent::SecConfig;
use sec_playground::experiment::{AgentKind, Run, RunConfig};
use sec_playground::session::{Applied, MemoryMap, Session, MAX_BATCH};

fn object_permanence() -> RunConfig {
    RunConfig { task: "object-permanence".into(), ..RunConfig::default() }
}

#[test]
fn one_parser_names_the_field_of_a_refused_config() {
    assert_eq!(RunConfig::from_json("{}").unwrap(), RunConfig::default());
    let cfg = RunConfig::from_json(r#"{"task": "detour", "agent": {"memory": {"tau": 0.5}}}"#).unwrap();
    assert_eq!((cfg.task.as_str(), cfg.section::<SecConfig>().memory.tau), ("detour", 0.5));
    let cases = [
        (r#"{"agent": {"memory": {"tau": "x"}}}"#, "agent.memory.tau", "line 1"),
        (r#"{"agent": {"memory": {"alfa": 1}}}"#, "agent.memory.alfa", "unknown field `alfa`"),
        (r#"{"agent": {"memory": {"tau": -1}}}"#, "tau", "out of range"),
        (r#"[1, 2]"#, "config", "is not an object"),
        (r#"{} {}"#, "config", "trailing characters"),
        (r#"{"task": "nowhere"}"#, "task", "nowhere"),
        ("", "config", "is not an object"),
    ];
    for (text, field, message) in cases {
        let e = RunConfig::from_json(text).unwrap_err();
        assert_eq!(e.field, field, "{text}: {e}");
        assert!(e.message.contains(message), "{text}: {e}");
    }
}

#[test]
fn a_session_steps_the_same_run_as_the_run_itself() {
    let mut run = Run::new(object_permanence(), 2).unwrap();
    let whole: Vec<String> = (0..18).map(|_| run.episode().to_json()).collect();
    let mut session = Session::new(object_permanence(), 2).unwrap();
    let mut stepped = Vec::new();
    let mut decisions = 0;
    while stepped.len() < 18 {
        let batch = session.run_decisions(37).unwrap();
        decisions += 37;
        stepped.extend(batch.iter().map(|m| m.to_json()));
    }
    assert_eq!(stepped[..18], whole[..]);
    assert_eq!(session.view().decisions, decisions);
    assert_eq!(session.run_decisions(0).unwrap_err().field, "decisions");
    assert_eq!(session.run_decisions(MAX_BATCH + 1).unwrap_err().field, "decisions");
}

#[test]
fn the_explanation_adds_up_and_the_views_show_the_memory() {
    let mut session = Session::new(object_permanence(), 2).unwrap();
    let mut found = None;
    for _ in 0..20_000 {
        session.step_decision();
        let e = session.explain();
        if !e.couplets.is_empty() {
            found = Some(e);
            break;
        }
    }
    let e = found.expect("memory selects couplets within 20000 decisions (golden seed 2 acts from episode 16)");
    let mut q = [0.0; 9];
    for c in &e.couplets {
        q[c.action.index()] += c.value;
    }
    for (a, (&sum, &q)) in q.iter().zip(&e.q).enumerate() {
        assert!((sum - q).abs() <= 1e-12 * sum.abs().max(1.0), "Q[{a}]: {sum} vs {q}");
    }
    let total: f64 = e.q.iter().sum();
    for (p, q) in e.p.iter().zip(&e.q) {
        assert!((p - q / total).abs() < 1e-12, "p = Q / sum Q");
    }
    let view = session.view();
    assert_eq!(view.selected, e.couplets.len());
    assert_eq!(view.p, Some(e.p));
    assert_eq!(view.embedding.as_ref().map(Vec::len), Some(20));
    assert_eq!((view.min_sequences, view.gate), (5, Some(0.01)));
    let n = session.config().section::<SecConfig>().memory.n;
    let (mut t, mut g, mut marks) = (Vec::new(), Vec::new(), Vec::new());
    session.memory_map(MemoryMap::T, &mut t);
    session.memory_map(MemoryMap::G, &mut g);
    session.selected_couplets(&mut marks);
    assert_eq!((t.len(), g.len()), (view.ltm * n, view.ltm * n));
    assert_eq!(marks.len(), e.couplets.len());
    assert!(marks.iter().all(|&i| (i as usize) < view.ltm * n));
    assert!(e.couplets.iter().all(|c| marks.contains(&(c.row * n as u32 + c.col))));
    assert_eq!("h".parse::<MemoryMap>().unwrap_err().field, "which");
}

#[test]
fn an_agent_without_a_memory_shows_none_and_refuses_memory_files() {
    let cfg = RunConfig { kind: AgentKind::Mfec, ..object_permanence() };
    let mut session = Session::new(cfg, 1).unwrap();
    session.run_decisions(10).unwrap();
    let view = session.view();
    assert_eq!((view.embedding, view.p, view.selected, view.min_sequences, view.gate), (None, None, 0, 0, None));
    assert!(session.explain().couplets.is_empty());
    let mut heat = vec![1.0];
    session.memory_map(MemoryMap::T, &mut heat);
    assert!(heat.is_empty());
    assert_eq!(session.save_memory().unwrap_err().field, "agent");
    assert!(session.load_memory(b"x").is_err());
}

#[test]
fn configure_applies_live_or_restarts_and_a_refusal_changes_nothing() {
    let mut session = Session::new(object_permanence(), 2).unwrap();
    session.run_decisions(300).unwrap();
    let mut live = object_permanence();
    live.section_mut::<SecConfig>().memory.tau = 0.5;
    assert_eq!(session.configure(live.clone()).unwrap(), Applied::Live);
    assert_eq!((session.view().decisions, session.explain().tau), (300, 0.5));
    let mut bad = live.clone();
    bad.section_mut::<SecConfig>().memory.tau = -1.0;
    assert!(session.configure(bad).is_err());
    assert_eq!(session.config(), &live);
    let mut restart = live.clone();
    restart.section_mut::<SecConfig>().memory.n = 20;
    assert_eq!(session.configure(restart.clone()).unwrap(), Applied::Restart);
    assert_eq!((session.view().decisions, session.config(), session.seed()), (0, &restart, 2));
    session.reset(Some(5)).unwrap();
    assert_eq!((session.seed(), session.config()), (5, &restart));
}
