//! Loader for the Animal-AI YAML arena format (docs/ARENAS.md section 6), so users can bring their
//! own arenas. Tags (`!ArenaConfig`, `!Item`, `!Vector3`, `!RGB`) are accepted and ignored.
//! Every problem is a [`FileError`] (of file `arena`) naming the line and the field.

use super::{
    AgentSpec, Blackouts, ConfigError, Layout, ObjectKind, ObjectSpec, Rgb, Task, ARENA_SIZE, AXES, MAX_AGENT_Y,
    MAX_OBJECT_Y, MAX_T,
};
use crate::error::FileError;
use crate::util::shown;
use yaml_rust2::parser::{Event, MarkedEventReceiver, Parser};
use yaml_rust2::scanner::Marker;

/// A parsed YAML node with the line it starts on.
#[derive(Debug, Clone)]
pub(super) enum Node {
    Scalar(String, usize),
    Seq(Vec<Node>, usize),
    Map(Vec<(Node, Node)>, usize),
}

impl Node {
    pub(super) fn line(&self) -> usize {
        match self {
            Node::Scalar(_, l) | Node::Seq(_, l) | Node::Map(_, l) => *l,
        }
    }
}

/// Collections under construction; maps hold keys and values alternately until they close.
enum Open {
    Seq(Vec<Node>, usize),
    Map(Vec<Node>, usize),
}

#[derive(Default)]
struct Builder {
    stack: Vec<Open>,
    root: Option<Node>,
    alias: Option<usize>,
}

impl Builder {
    fn push(&mut self, node: Node) {
        match self.stack.last_mut() {
            Some(Open::Seq(items, _)) | Some(Open::Map(items, _)) => items.push(node),
            None => self.root = Some(node),
        }
    }
}

impl MarkedEventReceiver for Builder {
    fn on_event(&mut self, ev: Event, mark: Marker) {
        let line = mark.line().max(1);
        match ev {
            Event::Scalar(s, ..) => self.push(Node::Scalar(s, line)),
            Event::SequenceStart(..) => self.stack.push(Open::Seq(Vec::new(), line)),
            Event::MappingStart(..) => self.stack.push(Open::Map(Vec::new(), line)),
            Event::SequenceEnd | Event::MappingEnd => match self.stack.pop() {
                Some(Open::Seq(items, l)) => self.push(Node::Seq(items, l)),
                Some(Open::Map(flat, l)) => {
                    let mut it = flat.into_iter();
                    let mut pairs = Vec::new();
                    while let (Some(k), Some(v)) = (it.next(), it.next()) {
                        pairs.push((k, v));
                    }
                    self.push(Node::Map(pairs, l));
                }
                None => {}
            },
            Event::Alias(_) => self.alias = Some(line),
            _ => {}
        }
    }
}

/// Nesting a file may have: Animal-AI's need 6 (arenas, an arena, items, an item, positions, a
/// vector). The parser is driven event by event here, not by its recursive loader, and refused
/// past this depth, so a deeply nested file cannot overflow the stack.
pub const MAX_DEPTH: usize = 32;
/// Objects an arena may hold (Animal-AI's tasks hold a few dozen); beyond it spawning, which
/// tries every random object against every placed one, would take seconds per reset.
pub const MAX_OBJECTS: usize = 200;

pub(super) fn parse(src: &str) -> Result<Node, ConfigError> {
    let mut b = Builder::default();
    let mut parser = Parser::new_from_str(src);
    loop {
        let (ev, mark) =
            parser.next_token().map_err(|e| ConfigError::at(e.marker().line().max(1), "yaml", e.info().to_string()))?;
        // One document, as the loader's single-document mode reads.
        if matches!(ev, Event::StreamEnd | Event::DocumentEnd) {
            break;
        }
        b.on_event(ev, mark);
        if b.stack.len() > MAX_DEPTH {
            let message = format!("nested deeper than {MAX_DEPTH} levels (Animal-AI files need 6)");
            return Err(ConfigError::at(mark.line().max(1), "yaml", message));
        }
    }
    if let Some(line) = b.alias {
        return Err(ConfigError::at(line, "yaml", "aliases are not supported"));
    }
    b.root.ok_or_else(|| ConfigError::at(1, "yaml", "the file is empty"))
}

/// Loads one Animal-AI arena file as a task; each `!Arena` in it becomes one layout. What the
/// loader changed to read it as v1 does (a size clamped) is in the task's `warnings`.
pub fn load_task(name: &str, src: &str) -> Result<Task, FileError> {
    crate::util::check_text_size(src, "yaml").map_err(|e| FileError::new("arena", e))?;
    let mut warnings = Vec::new();
    let layouts = layouts(name, src, &mut warnings).map_err(|e| FileError::value("arena", e))?;
    Ok(Task { name: name.to_string(), description: format!("Loaded from {name}"), layouts, warnings })
}

/// Parses every `!Arena` of a file into layouts named `name` (or `name#k` when there are several).
pub fn load_layouts(name: &str, src: &str) -> Result<Vec<Layout>, FileError> {
    load_task(name, src).map(|t| t.layouts)
}

fn layouts(name: &str, src: &str, warnings: &mut Vec<String>) -> Result<Vec<Layout>, ConfigError> {
    let root = parse(src)?;
    let arenas = map_get(&root, "", &["arenas"])?
        .into_iter()
        .find(|(k, _)| k == "arenas")
        .map(|(_, v)| v)
        .ok_or_else(|| ConfigError::at(root.line(), "arenas", "missing"))?;
    let Node::Map(pairs, line) = arenas else {
        return Err(ConfigError::at(arenas.line(), "arenas", "must be a map of arena numbers to arenas"));
    };
    if pairs.is_empty() {
        return Err(ConfigError::at(*line, "arenas", "holds no arena"));
    }
    let several = pairs.len() > 1;
    pairs
        .iter()
        .map(|(k, v)| {
            let key = scalar(k, "arenas")?;
            let lname = if several { format!("{name}#{key}") } else { name.to_string() };
            layout(&lname, v, &format!("arenas.{key}"), warnings)
        })
        .collect()
}

/// The entries of a map node, refusing keys outside `allowed`.
fn map_get<'a>(node: &'a Node, field: &str, allowed: &[&str]) -> Result<Vec<(String, &'a Node)>, ConfigError> {
    let Node::Map(pairs, line) = node else {
        return Err(ConfigError::at(node.line(), field_or(field, "document"), "must be a map"));
    };
    let mut out = Vec::new();
    for (k, v) in pairs {
        let key = scalar(k, field)?;
        if !allowed.contains(&key.as_str()) {
            let named = if key.is_empty() { "\"\"".to_string() } else { shown(&key) };
            return Err(ConfigError::at(
                k.line(),
                join(field, &named),
                format!("unknown field; expected one of {}", allowed.join(", ")),
            ));
        }
        if out.iter().any(|(seen, _): &(String, &Node)| *seen == key) {
            return Err(ConfigError::at(k.line(), join(field, &key), "appears twice"));
        }
        out.push((key, v));
    }
    let _ = line;
    Ok(out)
}

fn field_or(field: &str, fallback: &str) -> String {
    if field.is_empty() {
        fallback.to_string()
    } else {
        field.to_string()
    }
}

fn join(field: &str, key: &str) -> String {
    if field.is_empty() {
        key.to_string()
    } else {
        format!("{field}.{key}")
    }
}

fn scalar(node: &Node, field: &str) -> Result<String, ConfigError> {
    match node {
        Node::Scalar(s, _) => Ok(s.clone()),
        _ => Err(ConfigError::at(node.line(), field_or(field, "value"), "must be a plain value")),
    }
}

fn number(node: &Node, field: &str) -> Result<f32, ConfigError> {
    let s = scalar(node, field)?;
    match s.trim().parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(ConfigError::at(node.line(), field, format!("'{}' is not a number", shown(&s)))),
    }
}

fn seq<'a>(node: &'a Node, field: &str) -> Result<&'a [Node], ConfigError> {
    match node {
        Node::Seq(items, _) => Ok(items),
        _ => Err(ConfigError::at(node.line(), field, "must be a list")),
    }
}

fn layout(name: &str, node: &Node, field: &str, warnings: &mut Vec<String>) -> Result<Layout, ConfigError> {
    // A missing t is the project default (1000), which is also Animal-AI's `Arena` default.
    let mut out = Layout {
        name: name.to_string(),
        t: super::DEFAULT_T,
        objects: Vec::new(),
        agent: AgentSpec::default(),
        blackouts: Blackouts::default(),
    };
    let mut agent_seen = false;
    // Where each object was written: its item's line and field, and its place in the item.
    let mut origins: Vec<(usize, String, usize)> = Vec::new();
    for (key, v) in map_get(node, field, &["t", "pass_mark", "blackouts", "items"])? {
        let f = join(field, &key);
        match key.as_str() {
            "t" => {
                let t = number(v, &f)?;
                if t.fract() != 0.0 || !(0.0..=MAX_T as f32).contains(&t) {
                    return Err(ConfigError::at(v.line(), f, format!("{t} must be a whole number in 0..={MAX_T}")));
                }
                out.t = t as u32;
            }
            "pass_mark" => {
                number(v, &f)?;
            }
            // Lights-off switches in env steps (`Blackouts`): whole numbers, a negative one (a
            // period) only alone, as v1 reads it.
            "blackouts" => {
                let list = seq(v, &f)?;
                let mut steps = Vec::new();
                for (i, b) in list.iter().enumerate() {
                    let fi = format!("{f}[{i}]");
                    let x = number(b, &fi)?;
                    if x.fract() != 0.0 || x.abs() > MAX_T as f32 {
                        return Err(ConfigError::at(
                            b.line(),
                            fi,
                            format!("{x} must be a whole number in -{MAX_T}..={MAX_T}"),
                        ));
                    }
                    if x < 0.0 && list.len() > 1 {
                        let message = format!(
                            "{x} is a period (lights switch every {} steps) and must be the list's only entry",
                            -x
                        );
                        return Err(ConfigError::at(b.line(), fi, message));
                    }
                    steps.push(x as i32);
                }
                out.blackouts = Blackouts(steps);
            }
            "items" => {
                for (i, item) in seq(v, &f)?.iter().enumerate() {
                    let ifield = format!("{f}[{i}]");
                    match parse_item(item, &ifield, warnings)? {
                        Item::Objects(objs) => {
                            origins.extend((0..objs.len()).map(|j| (item.line(), ifield.clone(), j)));
                            out.objects.extend(objs);
                            if out.objects.len() > MAX_OBJECTS {
                                let message = format!(
                                    "the arena holds {} objects with this item, more than {MAX_OBJECTS}",
                                    out.objects.len()
                                );
                                return Err(ConfigError::at(item.line(), ifield, message));
                            }
                        }
                        Item::Agent(a) => {
                            if agent_seen {
                                return Err(ConfigError::at(item.line(), ifield, "a second Agent item"));
                            }
                            agent_seen = true;
                            out.agent = a;
                        }
                    }
                }
            }
            _ => unreachable!("map_get filters keys"),
        }
    }
    // v1 leaves out an object whose spot is taken by what was placed before it (its spawn check
    // finds a collider there); so does the loader, and says so. Only objects no draw can place:
    // one that fits in some draws stays, and the env places it where it fits.
    let left_out = super::World::always_left_out(&out);
    for &i in &left_out {
        let (line, item, j) = &origins[i];
        let o = &out.objects[i];
        let at = |v: Option<f32>| v.map_or("random".to_string(), |v| v.to_string());
        warnings.push(format!(
            "line {line}: {item}: its {} (object {j} of the item) at ({}, {}, {}) overlaps what is placed before it; \
             left out, as v1 does",
            o.kind.name(),
            at(o.position[0]),
            at(o.position[1]),
            at(o.position[2]),
        ));
    }
    for &i in left_out.iter().rev() {
        out.objects.remove(i);
    }
    Ok(out)
}

enum Item {
    Objects(Vec<ObjectSpec>),
    Agent(AgentSpec),
}

/// A vector-like map: `{x, y, z}` or `{r, g, b}`; components of -1 mean random (`None`).
fn vector(node: &Node, field: &str, keys: [&str; 3]) -> Result<[Option<f32>; 3], ConfigError> {
    let entries = map_get(node, field, &keys)?;
    let mut out = [None; 3];
    for k in keys {
        let Some((_, v)) = entries.iter().find(|(key, _)| key == k) else {
            return Err(ConfigError::at(node.line(), join(field, k), "missing"));
        };
        let f = join(field, k);
        let value = number(v, &f)?;
        if value < 0.0 && value != -1.0 {
            return Err(ConfigError::at(
                v.line(),
                f,
                format!("{value} is negative (only -1, meaning random, is allowed)"),
            ));
        }
        out[keys.iter().position(|&x| x == k).unwrap()] = if value == -1.0 { None } else { Some(value) };
    }
    Ok(out)
}

fn in_range(v: Option<f32>, lo: f32, hi: f32, line: usize, field: &str) -> Result<(), ConfigError> {
    match v {
        Some(x) if !(lo..=hi).contains(&x) => {
            Err(ConfigError::at(line, field, format!("{x} is out of range {lo}..={hi} (or -1 for random)")))
        }
        _ => Ok(()),
    }
}

fn parse_item(node: &Node, field: &str, warnings: &mut Vec<String>) -> Result<Item, ConfigError> {
    let entries = map_get(node, field, &["name", "positions", "rotations", "sizes", "colors"])?;
    let name_node = entries
        .iter()
        .find(|(k, _)| k == "name")
        .map(|(_, v)| *v)
        .ok_or_else(|| ConfigError::at(node.line(), join(field, "name"), "missing"))?;
    let name = scalar(name_node, &join(field, "name"))?;
    let list = |key: &str| -> Result<&[Node], ConfigError> {
        match entries.iter().find(|(k, _)| k == key) {
            Some((_, v)) => seq(v, &join(field, key)),
            None => Ok(&[]),
        }
    };
    let mut positions = Vec::new();
    for (j, p) in list("positions")?.iter().enumerate() {
        let f = format!("{field}.positions[{j}]");
        let v = vector(p, &f, ["x", "y", "z"])?;
        in_range(v[0], 0.0, ARENA_SIZE, p.line(), &format!("{f}.x"))?;
        in_range(v[1], 0.0, MAX_OBJECT_Y, p.line(), &format!("{f}.y"))?;
        in_range(v[2], 0.0, ARENA_SIZE, p.line(), &format!("{f}.z"))?;
        positions.push(v);
    }
    let mut rotations = Vec::new();
    for (j, r) in list("rotations")?.iter().enumerate() {
        let f = format!("{field}.rotations[{j}]");
        let v = number(r, &f)?;
        let v = if v == -1.0 { None } else { Some(v) };
        in_range(v, -360.0, 360.0, r.line(), &f)?;
        rotations.push(v);
    }
    if name == "Agent" {
        for key in ["sizes", "colors"] {
            if let Some((_, v)) = entries.iter().find(|(k, _)| k == key) {
                return Err(ConfigError::at(v.line(), join(field, key), "an Agent takes only positions and rotations"));
            }
        }
        if positions.len() > 1 || rotations.len() > 1 {
            return Err(ConfigError::at(node.line(), field, "an Agent takes at most one position and one rotation"));
        }
        let p = positions.first().copied().unwrap_or([None; 3]);
        for (k, v) in [(0, p[0]), (2, p[2])] {
            in_range(v, 0.5, ARENA_SIZE - 0.5, node.line(), &format!("{field}.positions[0].{}", AXES[k]))?;
        }
        in_range(p[1], 0.0, MAX_AGENT_Y, node.line(), &format!("{field}.positions[0].y"))?;
        return Ok(Item::Agent(AgentSpec {
            position: [p[0], p[2]],
            y: p[1].unwrap_or(0.0),
            rotation: rotations.first().copied().flatten(),
        }));
    }
    let Some(kind) = ObjectKind::from_name(&name) else {
        let known: Vec<&str> =
            ObjectKind::ALL.iter().filter(|k| k.simulated()).map(|k| k.name()).chain(["Agent"]).collect();
        return Err(ConfigError::at(
            name_node.line(),
            join(field, "name"),
            format!("unknown item '{}'; supported: {}", shown(&name), known.join(", ")),
        ));
    };
    let (lo, hi) = kind.size_range();
    let mut sizes = Vec::new();
    for (j, s) in list("sizes")?.iter().enumerate() {
        let f = format!("{field}.sizes[{j}]");
        let mut v = vector(s, &f, ["x", "y", "z"])?;
        // v1 clamps a size into its object's range (`Prefab.SetSize`: max(sizeMin, min(sizeMax,
        // size))); the loader does the same and says so.
        for axis in 0..3 {
            if let Some(x) = v[axis] {
                let clamped = x.clamp(lo[axis], hi[axis]);
                // A sphere's size is its x alone (y and z are ignored): only x is worth a warning.
                if clamped != x && (axis == 0 || !kind.is_goal()) {
                    warnings.push(format!(
                        "line {}: {f}.{}: {x} is outside {}..={} for a {name}; clamped to {clamped}, as v1 does",
                        s.line(),
                        AXES[axis],
                        lo[axis],
                        hi[axis]
                    ));
                }
                v[axis] = Some(clamped);
            }
        }
        sizes.push(v);
    }
    let mut colours = Vec::new();
    for (j, c) in list("colors")?.iter().enumerate() {
        let f = format!("{field}.colors[{j}]");
        // v1 files write colours as !RGB {r, g, b} or as !Vector3 {x, y, z}.
        let keys = match c {
            Node::Map(pairs, _) if pairs.iter().any(|(k, _)| matches!(k, Node::Scalar(s, _) if s == "x")) => {
                ["x", "y", "z"]
            }
            _ => ["r", "g", "b"],
        };
        let v = vector(c, &f, keys)?;
        for (axis, key) in keys.iter().enumerate() {
            in_range(v[axis], 0.0, 255.0, c.line(), &format!("{f}.{key}"))?;
        }
        colours.push(match v {
            [Some(r), Some(g), Some(b)] => Some(Rgb(r.round() as u8, g.round() as u8, b.round() as u8)),
            _ => None,
        });
    }
    let count = positions.len().max(rotations.len()).max(sizes.len()).max(colours.len()).max(1);
    let default = kind.default_size();
    let objects = (0..count)
        .map(|j| ObjectSpec {
            kind,
            position: positions.get(j).copied().unwrap_or([None; 3]),
            // A missing rotation is random, except for spheres, which look the same either way
            // (a bouncing goal's sets where it is launched).
            rotation: if kind.is_goal() && !kind.bounces() {
                Some(rotations.get(j).copied().flatten().unwrap_or(0.0))
            } else {
                rotations.get(j).copied().flatten()
            },
            size: sizes.get(j).copied().unwrap_or(default.map(Some)),
            colour: colours.get(j).copied().flatten(),
        })
        .collect();
    Ok(Item::Objects(objects))
}
