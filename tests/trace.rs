//! The trace command's core: recorded events through the contextual layer, internals out.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::agent::SecConfig;
use sec_playground::encoder::PerceptionKind;
use sec_playground::experiment::trace::{parse_event, trace, Event, TraceLine};
use sec_playground::experiment::{Run, RunConfig};

fn run_trace(cfg: &SecConfig, seed: u64, input: &str) -> Result<Vec<TraceLine>, String> {
    let mut out = Vec::new();
    trace(cfg, None, seed, input.as_bytes(), &mut out).map_err(|e| e.to_string())?;
    Ok(String::from_utf8(out).unwrap().lines().map(|l| serde_json::from_str(l).unwrap()).collect())
}

fn decision(x: f32) -> String {
    format!(r#"{{"event":"decision","embedding":{:?}}}"#, [x; 20].to_vec())
}

#[test]
fn a_hand_made_stream_shows_selection_and_the_sequential_bias() {
    let cfg =
        SecConfig { memory: sec_playground::memory::MemoryConfig { n: 3, ..Default::default() }, ..Default::default() };
    // Episode 1: states 1, 2, 3, then the goal. The STM then holds [start, 1, 2] (D4: the
    // couplet of 3 is not stored).
    let mut lines = vec![decision(1.0), decision(2.0), decision(3.0), r#"{"event":"goal","reward":2.5}"#.into()];
    lines.push(r#"{"event":"episodeEnd"}"#.into());
    // Episode 2: state 1 again, then 2.
    lines.push(decision(1.0));
    lines.push(decision(2.0));
    let t = run_trace(&cfg, 5, &lines.join("\n")).unwrap();
    assert_eq!(t.len(), 5);
    assert!(t[..3].iter().all(|l| l.ltm == 0 && l.selected.is_empty() && l.q.is_none() && l.entropy == 0.0));
    // State 1 matches column 1 of sequence 0 exactly: G = 1 (> 0.98, and the only one).
    let l = &t[3];
    assert_eq!((l.ltm, l.layer.as_str()), (1, "R"), "fewer than 5 sequences: the reactive layer acts");
    assert_eq!(l.selected.len(), 1);
    assert_eq!((l.selected[0].row, l.selected[0].col, l.selected[0].g), (0, 1, 1.0));
    assert!(l.t.is_empty(), "T is all ones until a selection has been made");
    let p = l.p.as_ref().unwrap();
    assert_eq!(p.iter().filter(|&&v| v == 1.0).count(), 1, "one couplet: all probability on its action");
    assert_eq!(l.entropy, 0.0);
    // Next decision: the successor of (0, 1) got +0.01, and state 2 matches it with G = 1.01.
    let l = &t[4];
    assert_eq!(l.t, vec![(0, 2, 1.01)]);
    assert_eq!(l.selected.len(), 1);
    assert_eq!((l.selected[0].row, l.selected[0].col, l.selected[0].g), (0, 2, 1.01));
}

#[test]
fn recorded_events_trace_to_the_runs_own_decisions() {
    // Object permanence, seed 2, reaches goals early, so the LTM fills and the contextual layer
    // acts (the default, untrained perception).
    let cfg = RunConfig { task: "object-permanence".into(), ..RunConfig::default() };
    let seed = 2;
    let mut run = Run::new(cfg.clone(), seed).unwrap();
    run.record_events();
    let episodes: Vec<_> = (0..20).map(|_| run.episode()).collect();
    let events: Vec<String> = run.take_events().iter().map(|e| serde_json::to_string(e).unwrap()).collect();
    assert_eq!(events[0], r#"{"event":"perception","perception":"untrained","embeddingScale":1.0}"#);
    let t = run_trace(cfg.section::<SecConfig>(), seed, &events.join("\n")).unwrap();
    let (mut i, mut ltm) = (0, 0);
    for m in &episodes {
        assert_eq!(t[i].ltm, ltm, "the LTM as the previous episode left it");
        ltm = m.ltm;
        let lines = &t[i..i + m.decisions as usize];
        i += m.decisions as usize;
        let contextual = lines.iter().filter(|l| l.layer == "C").count();
        assert_eq!(contextual as f64 / m.decisions as f64, m.contextual_share, "episode {}", m.episode);
        // The same entropies in the same order give the same mean, bit for bit.
        let mean = lines.iter().map(|l| l.entropy).sum::<f64>() / m.decisions as f64;
        assert_eq!(mean, m.entropy, "episode {}", m.episode);
    }
    assert_eq!(i, t.len());
    assert!(episodes.iter().any(|m| m.contextual_share > 0.0), "the contextual layer acted");
}

#[test]
fn bad_events_are_refused_with_their_line() {
    let cfg = SecConfig::default();
    let two = format!("{}\n{}", decision(1.0), r#"{"event":"decision","embedding":[1,2,3]}"#);
    assert_eq!(run_trace(&cfg, 1, &two).unwrap_err(), "line 2: embedding: has 3 numbers, not 20");
    let e = run_trace(&cfg, 1, r#"{"event":"jump"}"#).unwrap_err();
    assert!(e.starts_with("line 1: event: unknown variant `jump`"), "{e}");
    let e = run_trace(&cfg, 1, r#"{"event":"goal"}"#).unwrap_err();
    assert!(e.starts_with("line 1: event: missing field `reward`"), "{e}");
    let e = parse_event(r#"{"event":"decision","embedding":[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0],"recMse":-1}"#, 4);
    assert_eq!(e.unwrap_err().to_string(), "line 4: recMse: -1 is out of range [0, inf)");
    assert_eq!(parse_event(r#"{"event":"episodeEnd"}"#, 1).unwrap(), Event::EpisodeEnd);
}

#[test]
fn a_trace_refuses_events_of_another_perception() {
    let events =
        format!("{}\n{}", r#"{"event":"perception","perception":"trained","embeddingScale":0.2}"#, decision(1.0));
    let mut out = Vec::new();
    let cfg = SecConfig::default();
    let e = trace(&cfg, Some(PerceptionKind::Untrained), 1, events.as_bytes(), &mut out).unwrap_err().to_string();
    assert_eq!(e, "line 1: perception: the events were recorded with the Trained encoder, the config says Untrained");
    assert_eq!(trace(&cfg, Some(PerceptionKind::Trained), 1, events.as_bytes(), &mut out).unwrap(), 1);
}
