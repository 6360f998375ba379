//! What an Animal-AI arena file asks of a simulator beyond what this one does (docs/ARENAS.md
//! section 6): read leniently, so that a file the loader refuses at its first problem still lists
//! every feature it needs. The arenas report (`sec-experiment arenas`) uses it on the Animal-AI
//! Olympics corpus to say why each refused file is refused, and which loaded files would behave
//! otherwise than in v1.

use super::yaml::{parse, Node};
use super::{ConfigError, Footprint, ObjectKind};
use glam::Vec2;
use std::collections::BTreeSet;

/// A feature of Animal-AI arena files that this simulator lacks or ignores.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Feature {
    /// Something that stands above the floor: an agent or a box placed at `y > 0` (on a platform,
    /// raised), or a goal over a box's footprint (it comes to rest on the box). The world is
    /// flat: a loaded file puts them on the floor. (A goal over bare floor falls onto it, as here.)
    World3d,
    /// A `Ramp`.
    Ramp,
    /// `GoodGoalBounce`, `BadGoalBounce`, `GoodGoalMultiBounce`: goals launched along their rotation.
    BouncingGoals,
    /// `Cardbox1`, `Cardbox2`, `UObject`, `LObject`, `LObject2`: objects the agent pushes.
    Pushable,
    /// Any other item the simulator does not know.
    Item(String),
}

impl Feature {
    /// Short name for reports.
    pub fn name(&self) -> String {
        match self {
            Feature::World3d => "3-D world".into(),
            Feature::Ramp => "ramps".into(),
            Feature::BouncingGoals => "bouncing goals".into(),
            Feature::Pushable => "pushable objects".into(),
            Feature::Item(name) => format!("item {name}"),
        }
    }

    /// Whether a file with it can load, with the feature ignored (it then does not behave as
    /// in v1), as opposed to being refused.
    pub fn ignored_on_load(&self) -> bool {
        matches!(self, Feature::World3d)
    }

    /// The feature an item's name asks for, if it is not one the simulator has.
    fn of_item(name: &str) -> Option<Feature> {
        match name {
            "Agent" => None,
            "Ramp" => Some(Feature::Ramp),
            "GoodGoalBounce" | "BadGoalBounce" | "GoodGoalMultiBounce" => Some(Feature::BouncingGoals),
            "Cardbox1" | "Cardbox2" | "UObject" | "LObject" | "LObject2" => Some(Feature::Pushable),
            _ if ObjectKind::from_name(name).is_some() => None,
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
        // Footprints of the boxes placed where the file says, and the goals' spots.
        let mut boxes = Vec::new();
        let mut goals = Vec::new();
        for item in items {
            let Some(Node::Scalar(name, _)) = entry(item, "name") else { continue };
            out.extend(Feature::of_item(name));
            let kind = ObjectKind::from_name(name);
            let goal = kind.is_some_and(ObjectKind::is_goal) || name.contains("Goal");
            let positions = match entry(item, "positions") {
                Some(Node::Seq(ps, _)) => ps.as_slice(),
                _ => &[],
            };
            if !goal && positions.iter().any(|p| component(p, "y").is_some_and(|y| y > 0.0)) {
                out.insert(Feature::World3d);
            }
            let list = |key| match entry(item, key) {
                Some(Node::Seq(v, _)) => v.as_slice(),
                _ => &[],
            };
            for (j, p) in positions.iter().enumerate() {
                let (Some(x), Some(z)) =
                    (component(p, "x").filter(|v| *v >= 0.0), component(p, "z").filter(|v| *v >= 0.0))
                else {
                    continue;
                };
                if goal {
                    goals.push(Vec2::new(x, z));
                } else if matches!(kind, Some(ObjectKind::Wall | ObjectKind::WallTransparent)) {
                    let size = list("sizes").get(j);
                    let (sx, sz) = (size.and_then(|s| component(s, "x")), size.and_then(|s| component(s, "z")));
                    let rotation = match list("rotations").get(j) {
                        Some(Node::Scalar(r, _)) => r.trim().parse::<f32>().ok().filter(|r| *r != -1.0),
                        _ => Some(0.0),
                    };
                    if let (Some(sx), Some(sz), Some(r)) = (sx.filter(|v| *v > 0.0), sz.filter(|v| *v > 0.0), rotation)
                    {
                        boxes.push(Footprint::new(Vec2::new(x, z), Vec2::new(sx / 2.0, sz / 2.0), r));
                    }
                }
            }
        }
        if goals.iter().any(|g| boxes.iter().any(|b| b.contains(*g, 0.0))) {
            out.insert(Feature::World3d);
        }
    }
    Ok(out)
}

/// The value under `key` of a map node.
fn entry<'a>(node: &'a Node, key: &str) -> Option<&'a Node> {
    let Node::Map(pairs, _) = node else { return None };
    pairs.iter().find(|(k, _)| matches!(k, Node::Scalar(s, _) if s == key)).map(|(_, v)| v)
}

/// A vector's component `key`, if it is a number.
fn component(node: &Node, key: &str) -> Option<f32> {
    match entry(node, key)? {
        Node::Scalar(s, _) => s.trim().parse::<f32>().ok().filter(|v| v.is_finite()),
        _ => None,
    }
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
            \x20   - !Item\n      name: Cardbox1\n    - !Item\n      name: Pillar\n";
        let names: Vec<String> = features(src).unwrap().iter().map(Feature::name).collect();
        assert_eq!(names, ["3-D world", "ramps", "pushable objects", "item Pillar"]);
    }

    #[test]
    fn the_papers_arenas_need_nothing() {
        for task in ["v1_3-4-1.yml", "v1_3-5-1.yml", "v1_3-13-1.yml", "v1_8-7-1.yml"] {
            let src = std::fs::read_to_string(format!("{}/assets/arenas/{task}", env!("CARGO_MANIFEST_DIR"))).unwrap();
            assert_eq!(features(&src).unwrap(), BTreeSet::new(), "{task}");
        }
    }
}
