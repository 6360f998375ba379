//! A scripted run whose log is compared across native, Node and browser builds: the proof that
//! a run is a pure function of (configuration, seed) on every target.

use super::{Env, EnvConfig};
use crate::arena::{Action, ConfigError, Task};
use crate::render::Surface;
use std::fmt::Write;

/// Runs `steps` env steps of `task` drawn with `surface` from `seed` with a fixed action script (a
/// 32-bit LCG, so the script itself is target independent), resetting at episode ends. One line
/// per step: `step action reward-bits terminated truncated agent-x-bits agent-z-bits frame-hash`,
/// then each pushable box's `x-bits:z-bits`, under a header naming the task (`<task>-textured` for
/// the textured surface).
pub fn scripted_run(task: &str, surface: Surface, seed: u64, steps: u32) -> Result<String, ConfigError> {
    scripted_task_run(Task::preset(task)?, surface, seed, steps)
}

/// `scripted_run` of any task (an arena file's, `arena::yaml::load_task`).
pub fn scripted_task_run(task: Task, surface: Surface, seed: u64, steps: u32) -> Result<String, ConfigError> {
    let name = crate::encoder::model_name(&task.name, surface);
    let mut env = Env::new(EnvConfig { surface, ..EnvConfig::new(task) }, seed)?;
    let mut out = String::new();
    let h = env.observation().hash();
    let _ = writeln!(out, "# {name} seed {seed} layout {} frame {h:016x}", env.layout_name());
    let mut lcg: u32 = seed as u32 ^ 0x9e37_79b9;
    for i in 0..steps {
        lcg = lcg.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        // Mostly forward and turns, like an exploring agent, with some of every action.
        let a = match lcg >> 28 {
            0..=6 => Action::FORWARD,
            7..=9 => Action::RIGHT,
            10..=12 => Action::LEFT,
            k => Action::new(k % 9)?,
        };
        let s = env.step(a)?;
        let (rew, term, trunc, hash) = (s.reward, s.terminated, s.truncated, s.observation.hash());
        let p = env.world().agent.pos;
        let _ = writeln!(
            out,
            "{i} {} {:016x} {} {} {:08x} {:08x} {hash:016x}",
            a.index(),
            rew.to_bits(),
            term as u8,
            trunc as u8,
            p.x.to_bits(),
            p.y.to_bits()
        );
        // Where each pushable object is, after the hash (none in the preset tasks).
        out.pop();
        for b in &env.world().pushed {
            let c = b.pose.centre;
            let _ = write!(out, " {:08x}:{:08x}", c.x.to_bits(), c.y.to_bits());
        }
        out.push('\n');
        if term || trunc {
            let h = env.reset(None).hash();
            let _ = writeln!(out, "# reset layout {} frame {h:016x}", env.layout_name());
        }
    }
    Ok(out)
}

/// The action cycle the speed benchmarks drive with (native criterion and the Node wasm script),
/// so both measure the same work: mostly forward, with turns and a pause, bumping into walls.
pub const BENCH_SCRIPT: [Action; 8] = [
    Action::FORWARD,
    Action::FORWARD,
    Action::RIGHT,
    Action::FORWARD,
    Action::LEFT,
    Action::FORWARD,
    Action::NOOP,
    Action::FORWARD,
];

/// Runs `n` physics-only env steps of the benchmark script, resetting at episode ends; returns
/// the summed reward so the work cannot be optimised away.
pub fn bench_env_steps(env: &mut Env, n: u32) -> f64 {
    let mut total = 0.0;
    for i in 0..n {
        if env.is_over() {
            env.reset(None);
        }
        let a = BENCH_SCRIPT[i as usize % BENCH_SCRIPT.len()];
        total += env.advance(a, 1).map(|o| o.reward).unwrap_or(0.0);
    }
    total
}

/// Ten poses of a task for the render benchmarks: the world every 40 steps of the script.
pub fn bench_worlds(task: &str) -> Result<Vec<super::World>, ConfigError> {
    let mut env = Env::new(EnvConfig::new(Task::preset(task)?), 1)?;
    let mut worlds = Vec::new();
    for i in 0..400u32 {
        if i % 40 == 0 {
            worlds.push(env.world().clone());
        }
        bench_env_steps(&mut env, 1);
    }
    Ok(worlds)
}
