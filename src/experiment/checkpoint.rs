//! A run between two episodes as bytes: what a long run (DQN's hours) writes every few episodes,
//! so that an interruption costs only the episodes since. A run is rebuilt from its configuration
//! and seed, then brought to the checkpoint: the environment replays its resets (its generator
//! draws only there, so `k` resets give the state after `k` episodes), the agent stream is set to
//! its saved position, and the controller restores its own state (`Controller::save_state`).
//! Resumed, the run gives the same episodes as one never interrupted.
//!
//! Layout: `SECCKPT1`, a little-endian u32 length, that many bytes of a JSON header (seed,
//! configuration, episodes played, the agent stream's word position), then the controller's state
//! to the end.

use super::{AgentFactory, Run, RunConfig};
use crate::error::{Error, FileError};
use std::io::{Read, Write};

const MAGIC: &[u8; 8] = b"SECCKPT1";
/// A header longer than this is not one (configurations are a few KiB).
const MAX_HEADER: u32 = 1 << 20;
/// Episodes a checkpoint may claim: each costs a reset on resume.
pub const MAX_EPISODES: u64 = 10_000_000;

/// What a checkpoint says of the run that wrote it; the controller's state follows it.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct Header {
    pub seed: u64,
    pub config: RunConfig,
    /// Episodes played.
    pub episodes: u64,
    /// `ChaCha8Rng::get_word_pos` of the agent stream, as a decimal string (a u128).
    agent_stream: String,
}

impl Header {
    /// Reads a checkpoint's header, leaving `input` at the controller's state.
    pub fn read(input: &mut dyn Read) -> Result<Header, Error> {
        let mut magic = [0u8; 8];
        input.read_exact(&mut magic).map_err(io)?;
        if &magic != MAGIC {
            return Err(FileError::new("checkpoint", "not a run checkpoint (or of another version)").into());
        }
        let mut len = [0u8; 4];
        input.read_exact(&mut len).map_err(io)?;
        let len = u32::from_le_bytes(len);
        if len > MAX_HEADER {
            return Err(FileError::field("checkpoint", "header", format!("{len} bytes is over {MAX_HEADER}")).into());
        }
        let mut json = vec![0u8; len as usize];
        input.read_exact(&mut json).map_err(io)?;
        let header: Header =
            serde_json::from_slice(&json).map_err(|e| FileError::field("checkpoint", "header", e.to_string()))?;
        if header.episodes > MAX_EPISODES {
            let message = format!("{} is out of range 0..={MAX_EPISODES}", header.episodes);
            return Err(FileError::field("checkpoint", "episodes", message).into());
        }
        Ok(header)
    }
}

fn io(e: std::io::Error) -> Error {
    FileError::new("checkpoint", e.to_string()).into()
}

impl Run {
    /// Whether `save_checkpoint` can write this run (its agent checkpoints, and nothing that a
    /// checkpoint leaves out is in use: a person driving, the reconstruction gate).
    pub fn can_checkpoint(&self) -> bool {
        self.controller.checkpoints() && !self.controller.uses_gate() && self.driver.is_none()
    }

    /// Writes the run as it stands between two episodes (refused in the middle of one).
    pub fn save_checkpoint(&self, out: &mut dyn Write) -> Result<(), Error> {
        if self.current.is_some() {
            return Err(FileError::new("checkpoint", "a run checkpoints between two episodes, not during one").into());
        }
        if !self.can_checkpoint() {
            return Err(FileError::field("checkpoint", "kind", "this run's agent does not checkpoint").into());
        }
        let header = Header {
            seed: self.seed,
            config: self.cfg.clone(),
            episodes: self.env.episode(),
            agent_stream: self.rng.get_word_pos().to_string(),
        };
        let json = serde_json::to_vec(&header).expect("headers serialise");
        out.write_all(MAGIC).map_err(io)?;
        out.write_all(&(json.len() as u32).to_le_bytes()).map_err(io)?;
        out.write_all(&json).map_err(io)?;
        self.controller.save_state(out).map_err(|e| FileError::field("checkpoint", "agent", e))?;
        Ok(())
    }

    /// The run of `cfg` and `seed` brought to the checkpoint `input`; a checkpoint of another
    /// configuration or seed, or a corrupt one, is refused.
    pub fn resume(cfg: RunConfig, seed: u64, extra: Option<AgentFactory>, input: &mut dyn Read) -> Result<Run, Error> {
        let header = Header::read(input)?;
        if header.seed != seed {
            let message = format!("written by seed {}, not {seed}", header.seed);
            return Err(FileError::field("checkpoint", "seed", message).into());
        }
        if header.config != cfg {
            return Err(FileError::field("checkpoint", "config", "written by a run of another configuration").into());
        }
        let stream: u128 = header
            .agent_stream
            .parse()
            .map_err(|_| FileError::field("checkpoint", "agentStream", "not a word position"))?;
        let mut run = Run::with_agents(cfg, seed, extra)?;
        if !run.can_checkpoint() {
            return Err(FileError::field("checkpoint", "kind", "this run's agent does not checkpoint").into());
        }
        for _ in 0..header.episodes {
            run.env.reset(None);
        }
        run.rng.set_word_pos(stream);
        run.controller.load_state(input).map_err(|e| FileError::field("checkpoint", "agent", e))?;
        Ok(run)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::AgentKind;

    fn reactive() -> RunConfig {
        RunConfig { kind: AgentKind::Reactive, t: Some(200), ..RunConfig::default() }
    }

    /// Each episode's metrics and where the agent stood 30 decisions into it (the metrics of a
    /// walk that finds no goal do not show its path).
    fn log(run: &mut Run, episodes: usize) -> Vec<String> {
        let mut lines = Vec::new();
        for _ in 0..episodes {
            for _ in 0..30 {
                run.decision();
            }
            let p = run.env().world().agent.pos;
            lines.push(format!("{p:?} {}", run.episode().to_json()));
        }
        lines
    }

    #[test]
    fn a_resumed_run_plays_the_episodes_of_an_uninterrupted_one() {
        let mut whole = Run::new(reactive(), 7).unwrap();
        let expected = log(&mut whole, 6);
        let mut first = Run::new(reactive(), 7).unwrap();
        let mut got = log(&mut first, 3);
        let mut bytes = Vec::new();
        first.save_checkpoint(&mut bytes).unwrap();
        drop(first);
        let mut resumed = Run::resume(reactive(), 7, None, &mut bytes.as_slice()).unwrap();
        got.extend(log(&mut resumed, 3));
        assert_eq!(got, expected);
    }

    #[test]
    fn checkpoints_of_another_run_or_mid_episode_are_refused() {
        let mut run = Run::new(reactive(), 7).unwrap();
        run.episode();
        let mut bytes = Vec::new();
        run.save_checkpoint(&mut bytes).unwrap();
        let field = |r: Result<Run, Error>| r.err().expect("refused").field().to_string();
        assert_eq!(field(Run::resume(reactive(), 8, None, &mut bytes.as_slice())), "seed");
        let other = RunConfig { t: Some(300), ..reactive() };
        assert_eq!(field(Run::resume(other, 7, None, &mut bytes.as_slice())), "config");
        assert_eq!(field(Run::resume(reactive(), 7, None, &mut &bytes[..20])), "checkpoint");
        let mut bad = bytes.clone();
        bad[0] = b'X';
        assert_eq!(field(Run::resume(reactive(), 7, None, &mut bad.as_slice())), "checkpoint");
        run.tick();
        assert!(run.save_checkpoint(&mut Vec::new()).is_err(), "mid-episode");
        let sec = Run::new(RunConfig::default(), 7).unwrap();
        assert!(!sec.can_checkpoint());
        assert_eq!(sec.save_checkpoint(&mut Vec::new()).unwrap_err().field(), "kind");
    }
}
