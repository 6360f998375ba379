//! The page's flat settings (URL hash keys) and their mapping onto a run configuration.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::agent::SecConfig;
use sec_playground::experiment::settings::{
    apply, defaults, from_settings, params, preset, to_settings, Kind, Settings,
};
use sec_playground::experiment::AgentKind;

fn settings(pairs: &[(&str, &str)]) -> Settings {
    pairs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect()
}

#[test]
fn settings_round_trip_and_cover_every_parameter() {
    let (cfg, seed) = defaults();
    let s = to_settings(&cfg, seed);
    assert_eq!(s.len(), params().len(), "one hash key per control");
    let (back, seed2, errors) = from_settings(&s);
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!((to_settings(&back, seed2), &back), (s, &cfg));
    // Settings made from the same values give equal configurations: no needless restart.
    let (again, _, _) = from_settings(&Default::default());
    assert!(!back.needs_restart(&again));
    let odd = settings(&[
        ("task", "detour"),
        ("agent", "mfec-rp"),
        ("bias", "0"),
        ("alpha", "0.25"),
        ("tau", "3"),
        ("m", "125"),
        ("forgetting", "rwd-prop"),
        ("value", "soloRR"),
        ("perception", "trained"),
        ("embeddingScale", "0.5"),
        ("startHeading", "fixed"),
        ("t", "400"),
        ("seed", "9007199254740991"),
    ]);
    let (cfg, seed, errors) = from_settings(&odd);
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!((cfg.kind, cfg.t, seed), (AgentKind::Mfec, Some(400), 9007199254740991));
    let again = to_settings(&cfg, seed);
    for (k, v) in &odd {
        assert_eq!(&again[k], v, "{k}");
    }
}

#[test]
fn every_range_is_checked_at_both_ends_and_named() {
    for p in params() {
        let (mut cfg, mut seed) = defaults();
        let (ok, bad): (Vec<String>, Vec<String>) = match &p.kind {
            Kind::Number { min, max, min_open, auto, .. } => {
                let lo = if *min_open { vec![] } else { vec![min.to_string()] };
                let auto = if *auto { vec!["auto".to_string()] } else { vec![] };
                let ok = [lo, vec![max.to_string()], auto].concat();
                let below = if *min_open { min.to_string() } else { (min - 1e-9).to_string() };
                (ok, vec![below, (max + 1e-9).to_string(), "NaN".into(), "inf".into(), "".into(), "x".into()])
            }
            Kind::Integer { min, max } => {
                let mut bad = vec![(max + 1).to_string(), "1.5".into(), "-1".into(), "".into(), "1e3".into()];
                if *min > 0 {
                    bad.push((min - 1).to_string());
                }
                (vec![min.to_string(), max.to_string()], bad)
            }
            Kind::Choice { options } => (options.clone(), vec!["nope".into(), "".into()]),
            Kind::Switch => (vec!["0".into(), "1".into()], vec!["2".into(), "yes".into()]),
        };
        for v in &ok {
            apply(&mut cfg, &mut seed, p.key, v).unwrap_or_else(|e| panic!("{} = {v}: {e}", p.key));
        }
        let before = (cfg.clone(), seed);
        for v in &bad {
            let e = apply(&mut cfg, &mut seed, p.key, v).expect_err(&format!("{} = {v:?} accepted", p.key));
            assert_eq!(e.field, p.key);
            assert!(e.message.contains("out of range") || e.message.contains("not a number"), "{e}");
            assert_eq!((cfg.clone(), seed), before, "a refused value changes nothing");
        }
    }
}

#[test]
fn bad_settings_keep_their_defaults_and_are_reported() {
    let (cfg, seed, errors) = from_settings(&settings(&[("alpha", "5"), ("beta", "0.2"), ("colour", "red")]));
    let named: Vec<&str> = errors.iter().map(|e| e.field.as_str()).collect();
    assert_eq!(named, ["alpha", "colour"]);
    assert!(errors[0].to_string().contains("alpha: '5' is out of range [0, 1]"), "{}", errors[0]);
    assert_eq!((cfg.section::<SecConfig>().memory.alpha, cfg.section::<SecConfig>().memory.beta, seed), (0.01, 0.2, 1));
    // Fine one by one, not together: SEC needs 5 sequences to act, so m = 3 cannot run.
    let (cfg, _, errors) = from_settings(&settings(&[("m", "3"), ("alpha", "0.5")]));
    assert_eq!(errors.len(), 1);
    assert_eq!(errors[0].field, "minSequences");
    assert_eq!(cfg, defaults().0, "every default kept");
}

/// HTML lowercases attribute names and people write links by hand: every key of the table is
/// accepted in camelCase, lowercase, kebab and snake form, as the same setting.
#[test]
fn every_key_is_accepted_in_any_case_and_kebab_form() {
    use sec_playground::experiment::settings::canonical_key;
    for p in params() {
        let kebab: String = p
            .key
            .chars()
            .flat_map(|c| if c.is_ascii_uppercase() { vec!['-', c.to_ascii_lowercase()] } else { vec![c] })
            .collect();
        for form in
            [p.key.to_string(), p.key.to_lowercase(), p.key.to_uppercase(), kebab.clone(), kebab.replace('-', "_")]
        {
            assert_eq!(canonical_key(&form), Some(p.key), "{form}");
        }
    }
    assert_eq!(canonical_key("colour"), None);
    let (cfg, _, errors) = from_settings(&settings(&[("startheading", "fixed"), ("embedding-scale", "2")]));
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!((cfg.start_heading, cfg.embedding_scale), (sec_playground::arena::StartHeading::Fixed, Some(2.0)));
}

#[test]
fn non_numbers_and_impossible_combinations_say_what_to_change() {
    let (_, _, errors) = from_settings(&settings(&[("alpha", "abc"), ("tau", "")]));
    assert_eq!(errors[0].to_string(), "alpha: 'abc' is not a number in [0, 1]");
    assert_eq!(errors[1].to_string(), "tau: is empty, not a number in [0.01, 100]");
    let (_, _, errors) = from_settings(&settings(&[("m", "3")]));
    let message = errors[0].to_string();
    assert!(message.contains("raise m to 5 or more, or lower minSequences to 3 or less"), "{message}");
}

#[test]
fn presets_set_the_code_and_the_paper_values() {
    let paper = preset("paper").unwrap();
    assert_eq!(
        (paper["thetaAbs"].as_str(), paper["thetaProp"].as_str(), paper["alpha"].as_str()),
        ("0.995", "0.98", "0.1")
    );
    assert_eq!((paper["perception"].as_str(), paper["embeddingScale"].as_str()), ("trained", "auto"));
    let code = preset("code").unwrap();
    assert_eq!(
        (code["thetaAbs"].as_str(), code["thetaProp"].as_str(), code["alpha"].as_str()),
        ("0.98", "0.995", "0.01")
    );
    assert_eq!((code["perception"].as_str(), code["embeddingScale"].as_str()), ("untrained", "auto"));
    assert_eq!(preset("book").unwrap_err().field, "preset");
}

#[test]
fn perception_scale_and_heading_are_settings_of_a_new_run() {
    let (cfg, seed, errors) =
        from_settings(&settings(&[("perception", "trained"), ("embeddingScale", "2.5"), ("startHeading", "fixed")]));
    assert!(errors.is_empty(), "{errors:?}");
    use sec_playground::arena::StartHeading;
    use sec_playground::encoder::PerceptionKind;
    assert_eq!(
        (cfg.perception, cfg.embedding_scale, cfg.start_heading),
        (PerceptionKind::Trained, Some(2.5), StartHeading::Fixed)
    );
    assert!(defaults().0.needs_restart(&cfg));
    assert_eq!(to_settings(&defaults().0, seed)["embeddingScale"], "auto");
    for (k, v) in [("perception", "raw"), ("embeddingScale", "0"), ("embeddingScale", "-1"), ("startHeading", "north")]
    {
        let (c, _, errors) = from_settings(&settings(&[(k, v)]));
        assert_eq!(errors.len(), 1, "{k}={v}");
        assert_eq!(errors[0].field, k);
        assert_eq!(c, defaults().0);
    }
}

/// Values of `p` other than `current`, inside its range, to try in turn (a whole configuration
/// may refuse some: m below SEC's 5 sequences).
fn other_values(p: &Kind, current: &str) -> Vec<String> {
    let all: Vec<String> = match p {
        Kind::Number { min, max, .. } => vec![((min + max) / 2.0).to_string(), max.to_string()],
        Kind::Integer { min, max } => [*min, *max, 3, 6].iter().map(u64::to_string).collect(),
        Kind::Choice { options } => options.clone(),
        Kind::Switch => vec!["0".into(), "1".into()],
    };
    all.into_iter().filter(|v| v != current).collect()
}

/// Each row's `live` is what the running agent does: a live setting changes the run in place
/// (`Run::reconfigure` takes it and the run's configuration is the new one), any other asks for
/// a new run and changes nothing. Liveness is declared in the rows alone, so this is the check
/// that the agents honour it.
#[test]
fn every_live_flag_is_what_a_running_agent_does() {
    use sec_playground::experiment::Run;
    for p in params() {
        let (before, seed) = defaults();
        let current = to_settings(&before, seed)[p.key].clone();
        let (after, seed2) = other_values(&p.kind, &current)
            .into_iter()
            .find_map(|v| {
                let (mut after, mut seed2) = (before.clone(), seed);
                apply(&mut after, &mut seed2, p.key, &v).unwrap_or_else(|e| panic!("{} = {v}: {e}", p.key));
                after.validate().is_ok().then_some((after, seed2))
            })
            .unwrap_or_else(|| panic!("{}: no other value makes a valid run", p.key));
        assert!((after.clone(), seed2) != (before.clone(), seed), "{} changes something", p.key);
        if p.key == "seed" {
            assert!(!p.live, "a new seed is a new run");
            continue;
        }
        let mut run = Run::new(before.clone(), seed).unwrap();
        run.episode();
        let applied = run.reconfigure(after.clone()).unwrap_or_else(|e| panic!("{}: {e}", p.key));
        assert_eq!(applied, p.live, "{}: live {} but the running agent says otherwise", p.key, p.live);
        assert_eq!(run.config(), if p.live { &after } else { &before }, "{}", p.key);
        // The agent itself took it, not only the run's record of it.
        let view = run.inspect();
        let memory = view.memory.expect("the default agent is SEC");
        assert_eq!(memory.config(), &run.config().section::<SecConfig>().memory, "{}", p.key);
        assert_eq!(view.min_sequences, Some(run.config().section::<SecConfig>().min_sequences), "{}", p.key);
    }
}

#[test]
fn value_function_names_are_one_spelling_everywhere() {
    use sec_playground::memory::ValueFn;
    for (name, f) in ValueFn::ALL {
        let json = serde_json::to_string(&f).unwrap();
        assert_eq!(json, format!("\"{name}\""), "RunConfig JSON spells {f:?} as the settings do");
        assert_eq!(serde_json::from_str::<ValueFn>(&json).unwrap(), f);
    }
    assert!(serde_json::from_str::<ValueFn>("\"noRr\"").is_err(), "one spelling: noRR");
}

#[test]
fn every_setting_has_a_group_and_names_real_agents() {
    use sec_playground::experiment::settings::page_agents;
    for p in params() {
        assert!(["run", "perception", "memory", "retrieval"].contains(&p.group), "{}: group {}", p.key, p.group);
        assert!(p.agents.iter().all(|a| page_agents().contains(a)), "{}: {:?}", p.key, p.agents);
    }
    let sec_only: Vec<&str> = params().iter().filter(|p| p.agents == ["sec"]).map(|p| p.key).collect();
    assert!(sec_only.contains(&"alpha") && sec_only.contains(&"m") && !sec_only.contains(&"task"));
}

#[test]
fn a_long_bad_value_is_cut_in_the_message() {
    let long = "9".repeat(10_000);
    let (_, _, errors) = from_settings(&settings(&[("alpha", long.as_str()), (long.as_str(), "1")]));
    assert_eq!(errors.len(), 2);
    for e in &errors {
        let text = e.to_string();
        assert!(text.len() < 400, "{} characters: {}", text.len(), &text[..200]);
        assert!(text.contains("(10000 characters)"), "{text}");
    }
    assert_eq!(errors.iter().filter(|e| e.field == "alpha").count(), 1, "the parameter is still named");
}

/// A batch of changes goes in as one (what the page's worker forwards, once): every bad change
/// is named, and then nothing applies; good changes that only go together apply together.
#[test]
fn a_batch_of_changes_applies_all_or_none() {
    use sec_playground::experiment::settings::apply_all;
    let (cfg, seed) = defaults();
    let errors = apply_all(&cfg, seed, &settings(&[("alpha", "0.2"), ("beta", "7"), ("tau", "x")])).unwrap_err();
    let messages: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
    assert_eq!(messages, ["beta: '7' is out of range [0, 1]", "tau: 'x' is not a number in [0.01, 100]"]);
    let (next, next_seed) = apply_all(&cfg, seed, &settings(&[("alpha", "0.2"), ("seed", "9")])).unwrap();
    assert_eq!((next.section::<SecConfig>().memory.alpha, next_seed), (0.2, 9));
    assert_eq!(next.section::<SecConfig>().memory.tau, cfg.section::<SecConfig>().memory.tau, "the rest as it was");
    // m = 3 is below what SEC needs: refused alone, as a whole.
    let errors = apply_all(&cfg, seed, &settings(&[("m", "3")])).unwrap_err();
    assert!(errors[0].to_string().contains("raise m to 5 or more"), "{errors:?}");
}
