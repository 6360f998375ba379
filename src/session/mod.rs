//! A run as a front end drives it: the page's worker (`web::run`), Python's `Run` and the
//! CLI are thin adapters over `Session`, which owns what they would otherwise each re-do:
//! parsing a configuration (`RunConfig::from_json`), live changes and restarts, stepping by
//! decisions or episodes, the views and the explanation of a decision, the top-down trail, the
//! memory maps, memory files and driving.

mod view;

pub use view::{DecisionView, Explanation};

use crate::agent::Decision;
use crate::arena::ConfigError;
use crate::error::Error;
use crate::experiment::{AgentFactory, Driver, EpisodeMetrics, Run, RunConfig, Tick};
use crate::render::Trail;

/// Most decisions one `run_decisions` call may run (keeps a front end's time slice bounded).
pub const MAX_BATCH: u32 = 100_000;

/// What `Session::configure` did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Applied {
    /// The change acts from the next decision, in the same run.
    Live,
    /// The change needs a new run: it restarted, with the same seed.
    Restart,
}

impl Applied {
    /// "live" or "restart", as the page and Python report it.
    pub fn as_str(self) -> &'static str {
        match self {
            Applied::Live => "live",
            Applied::Restart => "restart",
        }
    }
}

/// What `Session::configure_patch` did: "live" or "restart" for the change as a whole, and each
/// field it changed.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ConfigChange {
    /// "live" (the change acts from the next decision) or "restart" (a new run, the same seed).
    pub applied: &'static str,
    /// The fields that changed, in path order.
    pub changed: Vec<crate::experiment::change::FieldChange>,
}

/// The memory maps a view can draw, sequences x STM positions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MemoryMap {
    /// The last decision's biased similarity G.
    G,
    /// The sequential bias T.
    T,
}

impl std::str::FromStr for MemoryMap {
    type Err = ConfigError;
    fn from_str(s: &str) -> Result<Self, ConfigError> {
        match s {
            "g" => Ok(MemoryMap::G),
            "t" => Ok(MemoryMap::T),
            _ => Err(ConfigError::new("which", format!("'{}' is not one of g, t", crate::util::shown(s)))),
        }
    }
}

/// A run with what its front ends show: the last decision, the decisions so far, the trail.
/// The page, Python's `Run` and the CLI drive runs through it.
///
/// ```
/// use sec_playground::session::Session;
/// let mut session = Session::from_json(r#"{"task": "object-permanence", "t": 100}"#, 1)?;
/// session.run_decisions(10)?;
/// let change = session.configure_patch(r#"{"agent": {"memory": {"tau": 0.5}}}"#)?;
/// assert_eq!(change.applied, "live", "tau acts from the next decision, in the same run");
/// assert_eq!((session.decisions(), session.config().t), (10, Some(100)));
/// # Ok::<(), sec_playground::error::Error>(())
/// ```
pub struct Session {
    run: Run,
    extra: Option<AgentFactory>,
    last: Option<Decision>,
    decisions: u64,
    trail: Trail,
}

/// The decisions a resumed session may say it has counted: far beyond any run, far below where
/// counting on overflows.
pub const MAX_DECISIONS: u64 = 1 << 50;

impl Session {
    /// A session of `cfg` with `seed` (see `Run::new`).
    pub fn new(cfg: RunConfig, seed: u64) -> Result<Self, Error> {
        Self::with_agents(cfg, seed, None)
    }

    /// `new`, with `extra` building the agents the core does not hold (DQN natively).
    pub fn with_agents(cfg: RunConfig, seed: u64, extra: Option<AgentFactory>) -> Result<Self, Error> {
        let run = Run::with_agents(cfg, seed, extra)?;
        let trail = Trail::new(run.env().world().agent.pos);
        Ok(Session { run, extra, last: None, decisions: 0, trail })
    }

    /// A session of the run `Run::resume` brings to `checkpoint`, its views counting `decisions`
    /// so far (the last decision itself is not kept: the views show none until the next).
    pub fn resume(
        cfg: RunConfig,
        seed: u64,
        extra: Option<AgentFactory>,
        checkpoint: &mut dyn std::io::Read,
        check: &crate::experiment::checkpoint::ResumeCheck,
        decisions: u64,
    ) -> Result<Self, Error> {
        if decisions > MAX_DECISIONS {
            let message = format!("{decisions} is out of range 0..={MAX_DECISIONS}");
            return Err(crate::error::ConfigError::new("decisions", message).into());
        }
        let run = Run::resume(cfg, seed, extra, checkpoint, check)?;
        let trail = Trail::new(run.env().world().agent.pos);
        Ok(Session { run, extra, last: None, decisions, trail })
    }

    /// Decisions taken so far (what the views count).
    pub fn decisions(&self) -> u64 {
        self.decisions
    }

    /// A session of a JSON configuration (`RunConfig::from_json`).
    pub fn from_json(config: &str, seed: u64) -> Result<Self, Error> {
        Self::new(RunConfig::from_json(config)?, seed)
    }

    /// The run itself.
    pub fn run(&self) -> &Run {
        &self.run
    }

    /// The run, to drive it directly (what it does is not counted in the views' `decisions`).
    pub fn run_mut(&mut self) -> &mut Run {
        &mut self.run
    }

    /// The configuration in force.
    pub fn config(&self) -> &RunConfig {
        self.run.config()
    }

    /// The run's seed.
    pub fn seed(&self) -> u64 {
        self.run.seed()
    }

    /// Applies `cfg`: live when only live parameters changed (`Run::reconfigure`), else a new
    /// run with the same seed. A refused `cfg` is an error and changes nothing.
    pub fn configure(&mut self, cfg: RunConfig) -> Result<Applied, Error> {
        if self.run.reconfigure(cfg.clone())? {
            return Ok(Applied::Live);
        }
        *self = Self::with_agents(cfg, self.seed(), self.extra)?;
        Ok(Applied::Restart)
    }

    /// Applies a partial change (`RunConfig::patched`: a JSON object naming only the fields to
    /// change; the others keep their values) as `configure` does, and says which fields changed
    /// and whether each alone would act live. A refused change is an error and changes nothing.
    pub fn configure_patch(&mut self, patch: &str) -> Result<ConfigChange, Error> {
        let next = self.config().patched(patch)?;
        self.replace_config(next)
    }

    /// `configure` with `next` whole, answered as `configure_patch`.
    pub fn replace_config(&mut self, next: RunConfig) -> Result<ConfigChange, Error> {
        let changed = self.config().changes(&next);
        let applied = self.configure(next)?;
        Ok(ConfigChange { applied: applied.as_str(), changed })
    }

    /// Starts over with `seed` (or the run's own); on an error nothing changes.
    pub fn reset(&mut self, seed: Option<u64>) -> Result<(), Error> {
        let seed = seed.unwrap_or(self.seed());
        *self = Self::with_agents(self.config().clone(), seed, self.extra)?;
        Ok(())
    }

    /// One env step (`Run::tick`), counted.
    pub fn tick(&mut self) -> Tick {
        let t = self.run.tick();
        if t.decision.is_some() {
            self.last = t.decision;
            self.decisions += 1;
        }
        let at = self.run.env().world().agent.pos;
        match t.finished {
            Some(_) => self.trail.restart(at),
            None => self.trail.push(at),
        }
        t
    }

    /// Runs `decisions` decisions (1..=`MAX_BATCH`); returns the episodes they finished.
    pub fn run_decisions(&mut self, decisions: u32) -> Result<Vec<EpisodeMetrics>, ConfigError> {
        if !(1..=MAX_BATCH).contains(&decisions) {
            return Err(ConfigError::new("decisions", format!("{decisions} is out of range 1..={MAX_BATCH}")));
        }
        let mut done = Vec::new();
        let mut left = decisions;
        while left > 0 {
            let t = self.tick();
            left -= t.decision.is_some() as u32;
            done.extend(t.finished);
        }
        Ok(done)
    }

    /// Plays to the next decision, or to the end of the episode if that comes first.
    pub fn step_decision(&mut self) -> Tick {
        loop {
            let t = self.tick();
            if t.decision.is_some() || t.finished.is_some() {
                return t;
            }
        }
    }

    /// Plays the current episode to its end.
    pub fn step_episode(&mut self) -> EpisodeMetrics {
        loop {
            if let Some(m) = self.tick().finished {
                return m;
            }
        }
    }

    /// The last decision and the run's state.
    pub fn view(&mut self) -> DecisionView {
        view::decision_view(&mut self.run, self.last, self.decisions)
    }

    /// The last decision's contextual layer term by term.
    pub fn explain(&self) -> Explanation {
        view::explain(&self.run)
    }

    /// The top-down view with the trail, `size` x `size` RGBA.
    pub fn top_down(&mut self, size: u32) -> Result<&[u8], ConfigError> {
        self.trail.render(self.run.env().world(), size)
    }

    /// The memory as a map, sequences x STM positions, row-major, into `out` (emptied first;
    /// left empty for an agent without a sequential memory).
    pub fn memory_map(&self, which: MemoryMap, out: &mut Vec<f32>) {
        out.clear();
        let Some(m) = self.run.inspect().memory else { return };
        match which {
            MemoryMap::G => {
                let g = m.biased_similarity();
                let cells = m.len() * m.config().n;
                out.extend((0..cells).map(|i| g.get(i).copied().unwrap_or(0.0) as f32));
            }
            MemoryMap::T => out.extend(m.bias().iter().map(|&t| t as f32)),
        }
    }

    /// Flat indices (row * n + column) of the couplets the last decision selected, into `out`.
    pub fn selected_couplets(&self, out: &mut Vec<u32>) {
        out.clear();
        if let Some(m) = self.run.inspect().memory {
            let n = m.config().n as u32;
            out.extend(m.selected().iter().map(|s| s.row * n + s.col));
        }
    }

    /// A person takes (`Some`) or gives back (`None`) the controls (`Run::set_driver`).
    pub fn set_driver(&mut self, driver: Option<Driver>) {
        self.run.set_driver(driver)
    }

    /// The agent's memory as a file (`Run::save_memory`).
    pub fn save_memory(&self) -> Result<Vec<u8>, ConfigError> {
        self.run.save_memory()
    }

    /// Replaces the agent's memory with a file's (`Run::load_memory`).
    pub fn load_memory(&mut self, bytes: &[u8]) -> Result<usize, Error> {
        self.run.load_memory(bytes)
    }
}
