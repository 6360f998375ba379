//! The Animal-AI v1 arenas that SEC was evaluated on (docs/ARENAS.md).
//!
//! A [`Task`] is a list of start [`Layout`]s (what a YAML arena file describes); [`World`] is one
//! layout instantiated with its random parts drawn; `physics` steps a world with the v1
//! dynamics. The Gymnasium-style env that draws it is `crate::env`, above this and the renderer.

mod action;
pub mod physics;
#[cfg(feature = "pushables")]
pub mod push;
pub mod survey;
mod tasks;
mod world;
pub mod yaml;

pub use crate::error::ConfigError;
pub use action::Action;
pub use physics::{DRAG_FACTOR, FRAMES_PER_STEP, FRAME_DT, FRICTION_DV, GRAVITY, IMPULSE_DV, TURN_DEGREES};
pub use tasks::{facing_centre, StartHeading, Task, TaskInfo, TASKS, TASK_NAMES};
pub use world::{
    support, Agent, BoxObj, Collider, Footprint, Goal, Pushable, Ramp, Support, Tunnel, World, Zone, AGENT_RADIUS,
    CARDBOARD, WOOD,
};

/// Side of the square arena, metres; the fences' inner faces are at 0 and 40.
pub const ARENA_SIZE: f32 = 40.0;
/// Default episode limit in env steps (the paper's 1000 for every task).
pub const DEFAULT_T: u32 = 1000;
/// Largest accepted episode limit: 100,000 env steps is over half an hour of simulated time.
pub const MAX_T: u32 = 100_000;
/// Highest an arena file may place an object, metres: v1 sets no bound, the Olympics corpus goes
/// to 1500 (05-30 drops a box from there).
pub const MAX_OBJECT_Y: f32 = 2000.0;
/// Highest it may place the agent, metres.
pub const MAX_AGENT_Y: f32 = 100.0;
/// Animal-AI scales every clamped size by this (`sizeAdjustement` in the prefabs).
pub const SIZE_ADJUST: f32 = 0.999;

/// An 8-bit RGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Rgb(pub u8, pub u8, pub u8);

/// The objects of the Animal-AI catalogue this simulator implements (docs/ARENAS.md section 5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ObjectKind {
    /// An opaque wall block.
    Wall,
    /// A see-through wall block.
    WallTransparent,
    /// A wedge rising towards its local -z, which the agent climbs.
    Ramp,
    /// An arch the agent can walk through.
    CylinderTunnel,
    /// A see-through arch.
    CylinderTunnelTransparent,
    /// A green sphere: positive reward, ends the episode.
    GoodGoal,
    /// A red sphere: negative reward, ends the episode.
    BadGoal,
    /// A gold sphere: positive reward, collected without ending the episode.
    GoodGoalMulti,
    /// A GoodGoal launched along its rotation when it spawns (v1's `BallGoalBounce`): it rolls
    /// and bounces off walls.
    GoodGoalBounce,
    /// A BadGoal launched likewise.
    BadGoalBounce,
    /// A GoodGoalMulti launched likewise.
    GoodGoalMultiBounce,
    /// A red floor zone: reward -1, ends the episode.
    DeathZone,
    /// An orange floor zone: a penalty per step on it.
    HotZone,
    /// A cardboard box the agent pushes, of mass 1 (a rigid body: `push`).
    Cardbox1,
    /// A heavier one, of mass 2.
    Cardbox2,
    /// A wooden U the agent pushes: a long bar with an arm at each end (mass 1.5).
    UObject,
    /// A wooden L: the bar with one arm.
    LObject,
    /// The L's mirror image.
    LObject2,
}

impl ObjectKind {
    /// Every kind, in the catalogue's order.
    pub const ALL: [ObjectKind; 18] = [
        ObjectKind::Wall,
        ObjectKind::WallTransparent,
        ObjectKind::Ramp,
        ObjectKind::CylinderTunnel,
        ObjectKind::CylinderTunnelTransparent,
        ObjectKind::GoodGoal,
        ObjectKind::BadGoal,
        ObjectKind::GoodGoalMulti,
        ObjectKind::GoodGoalBounce,
        ObjectKind::BadGoalBounce,
        ObjectKind::GoodGoalMultiBounce,
        ObjectKind::DeathZone,
        ObjectKind::HotZone,
        ObjectKind::Cardbox1,
        ObjectKind::Cardbox2,
        ObjectKind::UObject,
        ObjectKind::LObject,
        ObjectKind::LObject2,
    ];

    /// The prefab name used in YAML files.
    pub fn name(self) -> &'static str {
        match self {
            ObjectKind::Wall => "Wall",
            ObjectKind::WallTransparent => "WallTransparent",
            ObjectKind::Ramp => "Ramp",
            ObjectKind::CylinderTunnel => "CylinderTunnel",
            ObjectKind::CylinderTunnelTransparent => "CylinderTunnelTransparent",
            ObjectKind::GoodGoal => "GoodGoal",
            ObjectKind::BadGoal => "BadGoal",
            ObjectKind::GoodGoalMulti => "GoodGoalMulti",
            ObjectKind::GoodGoalBounce => "GoodGoalBounce",
            ObjectKind::BadGoalBounce => "BadGoalBounce",
            ObjectKind::GoodGoalMultiBounce => "GoodGoalMultiBounce",
            ObjectKind::DeathZone => "DeathZone",
            ObjectKind::HotZone => "HotZone",
            ObjectKind::Cardbox1 => "Cardbox1",
            ObjectKind::Cardbox2 => "Cardbox2",
            ObjectKind::UObject => "UObject",
            ObjectKind::LObject => "LObject",
            ObjectKind::LObject2 => "LObject2",
        }
    }

    /// The kind of an Animal-AI object name (`GoodGoal`, ...), if this build simulates it (the
    /// pushable boxes need the `pushables` feature).
    pub fn from_name(name: &str) -> Option<ObjectKind> {
        ObjectKind::ALL.into_iter().filter(|k| k.simulated()).find(|k| k.name() == name)
    }

    /// Whether this build simulates it: every kind, but a pushable object only with the rigid
    /// bodies of the `pushables` feature.
    pub fn simulated(self) -> bool {
        cfg!(feature = "pushables") || self.mass().is_none()
    }

    /// A pushable object's mass in kg (v1's prefabs' rigid bodies: Cardbox1 1, Cardbox2 2, the U
    /// and L objects 3); `None` for what does not move when pushed.
    pub fn mass(self) -> Option<f32> {
        match self {
            ObjectKind::Cardbox1 => Some(1.0),
            ObjectKind::Cardbox2 => Some(2.0),
            ObjectKind::UObject | ObjectKind::LObject | ObjectKind::LObject2 => Some(3.0),
            _ => None,
        }
    }

    /// A pushable object's friction (v1's prefabs: Unity's default 0.6 for Cardbox1, the
    /// `LowFriction` material's 0.5 for the others), averaged with what it touches.
    pub fn friction(self) -> f32 {
        match self {
            ObjectKind::Cardbox1 => 0.6,
            _ => 0.5,
        }
    }

    /// A pushable object's shape, from v1's prefab (docs/ARENAS.md section 5): each of its boxes
    /// as its centre and size along the prefab's own x and z, in the prefab's units (every box
    /// spans the object's whole height); the prefab's scale per unit of size along x and z (its
    /// `ratioSize`); and the prefab's own turn, in degrees, to which v1 adds the file's rotation
    /// (it turns the instance by it). A box's half-turn changes nothing and is left out. Empty
    /// for what is not pushable.
    pub fn prefab_boxes(self) -> (&'static [[f32; 4]], [f32; 2], f32) {
        // The bar: a unit cube scaled (10, 0.99, 0.99) and turned 90 degrees in the prefab; the
        // arms: unit cubes scaled (1, 1, 3), turned likewise, at (+-1, +-5).
        const BAR: [f32; 4] = [0.0, 0.0, 0.99, 10.0];
        const U_L: [f32; 2] = [0.3, 0.1];
        match self {
            ObjectKind::Cardbox1 | ObjectKind::Cardbox2 => (&[[0.0, 0.0, 1.0, 1.0]], [1.0, 1.0], 0.0),
            ObjectKind::UObject => (&[BAR, [1.0, 5.0, 3.0, 1.0], [1.0, -5.0, 3.0, 1.0]], U_L, 90.0),
            ObjectKind::LObject => (&[BAR, [1.0, -5.0, 3.0, 1.0]], U_L, 90.0),
            ObjectKind::LObject2 => (&[BAR, [-1.0, -5.0, 3.0, 1.0]], U_L, 90.0),
            _ => (&[], [1.0, 1.0], 0.0),
        }
    }

    /// Allowed size per axis, before the 0.999 adjustment (docs/ARENAS.md section 5). Sizes outside
    /// are refused rather than clamped, so a config never silently means something else.
    pub fn size_range(self) -> ([f32; 3], [f32; 3]) {
        match self {
            ObjectKind::Wall | ObjectKind::WallTransparent => ([0.1; 3], [40.0, 10.0, 40.0]),
            ObjectKind::Ramp => ([0.5, 0.1, 0.5], [40.0, 10.0, 40.0]),
            ObjectKind::CylinderTunnel | ObjectKind::CylinderTunnelTransparent => ([2.5; 3], [10.0; 3]),
            k if k.is_goal() => ([0.5; 3], [5.0; 3]),
            ObjectKind::Cardbox1 | ObjectKind::Cardbox2 => ([0.5; 3], [10.0; 3]),
            ObjectKind::UObject | ObjectKind::LObject | ObjectKind::LObject2 => ([1.0, 0.3, 3.0], [5.0, 2.0, 20.0]),
            _ => ([1.0, 0.0, 1.0], [40.0, 10.0, 40.0]),
        }
    }

    /// The size used when a config gives none (Animal-AI's prefab defaults).
    pub fn default_size(self) -> [f32; 3] {
        match self {
            ObjectKind::Wall | ObjectKind::WallTransparent | ObjectKind::Ramp => [1.0, 1.0, 1.0],
            ObjectKind::CylinderTunnel | ObjectKind::CylinderTunnelTransparent => [5.0, 5.0, 5.0],
            // The prefab at its own scale, 1 on every axis (its `ratioSize` is 0.3, 1, 0.1).
            ObjectKind::UObject | ObjectKind::LObject | ObjectKind::LObject2 => [1.0 / 0.3, 1.0, 10.0],
            k if k.is_goal() || k.mass().is_some() => [1.0, 1.0, 1.0],
            _ => [1.0, 0.0, 1.0],
        }
    }

    /// Whether a config may give this object a colour (goals and zones have fixed materials).
    pub fn colourable(self) -> bool {
        matches!(self, ObjectKind::Wall | ObjectKind::Ramp | ObjectKind::CylinderTunnel)
    }

    /// Whether touching it is a goal (good, bad or multi, bouncing or not).
    pub fn is_goal(self) -> bool {
        matches!(self.unbounced(), ObjectKind::GoodGoal | ObjectKind::BadGoal | ObjectKind::GoodGoalMulti)
    }

    /// The goal whose reward, ending and look a bouncing goal has; every other kind is its own.
    pub fn unbounced(self) -> ObjectKind {
        match self {
            ObjectKind::GoodGoalBounce => ObjectKind::GoodGoal,
            ObjectKind::BadGoalBounce => ObjectKind::BadGoal,
            ObjectKind::GoodGoalMultiBounce => ObjectKind::GoodGoalMulti,
            k => k,
        }
    }

    /// Whether it is launched when it spawns.
    pub fn bounces(self) -> bool {
        self.unbounced() != self
    }
}

/// One object of a layout. `None` stands for Animal-AI's `-1`: drawn at random on every reset.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectSpec {
    /// What the object is.
    pub kind: ObjectKind,
    /// x, y (bottom of the object), z.
    pub position: [Option<f32>; 3],
    /// Degrees about +y, clockwise seen from above.
    pub rotation: Option<f32>,
    /// Config size per axis (before the 0.999 adjustment); `None` per axis is random in range.
    pub size: [Option<f32>; 3],
    /// `None` for a colourable object means a random colour.
    pub colour: Option<Rgb>,
}

impl ObjectSpec {
    /// An object of `kind` at (x, y, z), unrotated, of its default size and a random colour.
    pub fn new(kind: ObjectKind, x: f32, y: f32, z: f32) -> Self {
        ObjectSpec {
            kind,
            position: [Some(x), Some(y), Some(z)],
            rotation: Some(0.0),
            size: kind.default_size().map(Some),
            colour: None,
        }
    }
    /// With this size per axis.
    pub fn size(mut self, sx: f32, sy: f32, sz: f32) -> Self {
        self.size = [Some(sx), Some(sy), Some(sz)];
        self
    }
    /// With this rotation (degrees about +y).
    pub fn rotation(mut self, degrees: f32) -> Self {
        self.rotation = Some(degrees);
        self
    }
    /// With this colour.
    pub fn colour(mut self, r: u8, g: u8, b: u8) -> Self {
        self.colour = Some(Rgb(r, g, b));
        self
    }
}

/// Where the agent starts; `None` parts are random (a free spot, any heading).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct AgentSpec {
    /// x and z.
    pub position: [Option<f32>; 2],
    /// The height of the agent's bottom as the file places it (0: on the floor); it falls onto
    /// whatever is under it.
    pub y: f32,
    /// Degrees about +y.
    pub rotation: Option<f32>,
}

/// One arena configuration: what one `!Arena` of a YAML file describes.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// Its name (the YAML file's, with the arena's index).
    pub name: String,
    /// Episode limit in env steps; 0 means no limit (and no time penalty).
    pub t: u32,
    /// Its objects.
    pub objects: Vec<ObjectSpec>,
    /// Where the agent starts.
    pub agent: AgentSpec,
    /// Lights-off switches, in env steps (`blackouts`; empty: always lit).
    pub blackouts: Blackouts,
}

/// v1's lights (`TrainEnv/Scripts/Lights.cs`, `LightsSwitch`): a list of env steps at which the
/// light switches, off first, or one negative number -n, a switch every n steps. The camera sees
/// black while the light is off (`Agent.SendInfoToBrain` sends a black texture); nothing else
/// changes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Blackouts(pub Vec<i32>);

impl Blackouts {
    /// Whether the light is on at env step `step` of an episode (0 at reset). v1 waits for the
    /// list's next entry with each step, so only its strictly increasing head ever switches.
    pub fn lit(&self, step: u32) -> bool {
        let step = step as i64;
        let switches = match self.0.first() {
            None => 0,
            Some(&first) if first < 0 => step / -(first as i64),
            Some(_) => {
                let mut last = i64::MIN;
                let mut n = 0;
                for &e in &self.0 {
                    let e = e as i64;
                    if e <= last || e > step {
                        break;
                    }
                    last = e;
                    n += 1;
                }
                n
            }
        };
        switches % 2 == 0
    }
}

impl Layout {
    /// Checks every value against the catalogue's ranges; the YAML loader reports the same
    /// problems with line numbers, this guards layouts built in code.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if self.t > MAX_T {
            return Err(ConfigError::new("t", format!("{} is out of range 0..={MAX_T}", self.t)));
        }
        for (i, o) in self.objects.iter().enumerate() {
            let (lo, hi) = o.kind.size_range();
            for (axis, s) in o.size.iter().enumerate() {
                if let Some(s) = *s {
                    check_range(&format!("objects[{i}].size.{}", AXES[axis]), s, lo[axis], hi[axis])?;
                }
            }
            for (axis, p) in o.position.iter().enumerate() {
                if let Some(p) = *p {
                    let hi = if axis == 1 { MAX_OBJECT_Y } else { ARENA_SIZE };
                    check_range(&format!("objects[{i}].position.{}", AXES[axis]), p, 0.0, hi)?;
                }
            }
            if let Some(r) = o.rotation {
                check_range(&format!("objects[{i}].rotation"), r, -360.0, 360.0)?;
            }
        }
        for (axis, p) in self.agent.position.iter().enumerate() {
            if let Some(p) = *p {
                check_range(
                    &format!("agent.position.{}", ["x", "z"][axis]),
                    p,
                    AGENT_RADIUS,
                    ARENA_SIZE - AGENT_RADIUS,
                )?;
            }
        }
        check_range("agent.position.y", self.agent.y, 0.0, MAX_AGENT_Y)?;
        if let Some(r) = self.agent.rotation {
            check_range("agent.rotation", r, -360.0, 360.0)?;
        }
        Ok(())
    }
}

pub(crate) const AXES: [&str; 3] = ["x", "y", "z"];

/// Refuses NaN and values outside `[lo, hi]`, naming the field and the range.
pub(crate) fn check_range(field: &str, v: f32, lo: f32, hi: f32) -> Result<(), ConfigError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(ConfigError::new(field, format!("{v} is out of range {lo}..={hi}")))
    }
}
