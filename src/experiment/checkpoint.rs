//! A run between two episodes as bytes: what a long run (DQN's hours) writes every few episodes,
//! so that an interruption costs only the episodes since. A run is rebuilt from its configuration
//! and seed, then brought to the checkpoint: the environment replays its resets (its generator
//! draws only there, so `k` resets give the state after `k` episodes), the agent stream is set to
//! its saved position, and the controller restores its own state (`Controller::save_state`).
//! Resumed, the run gives the same episodes as one never interrupted.
//!
//! Layout (version 4): `SECCKPT4`, a little-endian u32 length, that many bytes of a JSON header
//! (seed, configuration, episodes played, the agent stream's word position, the digest of the
//! episode log so far), a u64 length and that many bytes of the reconstruction gate's state, the
//! controller's state, and an FNV-1a 64 checksum (u64) of every byte before it, as the memory
//! files have. Loading checks the checksum first, then every value with a live run's rules
//! (finite rewards within the memory files' bounds, finite T, G, p and entropy, sizes that fit n
//! and m, a gate MSE that is a number, the walk's counters within a cycle), so an edited file is
//! refused by name, never resumed into another run. The caller bounds the episodes replayed
//! (`ResumeCheck::max_episodes`) and may hand the log: its head must be the one the checkpoint
//! continues, so a claimed count above or below the state's is refused. Earlier versions load
//! only when the caller says so (`ResumeCheck::legacy`), through the same value checks: version 3
//! has no log digest, version 2 (`SECCKPT2`) no checksum either, version 1 (`SECCKPT1`) no gate
//! section.

use super::metrics::extend_log;
use super::{AgentFactory, Run, RunConfig};
use crate::error::{Error, FileError};
use std::io::{Read, Write};

const MAGIC: &[u8; 8] = b"SECCKPT4";
/// Version 3: no log digest.
const MAGIC_V3: &[u8; 8] = b"SECCKPT3";
/// Version 2: no checksum either.
const MAGIC_V2: &[u8; 8] = b"SECCKPT2";
/// The first version: no gate section (only agents without the gate wrote it) and no checksum.
const MAGIC_V1: &[u8; 8] = b"SECCKPT1";
/// The agent stream's word position stays below this: ChaCha's 64-bit block counter times 16
/// words per block.
const MAX_WORD_POS: u128 = 1 << 68;
/// A gate section longer than this is not one (a frame of floats and a few numbers).
const MAX_GATE: u64 = 1 << 20;
/// A header longer than this is not one (configurations are a few KiB).
const MAX_HEADER: u32 = 1 << 20;
/// Episodes a checkpoint may claim: each costs a reset on resume.
pub const MAX_EPISODES: u64 = 10_000_000;

/// What a checkpoint says of the run that wrote it; the controller's state follows it.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct Header {
    /// The run's seed.
    pub seed: u64,
    /// The run's configuration.
    pub config: RunConfig,
    /// Episodes played.
    pub episodes: u64,
    /// `ChaCha8Rng::get_word_pos` of the agent stream, as a decimal string (a u128).
    agent_stream: String,
    /// The episode log's digest (`Run::log_digest`) as 16 hex digits; absent before version 4.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    log: Option<String>,
    /// The reconstruction gate's state (`None` in a version-1 checkpoint).
    #[serde(skip)]
    gate: Option<Vec<u8>>,
    /// The format's version (1-4), from the magic.
    #[serde(skip)]
    pub version: u8,
}

/// The magics, newest first.
const VERSIONS: [&[u8; 8]; 4] = [MAGIC, MAGIC_V3, MAGIC_V2, MAGIC_V1];

/// What a resume holds a checkpoint to besides the run's configuration and seed: bounds the
/// caller sets, never the file.
#[derive(Clone, Copy, Debug, Default)]
pub struct ResumeCheck<'a> {
    /// The most episodes the checkpoint may claim (each costs a reset to replay): the count of
    /// the caller's log, or the episodes it asked for.
    pub max_episodes: u64,
    /// The run's episode log so far (one `EpisodeMetrics::to_json` line per episode, as the
    /// runner writes it): it must hold every episode the checkpoint claims, and their lines must
    /// be the ones the checkpoint was written after (lines past them are episodes to play again).
    pub log: Option<&'a str>,
    /// Whether a checkpoint of an earlier format (versions 1-3) is loaded; it has no log digest,
    /// so it resumes only beside its log.
    pub legacy: bool,
}

impl ResumeCheck<'_> {
    /// No more than `max_episodes`, no log, the current format only.
    pub fn at_most(max_episodes: u64) -> Self {
        ResumeCheck { max_episodes, log: None, legacy: false }
    }
}

/// The digest of the first `episodes` whole lines of `log`, or `None` when it holds fewer.
fn log_head_digest(log: &str, episodes: u64) -> Option<u64> {
    let mut digest = crate::util::FNV_OFFSET;
    let mut lines = log.split_inclusive('\n');
    for _ in 0..episodes {
        let line = lines.next().filter(|l| l.ends_with('\n'))?;
        digest = extend_log(digest, &line[..line.len() - 1]);
    }
    Some(digest)
}

/// A little-endian length of `width` bytes (4 or 8), at most `max`, and that many bytes.
fn block(input: &mut dyn Read, width: usize, max: u64, field: &str) -> Result<Vec<u8>, Error> {
    let mut len = [0u8; 8];
    input.read_exact(&mut len[..width]).map_err(io)?;
    let len = u64::from_le_bytes(len);
    if len > max {
        return Err(FileError::field("checkpoint", field.to_string(), format!("{len} bytes is over {max}")).into());
    }
    let mut bytes = vec![0u8; len as usize];
    input.read_exact(&mut bytes).map_err(io)?;
    Ok(bytes)
}

impl Header {
    /// Reads a checkpoint's header (and the gate's section), leaving `input` at the controller's
    /// state. The checksum of a version-3 or -4 checkpoint is not checked here (`Run::resume` does):
    /// this is what a resume looks at first, before it replays anything.
    pub fn read(input: &mut dyn Read) -> Result<Header, Error> {
        let mut magic = [0u8; 8];
        input.read_exact(&mut magic).map_err(io)?;
        if ![MAGIC, MAGIC_V3, MAGIC_V2, MAGIC_V1].contains(&&magic) {
            return Err(FileError::new(
                "checkpoint",
                "not a run checkpoint, or of another version (re-run: it starts again from episode 0)",
            )
            .into());
        }
        let json = block(input, 4, MAX_HEADER as u64, "header")?;
        let mut header: Header =
            serde_json::from_slice(&json).map_err(|e| FileError::field("checkpoint", "header", e.to_string()))?;
        if &magic != MAGIC_V1 {
            header.gate = Some(block(input, 8, MAX_GATE, "gate")?);
        }
        if header.episodes > MAX_EPISODES {
            let message = format!("{} is out of range 0..={MAX_EPISODES}", header.episodes);
            return Err(FileError::field("checkpoint", "episodes", message).into());
        }
        header.version = VERSIONS.iter().position(|m| *m == &magic).map_or(0, |i| 4 - i as u8);
        if (header.version == 4) != header.log.is_some() {
            let message = format!("present in a version-{} checkpoint", header.version);
            return Err(FileError::field("checkpoint", "log", message).into());
        }
        Ok(header)
    }

    /// The agent stream's word position, checked.
    fn word_pos(&self) -> Result<u128, Error> {
        match self.agent_stream.parse::<u128>() {
            Ok(w) if w < MAX_WORD_POS => Ok(w),
            _ => Err(FileError::field(
                "checkpoint",
                "agentStream",
                format!("'{}' is not a word position below 2^68", self.agent_stream),
            )
            .into()),
        }
    }
}

/// FNV-1a 64 over the bytes written through it, so a checkpoint is hashed as it is streamed out.
struct Hashing<'a> {
    out: &'a mut dyn Write,
    hash: u64,
}

impl Write for Hashing<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.out.write(buf)?;
        self.hash = crate::util::fnv1a_extend(self.hash, &buf[..n]);
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

fn io(e: std::io::Error) -> Error {
    FileError::new("checkpoint", e.to_string()).into()
}

impl Run {
    /// Whether `save_checkpoint` can write this run (its agent checkpoints, and no person is
    /// driving, which a checkpoint leaves out).
    pub fn can_checkpoint(&self) -> bool {
        self.controller.checkpoints() && self.driver.is_none()
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
            log: Some(format!("{:016x}", self.log_digest)),
            gate: None,
            version: 4,
        };
        let json = serde_json::to_vec(&header).expect("headers serialise");
        let mut gate = Vec::new();
        self.gate.put_state(&mut gate);
        let mut w = Hashing { out, hash: crate::util::FNV_OFFSET };
        w.write_all(MAGIC).map_err(io)?;
        w.write_all(&(json.len() as u32).to_le_bytes()).map_err(io)?;
        w.write_all(&json).map_err(io)?;
        w.write_all(&(gate.len() as u64).to_le_bytes()).map_err(io)?;
        w.write_all(&gate).map_err(io)?;
        self.controller.save_state(&mut w).map_err(|e| FileError::field("checkpoint", "agent", e))?;
        let sum = w.hash;
        w.out.write_all(&sum.to_le_bytes()).map_err(io)?;
        Ok(())
    }

    /// The run of `cfg` and `seed` brought to the checkpoint `input`; a checkpoint of another
    /// configuration or seed, a corrupt one, one that claims more episodes than `check` allows or
    /// whose log disagrees, or one of an earlier format unless `check.legacy`, is refused by name
    /// before anything is replayed.
    pub fn resume(
        cfg: RunConfig,
        seed: u64,
        extra: Option<AgentFactory>,
        input: &mut dyn Read,
        check: &ResumeCheck,
    ) -> Result<Run, Error> {
        let mut bytes = Vec::new();
        input.read_to_end(&mut bytes).map_err(io)?;
        let mut body: &[u8] = &bytes;
        // Versions 3 and 4: the checksum over all the rest, checked before anything is read.
        if bytes.starts_with(MAGIC) || bytes.starts_with(MAGIC_V3) {
            if bytes.len() < MAGIC.len() + 8 {
                return Err(FileError::new("checkpoint", "truncated").into());
            }
            let (rest, sum) = bytes.split_at(bytes.len() - 8);
            let sum = u64::from_le_bytes(sum.try_into().expect("8 bytes"));
            if crate::util::fnv1a(rest) != sum {
                return Err(FileError::field("checkpoint", "checksum", "mismatch: the file was changed or cut").into());
            }
            body = rest;
        }
        let input = &mut body;
        let header = Header::read(input)?;
        if header.version < 4 && !check.legacy {
            let message = format!(
                "a version-{} checkpoint (the current is 4) loads only when asked for (--legacy-checkpoint, \
                 allow_legacy=True), beside its log",
                header.version
            );
            return Err(FileError::field("checkpoint", "version", message).into());
        }
        if header.episodes > check.max_episodes {
            let message = format!("{} claimed, more than the {} expected", header.episodes, check.max_episodes);
            return Err(FileError::field("checkpoint", "episodes", message).into());
        }
        let log_digest = match (check.log, &header.log) {
            (Some(log), claimed) => {
                let Some(head) = log_head_digest(log, header.episodes) else {
                    let message = format!("holds fewer than the checkpoint's {} episodes", header.episodes);
                    return Err(FileError::field("checkpoint", "log", message).into());
                };
                if claimed.as_ref().is_some_and(|c| *c != format!("{head:016x}")) {
                    let message = format!(
                        "its first {} lines are not the ones the checkpoint continues (a count or a log edited)",
                        header.episodes
                    );
                    return Err(FileError::field("checkpoint", "log", message).into());
                }
                head
            }
            (None, Some(claimed)) => u64::from_str_radix(claimed, 16)
                .map_err(|_| FileError::field("checkpoint", "log", format!("'{claimed}' is not 16 hex digits")))?,
            (None, None) => {
                let message = format!("a version-{} checkpoint resumes only beside its log", header.version);
                return Err(FileError::field("checkpoint", "log", message).into());
            }
        };
        if header.seed != seed {
            let message = format!("written by seed {}, not {seed}", header.seed);
            return Err(FileError::field("checkpoint", "seed", message).into());
        }
        if !header.config.same_run(&cfg) {
            return Err(FileError::field("checkpoint", "config", "written by a run of another configuration").into());
        }
        let stream = header.word_pos()?;
        let mut run = Run::with_agents(cfg, seed, extra)?;
        if !run.can_checkpoint() {
            return Err(FileError::field("checkpoint", "kind", "this run's agent does not checkpoint").into());
        }
        for _ in 0..header.episodes {
            run.env.reset(None);
        }
        run.rng.set_word_pos(stream);
        match &header.gate {
            Some(bytes) => {
                let mut r = crate::util::ByteReader { b: bytes, at: 0, what: "checkpoint" };
                run.gate.take_state(&mut r)?;
            }
            // A version-1 checkpoint: written only by agents without the gate.
            None if run.agent.has_gate => {
                return Err(FileError::field("checkpoint", "gate", "missing (a version-1 checkpoint)").into());
            }
            None => {}
        }
        run.controller.load_state(input).map_err(|e| FileError::field("checkpoint", "agent", e))?;
        run.log_digest = log_digest;
        Ok(run)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::agent::SecConfig;
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
        let mut resumed = Run::resume(reactive(), 7, None, &mut bytes.as_slice(), &ResumeCheck::at_most(1000)).unwrap();
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
        assert_eq!(field(Run::resume(reactive(), 8, None, &mut bytes.as_slice(), &ResumeCheck::at_most(1000))), "seed");
        let other = RunConfig { t: Some(300), ..reactive() };
        assert_eq!(field(Run::resume(other, 7, None, &mut bytes.as_slice(), &ResumeCheck::at_most(1000))), "config");
        assert_eq!(
            field(Run::resume(reactive(), 7, None, &mut &bytes[..20], &ResumeCheck::at_most(1000))),
            "checksum",
            "a cut file fails its checksum"
        );
        let mut bad = bytes.clone();
        bad[0] = b'X';
        assert_eq!(
            field(Run::resume(reactive(), 7, None, &mut bad.as_slice(), &ResumeCheck::at_most(1000))),
            "checkpoint"
        );
        run.tick();
        assert!(run.save_checkpoint(&mut Vec::new()).is_err(), "mid-episode");
        let mfec = Run::new(RunConfig { kind: AgentKind::Mfec, ..reactive() }, 7).unwrap();
        assert!(!mfec.can_checkpoint());
        assert_eq!(mfec.save_checkpoint(&mut Vec::new()).unwrap_err().field(), "kind");
    }

    #[test]
    fn a_resumed_sec_run_plays_the_episodes_of_an_uninterrupted_one() {
        // The golden run's task and seed, where the LTM fills and the contextual layer acts from
        // episode 16; FIFO forgetting with a small m so that the LTM forgets before the cut.
        let mut cfg = RunConfig { task: "object-permanence".into(), ..RunConfig::default() };
        cfg.section_mut::<SecConfig>().memory.m = 8;
        cfg.section_mut::<SecConfig>().memory.forgetting = crate::memory::Forgetting::Fifo;
        let full = |run: &mut Run, n: usize| (0..n).map(|_| run.episode().to_json()).collect::<Vec<_>>();
        let mut whole = Run::new(cfg.clone(), 2).unwrap();
        let expected = full(&mut whole, 24);
        let mut first = Run::new(cfg.clone(), 2).unwrap();
        let mut got = full(&mut first, 18);
        assert!(first.inspect().memory.unwrap().len() >= 5, "the contextual layer acts before the cut");
        let mut bytes = Vec::new();
        first.save_checkpoint(&mut bytes).unwrap();
        drop(first);
        let mut resumed = Run::resume(cfg, 2, None, &mut bytes.as_slice(), &ResumeCheck::at_most(1000)).unwrap();
        got.extend(full(&mut resumed, 6));
        assert_eq!(got, expected);
    }
}
