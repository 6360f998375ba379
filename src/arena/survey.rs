//! What an Animal-AI arena file asks of a simulator beyond what this one does (docs/ARENAS.md
//! section 6): read leniently, so that a file the loader refuses at its first problem still lists
//! every feature it needs. The arenas report (`sec-experiment arenas`) uses it on the Animal-AI
//! Olympics corpus to say why each refused file is refused, and which loaded files would behave
//! otherwise than in v1.

use super::yaml::{parse, Node};
use super::{ConfigError, ObjectKind};
use std::collections::BTreeSet;

/// A feature of Animal-AI arena files that this simulator lacks.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Feature {
    /// Objects the agent pushes (`Cardbox1`, `Cardbox2`, `UObject`, `LObject`, `LObject2`), in a
    /// build without the rigid bodies of the `pushables` feature.
    Pushable,
    /// Any other item the simulator does not know.
    Item(String),
}

impl Feature {
    /// Short name for reports.
    pub fn name(&self) -> String {
        match self {
            Feature::Pushable => "pushable objects".into(),
            Feature::Item(name) => format!("item {name}"),
        }
    }

    /// The feature an item's name asks for, if it is not one the simulator has.
    fn of_item(name: &str) -> Option<Feature> {
        match name {
            "Agent" => None,
            _ if ObjectKind::from_name(name).is_some() => None,
            _ if ObjectKind::ALL.iter().any(|k| k.name() == name) => Some(Feature::Pushable),
            _ => Some(Feature::Item(name.to_string())),
        }
    }
}

/// Every feature of `Feature` the arena file `src` uses, in order. Only a file that is not YAML,
/// or has no `arenas` map, is an error; anything else unreadable is skipped (the loader reports it).
pub fn features(src: &str) -> Result<BTreeSet<Feature>, ConfigError> {
    let root = parse(src)?;
    let arenas = entry(&root, "arenas").ok_or_else(|| ConfigError::at(root.line(), "arenas", "missing"))?;
    let Node::Map(arenas, _) = arenas else {
        return Err(ConfigError::at(arenas.line(), "arenas", "must be a map of arena numbers to arenas"));
    };
    let mut out = BTreeSet::new();
    for (_, arena) in arenas {
        let Some(Node::Seq(items, _)) = entry(arena, "items") else { continue };
        for item in items {
            if let Some(Node::Scalar(name, _)) = entry(item, "name") {
                out.extend(Feature::of_item(name));
            }
        }
    }
    Ok(out)
}

/// The value under `key` of a map node.
fn entry<'a>(node: &'a Node, key: &str) -> Option<&'a Node> {
    let Node::Map(pairs, _) = node else { return None };
    pairs.iter().find(|(k, _)| matches!(k, Node::Scalar(s, _) if s == key)).map(|(_, v)| v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_lists_every_feature_it_needs_even_where_the_loader_stops_at_the_first() {
        let src = "!ArenaConfig\narenas:\n  0: !Arena\n    t: 250\n    blackouts: [5, 10]\n    items:\n\
            \x20   - !Item\n      name: Ramp\n      positions:\n      - !Vector3 {x: 5, y: 0, z: 5}\n\
            \x20   - !Item\n      name: Agent\n      positions:\n      - !Vector3 {x: 20, y: 1.5, z: 20}\n\
            \x20   - !Item\n      name: Wall\n      sizes:\n      - !Vector3 {x: 45, y: 1, z: 1}\n\
            \x20   - !Item\n      name: GoodGoal\n    - !Item\n      name: GoodGoalMulti\n\
            \x20   - !Item\n      name: Cardbox1\n    - !Item\n      name: LObject\n    - !Item\n      name: Pillar\n";
        let names: Vec<String> = features(src).unwrap().iter().map(Feature::name).collect();
        // Pushable objects need nothing more where the rigid bodies are built in.
        let expected: Vec<String> = if cfg!(feature = "pushables") {
            vec!["item Pillar".into()]
        } else {
            vec![Feature::Pushable.name(), "item Pillar".into()]
        };
        assert_eq!(names, expected);
    }

    #[test]
    fn the_papers_arenas_need_nothing() {
        for task in ["v1_3-4-1.yml", "v1_3-5-1.yml", "v1_3-13-1.yml", "v1_8-7-1.yml"] {
            let src = std::fs::read_to_string(format!("{}/assets/arenas/{task}", env!("CARGO_MANIFEST_DIR"))).unwrap();
            assert_eq!(features(&src).unwrap(), BTreeSet::new(), "{task}");
        }
    }
}
