//! The Gymnasium-style environment: `reset(seed)`, `step(action)`: an arena of `crate::arena`
//! (its world and physics) drawn by `crate::render`'s camera. It sits above both, so neither
//! the world nor the renderer knows of the other's use here.

#[cfg(feature = "test-hooks")]
pub mod trace;

use crate::arena::physics::{physics_frame, FrameEvents, FRAMES_PER_STEP};
use crate::arena::{check_range, Action, ConfigError, Task, World, MAX_T};
use crate::render::{Camera, Frame, Surface};
use crate::seed::Stream;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// What the environment is: the task, and an optional override of its episode limit.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvConfig {
    /// The task whose layouts the episodes cycle through.
    pub task: Task,
    /// Episode limit in env steps; `None` keeps each layout's own `t`.
    pub t: Option<u32>,
    /// How the camera draws the floor and fences.
    pub surface: Surface,
}

impl EnvConfig {
    /// The task with its own episode limits.
    pub fn new(task: Task) -> Self {
        EnvConfig { task, t: None, surface: Surface::Flat }
    }
    /// Every field in its range, the error naming it.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if let Some(t) = self.t {
            if t > MAX_T {
                return Err(ConfigError::new("t", format!("{t} is out of range 0..={MAX_T}")));
            }
        }
        for l in &self.task.layouts {
            l.validate()?;
        }
        if self.task.layouts.is_empty() {
            return Err(ConfigError::new("task", "has no layout"));
        }
        Ok(())
    }
}

/// Reward and end flags of one (possibly held) step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepOutcome {
    /// Sum of rewards over the env steps taken: goals, zones and the -1/t time penalty.
    pub reward: f64,
    /// The episode ended on a goal, a bad goal or a death zone.
    pub terminated: bool,
    /// The episode ran out of time (t env steps).
    pub truncated: bool,
    /// A good goal was touched (SEC stores a sequence on this event).
    pub good_goal: bool,
    /// Env steps actually taken (fewer than asked when the episode ended early).
    pub env_steps: u32,
}

/// What `step` returns, in Gymnasium's order.
#[derive(Debug)]
pub struct Step<'a> {
    /// The camera image after the step.
    pub observation: &'a Frame,
    /// The step's reward.
    pub reward: f64,
    /// The episode ended by a goal or a death zone.
    pub terminated: bool,
    /// The episode ended by the time limit.
    pub truncated: bool,
    /// What else happened (goal touched, position, heading).
    pub info: StepOutcome,
}

/// An Animal-AI arena with v1 physics and the agent's 84x84 camera, with Gymnasium's reset and
/// step.
///
/// ```
/// use sec_playground::arena::{Action, Task};
/// use sec_playground::env::{Env, EnvConfig};
/// let mut env = Env::new(EnvConfig::new(Task::preset("double-t-maze")?), 42)?;
/// let first = env.reset(Some(42));
/// assert_eq!(first.rgba.len(), 84 * 84 * 4);
/// let step = env.step(Action::FORWARD)?; // observation, reward, terminated, truncated
/// assert!(step.reward < 0.0 && !step.terminated, "a step costs 1/t");
/// # Ok::<(), sec_playground::arena::ConfigError>(())
/// ```
#[derive(Clone, Debug)]
pub struct Env {
    config: EnvConfig,
    rng: ChaCha8Rng,
    /// Layout order for this run: shuffled once per seed, then cycled one per episode.
    order: Vec<usize>,
    episode: u64,
    layout: usize,
    world: World,
    steps: u32,
    over: bool,
    camera: Camera,
    frame: Frame,
    frame_fresh: bool,
    /// Counts the changes of what the camera shows: two observations of one serial are the
    /// same image, so a caller can skip what it did with the last one.
    view_serial: u64,
    /// Scratch for `advance`: what the camera depends on before and after the step.
    view_before: Vec<u32>,
    view_after: Vec<u32>,
    /// The pushable boxes' rigid bodies, built at each reset of a layout that has some.
    #[cfg(feature = "pushables")]
    bodies: Option<crate::arena::push::Bodies>,
}

impl Env {
    /// Builds the environment and resets it with `seed`.
    pub fn new(config: EnvConfig, seed: u64) -> Result<Env, ConfigError> {
        config.validate()?;
        for l in &config.task.layouts {
            World::check_room(l)
                .map_err(|m| ConfigError::new("layout", format!("'{}': {m}", crate::util::shown(&l.name))))?;
        }
        let rng = crate::seed::rng(seed, Stream::Env);
        let world = World::spawn(&config.task.layouts[0], &mut rng.clone());
        let camera = Camera::with_surface(config.surface);
        let mut env = Env {
            config,
            rng,
            order: Vec::new(),
            episode: 0,
            layout: 0,
            world,
            steps: 0,
            over: false,
            camera,
            frame: Frame::new(),
            frame_fresh: false,
            view_serial: 0,
            view_before: Vec::new(),
            view_after: Vec::new(),
            #[cfg(feature = "pushables")]
            bodies: None,
        };
        env.reset(Some(seed));
        Ok(env)
    }

    /// Starts an episode. With a seed, the run restarts: the generator is reseeded, the layout
    /// order reshuffled and the episode count zeroed. Without one, the next layout in the cycle.
    pub fn reset(&mut self, seed: Option<u64>) -> &Frame {
        match seed {
            Some(s) => {
                self.rng = crate::seed::rng(s, Stream::Env);
                let n = self.config.task.layouts.len();
                self.order = (0..n).collect();
                // Fisher-Yates with u32 draws: the same order on 32- and 64-bit targets.
                for i in (1..n).rev() {
                    let j = self.rng.gen_range(0..=i as u32) as usize;
                    self.order.swap(i, j);
                }
                self.episode = 0;
            }
            None => self.episode += 1,
        }
        self.layout = self.order[(self.episode % self.order.len() as u64) as usize];
        self.world = World::spawn(&self.config.task.layouts[self.layout], &mut self.rng);
        #[cfg(feature = "pushables")]
        {
            self.bodies = (!self.world.pushed.is_empty()).then(|| crate::arena::push::Bodies::new(&self.world));
        }
        self.steps = 0;
        self.over = false;
        self.view_changed();
        self.observation()
    }

    /// One env step (3 physics frames) with the action applied in each frame.
    pub fn step(&mut self, action: Action) -> Result<Step<'_>, ConfigError> {
        self.step_held(action, 1)
    }

    /// Holds the action for `k` env steps (SEC decides every 4) and renders once at the end.
    pub fn step_held(&mut self, action: Action, k: u32) -> Result<Step<'_>, ConfigError> {
        let info = self.advance(action, k)?;
        Ok(Step {
            observation: self.observation(),
            reward: info.reward,
            terminated: info.terminated,
            truncated: info.truncated,
            info,
        })
    }

    /// The physics of `step_held` without rendering, for speed when nobody looks.
    pub fn advance(&mut self, action: Action, k: u32) -> Result<StepOutcome, ConfigError> {
        check_range("k", k as f32, 1.0, 1000.0)?;
        if self.over {
            return Err(ConfigError::new("step", "the episode is over: call reset first"));
        }
        let (movement, turn) = action.branches();
        let t = self.t();
        let penalty = if t > 0 { -1.0 / t as f64 } else { 0.0 };
        let hot = if t > 0 { (-10.0 / (3.0 * t as f64)).min(-1e-5) } else { -1e-5 };
        let mut out = StepOutcome::default();
        self.world.view_key(&mut self.view_before);
        let lit_before = self.lit();
        for _ in 0..k {
            out.reward += penalty;
            for _ in 0..FRAMES_PER_STEP {
                let ev = self.frame(movement, turn, hot);
                out.reward += ev.reward;
                out.good_goal |= ev.good_goal;
                if ev.terminal {
                    out.terminated = true;
                    break;
                }
            }
            self.steps += 1;
            out.env_steps += 1;
            if !out.terminated && t > 0 && self.steps >= t {
                out.truncated = true;
            }
            if out.terminated || out.truncated {
                self.over = true;
                break;
            }
        }
        // Pressed against a wall or stopped, the agent sees what it saw: the frame stays, unless
        // the light switched.
        self.world.view_key(&mut self.view_after);
        if self.view_after != self.view_before || self.lit() != lit_before {
            self.view_changed();
        }
        Ok(out)
    }

    /// One physics frame, with the pushable boxes' rigid bodies if the layout has any.
    fn frame(&mut self, movement: u8, turn: u8, hot: f64) -> FrameEvents {
        #[cfg(feature = "pushables")]
        let bodies = self.bodies.as_mut().map(|b| b as &mut dyn crate::arena::physics::RigidBodies);
        #[cfg(not(feature = "pushables"))]
        let bodies = None;
        physics_frame(&mut self.world, bodies, movement, turn, hot)
    }

    /// The frame is no longer what the camera shows.
    fn view_changed(&mut self) {
        self.frame_fresh = false;
        self.view_serial += 1;
    }

    /// Which view `observation` shows: it changes whenever the image may (a reset, a step that
    /// moved the agent or a goal or switched the light, `world_mut`), and never otherwise.
    pub fn view_serial(&self) -> u64 {
        self.view_serial
    }

    /// The agent's current view, rendered on demand and cached until the world changes.
    pub fn observation(&mut self) -> &Frame {
        if !self.frame_fresh {
            if self.lit() {
                self.camera.render(&self.world, &mut self.frame);
            } else {
                // v1 sends a black texture while the light is off (docs/ARENAS.md section 6).
                self.frame.rgba.chunks_exact_mut(4).for_each(|p| p.copy_from_slice(&[0, 0, 0, 255]));
            }
            self.frame_fresh = true;
        }
        &self.frame
    }

    /// Whether the arena's light is on now (its layout's `blackouts` at this env step).
    pub fn lit(&self) -> bool {
        self.config.task.layouts[self.layout].blackouts.lit(self.steps)
    }

    /// The episode limit in force: the override, else the layout's own.
    pub fn t(&self) -> u32 {
        self.config.t.unwrap_or(self.config.task.layouts[self.layout].t)
    }
    /// The arena's current state.
    pub fn world(&self) -> &World {
        &self.world
    }
    /// Direct access for tests, tools and the "drive it yourself" mode; the cached observation
    /// is dropped because the world may change.
    pub fn world_mut(&mut self) -> &mut World {
        self.view_changed();
        &mut self.world
    }
    /// Its configuration.
    pub fn config(&self) -> &EnvConfig {
        &self.config
    }
    /// Env steps taken in this episode.
    pub fn steps(&self) -> u32 {
        self.steps
    }
    /// Episodes since the last seeded reset (0 for the first).
    pub fn episode(&self) -> u64 {
        self.episode
    }
    /// Name of the layout this episode uses.
    pub fn layout_name(&self) -> &str {
        &self.config.task.layouts[self.layout].name
    }
    /// Whether the episode has ended (a reset starts the next).
    pub fn is_over(&self) -> bool {
        self.over
    }
}
