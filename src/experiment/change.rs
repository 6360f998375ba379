//! A partial change of a run's configuration, as every front end applies it (the page's
//! `SecRun.configure`, Python's `Run.configure`, the CLI's `--set`): the fields it names replace
//! the run's, the rest keep their values (never their defaults), and the answer lists each field
//! that changed and whether a change of it alone would act live or need a new run.

use super::RunConfig;
use crate::arena::ConfigError;
use serde_json::{Map, Value};

/// One field a change altered.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FieldChange {
    /// Its path in the configuration, as errors name it (`agent.memory.tau`).
    pub field: String,
    /// Its value before (`null` for an unset optional field).
    pub from: Value,
    /// Its value after.
    pub to: Value,
    /// Whether changing it alone acts from the next decision in the same run
    /// (`RunConfig::needs_restart`); otherwise it needs a new run.
    pub live: bool,
}

impl RunConfig {
    /// `self` with the fields of `patch` (a JSON object, a partial RunConfig) replaced: objects
    /// merge key by key, any other value replaces the field's; `null` unsets an optional field.
    /// The result is read and checked as a whole configuration is (`from_json`), so a misspelt
    /// key or a value out of range is refused by its path and `self` is untouched.
    pub fn patched(&self, patch: &str) -> Result<RunConfig, ConfigError> {
        crate::util::check_text_size(patch, "config").map_err(|e| ConfigError::new("config", e))?;
        let patch: Value = serde_json::from_str(patch).map_err(|e| ConfigError::new("config", e.to_string()))?;
        let Value::Object(patch) = patch else {
            let message = format!("{} is not an object (a partial RunConfig)", crate::util::shown(&patch.to_string()));
            return Err(ConfigError::new("config", message));
        };
        let mut merged = serde_json::to_value(self).expect("configurations serialise");
        merge(merged.as_object_mut().expect("a configuration is an object"), patch);
        RunConfig::from_json(&merged.to_string())
    }

    /// The fields that differ from `self` in `next`, each with whether it alone would act live.
    pub fn changes(&self, next: &RunConfig) -> Vec<FieldChange> {
        let (a, b) = (serde_json::to_value(self).expect("serialises"), serde_json::to_value(next).expect("serialises"));
        let mut leaves = Vec::new();
        differences(&a, &b, String::new(), &mut leaves);
        leaves
            .into_iter()
            .map(|(field, from, to)| {
                let mut alone = serde_json::to_value(self).expect("serialises");
                set(&mut alone, &field, to.clone());
                let live = serde_json::from_value::<RunConfig>(alone).is_ok_and(|c| !self.needs_restart(&c));
                FieldChange { field, from, to, live }
            })
            .collect()
    }
}

fn merge(into: &mut Map<String, Value>, patch: Map<String, Value>) {
    for (key, value) in patch {
        match (into.get_mut(&key), value) {
            (Some(Value::Object(a)), Value::Object(b)) => merge(a, b),
            (_, value) => {
                into.insert(key, value);
            }
        }
    }
}

/// The leaves (paths, old and new values) where `a` and `b` differ; a field present on one side
/// only is `null` on the other.
fn differences(a: &Value, b: &Value, path: String, out: &mut Vec<(String, Value, Value)>) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let mut keys: Vec<&String> = x.keys().chain(y.keys()).collect();
            keys.sort();
            keys.dedup();
            for k in keys {
                let p = if path.is_empty() { k.clone() } else { format!("{path}.{k}") };
                differences(x.get(k).unwrap_or(&Value::Null), y.get(k).unwrap_or(&Value::Null), p, out);
            }
        }
        _ if a != b => out.push((path, a.clone(), b.clone())),
        _ => {}
    }
}

/// Sets the leaf at the dotted `path` of `v` (creating objects on the way).
fn set(v: &mut Value, path: &str, to: Value) {
    let mut at = v;
    let parts: Vec<&str> = path.split('.').collect();
    for p in &parts[..parts.len() - 1] {
        if !at.get(*p).is_some_and(Value::is_object) {
            at[*p] = Value::Object(Map::new());
        }
        at = &mut at[*p];
    }
    at[parts[parts.len() - 1]] = to;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::agent::SecConfig;

    #[test]
    fn a_patch_changes_what_it_names_and_keeps_the_rest() {
        let mut base = RunConfig { task: "object-permanence".into(), ..RunConfig::default() };
        base.section_mut::<SecConfig>().memory.alpha = 0.05;
        let next = base.patched(r#"{"agent": {"memory": {"tau": 0.5}}}"#).unwrap();
        assert_eq!(next.section::<SecConfig>().memory.tau, 0.5);
        assert_eq!(next.section::<SecConfig>().memory.alpha, 0.05, "kept, not the default");
        assert_eq!(next.task, "object-permanence");
        let changes = base.changes(&next);
        assert_eq!(changes.len(), 1);
        assert_eq!(changes[0].field, "agent.memory.tau");
        assert!(changes[0].live);
        let restart = base.patched(r#"{"agent": {"memory": {"n": 30}}, "t": 300}"#).unwrap();
        let fields: Vec<(String, bool)> = base.changes(&restart).into_iter().map(|c| (c.field, c.live)).collect();
        assert_eq!(fields, [("agent.memory.n".to_string(), false), ("t".to_string(), false)]);
        let err = base.patched(r#"{"agent": {"memory": {"tua": 0.5}}}"#).unwrap_err();
        assert!(err.to_string().contains("tua"), "{err}");
        assert!(base.patched("[1]").is_err());
        assert!(base.patched(r#"{"agent": {"memory": {"tau": -1}}}"#).unwrap_err().to_string().contains("tau"));
    }
}
