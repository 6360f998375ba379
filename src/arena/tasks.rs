//! The named task presets of SEC Playground (docs/ARENAS.md section 7).

use super::{AgentSpec, ConfigError, Layout, ObjectKind, ObjectSpec, DEFAULT_T};

/// A task: one or more start layouts, cycled one per episode in an order shuffled once per run.
#[derive(Clone, Debug, PartialEq)]
pub struct Task {
    /// Its name (`double-t-maze`, ...).
    pub name: String,
    /// One line on what it tests.
    pub description: String,
    /// The start layouts.
    pub layouts: Vec<Layout>,
    /// What loading it changed to read it as v1 does, one line each (a size clamped into its
    /// object's range, with the file's value and the value used); empty for the presets.
    pub warnings: Vec<String>,
}

/// How a layout that leaves the agent's heading open starts its episodes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StartHeading {
    /// A heading drawn at every reset (Animal-AI's behaviour for a missing rotation).
    #[default]
    Random,
    /// Facing the arena's centre from the layout's start position, the same every episode. The
    /// rule was fixed before any run: the unpublished newdac files' headings are unknown (D11).
    Fixed,
}

impl StartHeading {
    /// Every start heading with its name.
    pub const ALL: [(&'static str, StartHeading); 2] =
        [("random", StartHeading::Random), ("fixed", StartHeading::Fixed)];
}

const GREY: (u8, u8, u8) = (153, 153, 153);

fn wall(x: f32, z: f32, size: (f32, f32, f32), rgb: (u8, u8, u8)) -> ObjectSpec {
    ObjectSpec::new(ObjectKind::Wall, x, 0.0, z).size(size.0, size.1, size.2).colour(rgb.0, rgb.1, rgb.2)
}

fn goal(kind: ObjectKind, x: f32, y: f32, z: f32, size: f32) -> ObjectSpec {
    ObjectSpec::new(kind, x, y, z).size(size, size, size)
}

fn agent(x: f32, z: f32, rotation: Option<f32>) -> AgentSpec {
    AgentSpec { position: [Some(x), Some(z)], y: 0.0, rotation }
}

fn layout(name: &str, objects: Vec<ObjectSpec>, agent: AgentSpec) -> Layout {
    Layout { name: name.to_string(), t: DEFAULT_T, objects, agent, blackouts: Default::default() }
}

impl Task {
    /// The task with `heading` applied to its layouts that fix the agent's position but not its
    /// heading (only the double T-maze's corners among the presets).
    pub fn with_start_heading(mut self, heading: StartHeading) -> Task {
        if heading == StartHeading::Fixed {
            for l in &mut self.layouts {
                if let (None, [Some(x), Some(z)]) = (l.agent.rotation, l.agent.position) {
                    l.agent.rotation = Some(facing_centre(x, z));
                }
            }
        }
        self
    }

    /// A built-in task by name (its row of `TASKS`); every preset uses t = 1000 (the paper's
    /// limit).
    pub fn preset(name: &str) -> Result<Task, ConfigError> {
        let info = TaskInfo::find(name)?;
        Ok(Task {
            name: name.to_string(),
            description: info.description.to_string(),
            layouts: (info.layouts)(),
            warnings: Vec::new(),
        })
    }
}

/// One built-in task, declared once: the page, Python (its Gymnasium id) and the CLI read this
/// table. Adding a task is its layouts, a row here, and its trained model in
/// `assets/encoders/<name>.secae` (`sec-train` makes it).
#[derive(Clone, Copy, Debug, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct TaskInfo {
    /// Its name everywhere (`RunConfig.task`, the URL hash, the CLI).
    pub name: &'static str,
    /// As the page writes it in a sentence ("the double T-maze").
    pub title: &'static str,
    /// What it is and where it comes from.
    pub description: &'static str,
    /// Its Gymnasium id (`sec_playground` registers it).
    pub gym_id: &'static str,
    /// Its trained autoencoder's file, under `assets/encoders/` (the page fetches it).
    pub model_file: &'static str,
    /// Its start layouts.
    #[serde(skip)]
    pub layouts: fn() -> Vec<Layout>,
    /// Its trained autoencoder, compiled into native builds (empty in the wasm build, where the
    /// page registers the one it fetched).
    #[serde(skip)]
    pub model: &'static [u8],
    /// Its autoencoder trained on textured frames (`render::Surface::Textured`), compiled in like
    /// `model`; empty where none is trained yet (a textured run of the task is then refused).
    #[serde(skip)]
    pub textured_model: &'static [u8],
}

/// A model file's bytes in native builds; none in the wasm build.
macro_rules! model {
    ($file:literal) => {{
        #[cfg(not(target_arch = "wasm32"))]
        let bytes: &[u8] = include_bytes!(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/encoders/", $file));
        #[cfg(target_arch = "wasm32")]
        let bytes: &[u8] = &[];
        bytes
    }};
}

/// The built-in tasks, in the order the page lists them.
pub const TASKS: [TaskInfo; 6] = [
    TaskInfo {
        name: "double-t-maze",
        title: "the double T-maze",
        description: "SEC's double T-maze (arena_generator_lvl4.py): four corner rooms, a goal chamber open to \
             the west and east, goal size 3 (+2.997). Four layouts, one per corner start, random heading.",
        gym_id: "SecPlayground/DoubleTMaze-v0",
        model_file: "double-t-maze.secae",
        layouts: double_t_maze,
        model: model!("double-t-maze.secae"),
        textured_model: model!("double-t-maze-textured.secae"),
    },
    TaskInfo {
        name: "detour",
        title: "the detour",
        description: "Olympics 3-4-1 and 3-4-2, what SEC ran: a 0.5-high grey wall with the size-1 goal (+0.999) \
             visible above it; the way round is the west gap.",
        gym_id: "SecPlayground/Detour-v0",
        model_file: "detour.secae",
        layouts: || vec![detour("3-4-1", 10.0), detour("3-4-2", 15.0)],
        model: model!("detour.secae"),
        textured_model: &[],
    },
    TaskInfo {
        name: "detour-transparent",
        title: "the transparent detour",
        description: "Olympics 3-5-1, the paper's wording: a 3-high transparent wall with the goal behind it.",
        gym_id: "SecPlayground/DetourTransparent-v0",
        model_file: "detour-transparent.secae",
        layouts: || vec![detour_transparent()],
        model: model!("detour-transparent.secae"),
        textured_model: &[],
    },
    TaskInfo {
        name: "cylinder",
        title: "the cylinder",
        description: "Olympics 3-13-1 with SEC's goal size 2 (+1.998): a grey arch seen side-on hides the goal; \
             the agent must go round and enter along its axis.",
        gym_id: "SecPlayground/Cylinder-v0",
        model_file: "cylinder.secae",
        layouts: || vec![cylinder()],
        model: model!("cylinder.secae"),
        textured_model: &[],
    },
    TaskInfo {
        name: "object-permanence",
        title: "object permanence",
        description: "Olympics 8-7-1/2/3: a size-3 goal drops behind a 4-high wall and disappears; a small \
             visible goal (+0.999) is the local optimum.",
        gym_id: "SecPlayground/ObjectPermanence-v0",
        model_file: "object-permanence.secae",
        layouts: || permanence_layouts(false),
        model: model!("object-permanence.secae"),
        textured_model: &[],
    },
    TaskInfo {
        name: "object-permanence-pits",
        title: "object permanence with pits",
        description: "Object permanence with the paper's holes: 8-7 plus three DeathZone pits (-1, episode ends) \
             off the route around the wall.",
        gym_id: "SecPlayground/ObjectPermanencePits-v0",
        model_file: "object-permanence-pits.secae",
        layouts: || permanence_layouts(true),
        model: model!("object-permanence-pits.secae"),
        textured_model: &[],
    },
];

/// The built-in tasks' names, in the table's order.
pub const TASK_NAMES: [&str; TASKS.len()] = {
    let mut names = [""; TASKS.len()];
    let mut i = 0;
    while i < TASKS.len() {
        names[i] = TASKS[i].name;
        i += 1;
    }
    names
};

impl TaskInfo {
    /// The row of `name`; another name is refused, listing the tasks.
    pub fn find(name: &str) -> Result<&'static TaskInfo, ConfigError> {
        TASKS.iter().find(|t| t.name == name).ok_or_else(|| {
            ConfigError::new(
                "task",
                format!("unknown task '{}'; one of {}", crate::util::shown(name), TASK_NAMES.join(", ")),
            )
        })
    }
}

/// Object permanence's three layouts, with or without the pits.
fn permanence_layouts(pits: bool) -> Vec<Layout> {
    let suffix = if pits { "-pits" } else { "" };
    [25.0, 27.0, 23.0]
        .iter()
        .enumerate()
        .map(|(i, &r)| permanence(&format!("8-7-{}{suffix}", i + 1), r, pits))
        .collect()
}

/// The 14 walls of docs/ARENAS.md section 7.1, in the generator's order.
fn double_t_maze() -> Vec<Layout> {
    const BLUE: (u8, u8, u8) = (0, 0, 250);
    const RED: (u8, u8, u8) = (250, 0, 0);
    const MAGENTA: (u8, u8, u8) = (250, 0, 250);
    let objects = vec![
        wall(19.0, 36.0, (2.0, 5.0, 8.0), BLUE),
        wall(21.0, 36.0, (2.0, 5.0, 8.0), RED),
        wall(19.0, 4.0, (2.0, 5.0, 8.0), RED),
        wall(21.0, 4.0, (2.0, 5.0, 8.0), BLUE),
        wall(3.0, 20.0, (2.0, 2.0, 24.0), (0, 250, 250)),
        wall(37.0, 20.0, (2.0, 2.0, 24.0), (250, 250, 0)),
        wall(33.0, 7.0, (14.0, 5.0, 2.0), GREY),
        wall(33.0, 33.0, (14.0, 5.0, 2.0), GREY),
        wall(20.0, 25.0, (14.0, 5.0, 1.0), GREY),
        wall(20.0, 26.0, (14.0, 5.0, 1.0), MAGENTA),
        wall(20.0, 14.0, (14.0, 5.0, 1.0), MAGENTA),
        wall(20.0, 15.0, (14.0, 5.0, 1.0), GREY),
        wall(7.0, 7.0, (14.0, 5.0, 2.0), GREY),
        wall(7.0, 33.0, (14.0, 5.0, 2.0), GREY),
        goal(ObjectKind::GoodGoal, 20.0, 0.0, 20.0, 3.0).size(3.0, 1.0, 1.0),
    ];
    [(3.0, 37.0), (37.0, 37.0), (3.0, 3.0), (37.0, 3.0)]
        .iter()
        .enumerate()
        .map(|(i, &(x, z))| layout(&format!("corner-{}", i + 1), objects.clone(), agent(x, z, None)))
        .collect()
}

fn detour(name: &str, agent_x: f32) -> Layout {
    layout(
        name,
        vec![
            wall(20.0, 37.0, (35.0, 0.5, 1.0), GREY),
            wall(30.0, 38.75, (1.0, 0.5, 2.5), GREY),
            goal(ObjectKind::GoodGoal, 5.0, 0.0, 38.0, 1.0),
        ],
        agent(agent_x, 1.0, Some(0.0)),
    )
}

fn detour_transparent() -> Layout {
    let glass = |x, z, s: (f32, f32, f32)| ObjectSpec::new(ObjectKind::WallTransparent, x, 0.0, z).size(s.0, s.1, s.2);
    layout(
        "3-5-1",
        vec![
            glass(20.0, 37.0, (35.0, 3.0, 1.0)),
            glass(20.0, 38.75, (1.0, 0.5, 2.5)),
            goal(ObjectKind::GoodGoal, 5.0, 0.0, 38.0, 1.0),
        ],
        agent(10.0, 1.0, Some(0.0)),
    )
}

fn cylinder() -> Layout {
    layout(
        "3-13-1",
        vec![
            ObjectSpec::new(ObjectKind::CylinderTunnel, 20.0, 0.0, 20.0)
                .size(10.0, 10.0, 10.0)
                .rotation(135.0)
                .colour(GREY.0, GREY.1, GREY.2),
            goal(ObjectKind::GoodGoal, 20.0, 0.0, 20.0, 2.0).size(2.0, 1.0, 1.0),
        ],
        agent(1.0, 1.0, Some(45.0)),
    )
}

/// 8-7: a 4-high wall, a size-3 goal dropped from y = 10 behind it, a small goal beside the route.
/// The pit variant adds DeathZones clear of the route round the wall's east end (a project
/// proposal: the paper's "holes"; docs/ARENAS.md section 7.2).
fn permanence(name: &str, rotation: f32, pits: bool) -> Layout {
    let mut objects = vec![
        wall(10.0, 30.0, (20.0, 4.0, 1.0), GREY),
        goal(ObjectKind::GoodGoal, 10.0, 10.0, 35.0, 3.0),
        goal(ObjectKind::GoodGoal, 20.0, 0.0, 25.0, 1.0),
    ];
    if pits {
        let pit = |x, z, sx, sz| ObjectSpec::new(ObjectKind::DeathZone, x, 0.0, z).size(sx, 0.0, sz);
        objects.push(pit(30.0, 35.0, 8.0, 6.0));
        objects.push(pit(32.0, 16.0, 6.0, 6.0));
        objects.push(pit(8.0, 20.0, 6.0, 4.0));
    }
    layout(name, objects, agent(5.0, 5.0, Some(rotation)))
}

/// The heading (degrees clockwise from +z, docs/ARENAS.md section 2) that faces the arena's centre
/// from (x, z); 0 at the centre itself.
pub fn facing_centre(x: f32, z: f32) -> f32 {
    let half = super::ARENA_SIZE as f64 / 2.0;
    let (dx, dz) = (half - x as f64, half - z as f64);
    if dx == 0.0 && dz == 0.0 {
        return 0.0;
    }
    let deg = libm::atan2(dx, dz).to_degrees();
    (if deg < 0.0 { deg + 360.0 } else { deg }) as f32
}
