//! DQN's and ERLAM's state in a run checkpoint (`sec_playground::experiment::checkpoint`), as
//! CBOR: the online and target networks and the RMSprop state as burn writes them (burnpack
//! bytes, which keep the parameter ids the optimiser state is keyed by), the replay buffer or the
//! graph with its frames as byte strings, the reactive walk and the counters. Written between
//! episodes; loaded onto an agent built from the same configuration and seed.

use crate::graph::Graph;
use crate::net::NatureCnn;
use crate::replay::Replay;
use crate::{optimiser_config, Dqn, Memory, Progress};
use burn::module::Module;
use burn::store::ModuleRecord;
use burn::tensor::Bytes;
use sec_playground::encoder::{EMBEDDING, IMAGE};
use sec_playground::experiment::RunConfig;
use serde_bytes::ByteBuf;
use std::io::{BufReader, BufWriter, Read, Write};

/// The agent's state, with the memory as `M`: borrowed to write, owned when read.
#[derive(serde::Serialize, serde::Deserialize)]
struct Saved<M> {
    online: ByteBuf,
    target: ByteBuf,
    optimiser: ByteBuf,
    /// Flattened: the checkpoints of the runs in progress keep these fields at the top level.
    #[serde(flatten)]
    progress: Progress,
    memory: M,
}

/// ERLAM's state besides the graph: the frame the next transition starts from (with its
/// embedding) and the episodes added so far.
type Start = Option<(ByteBuf, [f32; EMBEDDING])>;

#[derive(serde::Serialize)]
enum MemoryOut<'a> {
    Replay(&'a Replay),
    Graph { graph: &'a Graph, start: Start, episodes: u64 },
}

#[derive(serde::Deserialize)]
enum MemoryIn {
    Replay(Replay),
    Graph { graph: Box<Graph>, start: Start, episodes: u64 },
}

fn network_bytes(net: &NatureCnn) -> Result<ByteBuf, String> {
    let bytes = net.clone().into_record().into_bytes().map_err(|e| format!("network: {e}"))?;
    Ok(ByteBuf::from(bytes.to_vec()))
}

fn network_from(net: NatureCnn, bytes: ByteBuf, what: &str) -> Result<NatureCnn, String> {
    let record =
        ModuleRecord::from_bytes(Bytes::from_bytes_vec(bytes.into_vec())).map_err(|e| format!("{what}: {e}"))?;
    net.try_load_record(record).map_err(|e| format!("{what}: {e}"))
}

/// Counters a checkpoint may claim: far beyond any run, far below where `+= 1` overflows.
const MAX_COUNT: u64 = 1 << 50;

/// Every float of a burnpack buffer (a network's parameters, the optimiser's averages) finite:
/// a NaN weight would load and turn every Q value into NaN.
fn finite_pack(bytes: &[u8], what: &str) -> Result<(), String> {
    let reader =
        burn_pack::Reader::from_bytes(Bytes::from_bytes_vec(bytes.to_vec())).map_err(|e| format!("{what}: {e}"))?;
    for t in reader.into_tensors().map_err(|e| format!("{what}: {e}"))? {
        let data = t.to_bytes().map_err(|e| format!("{what}: {e}"))?;
        let finite = match t.dtype {
            burn_pack::DType::F32 => {
                data.chunks_exact(4).all(|c| f32::from_le_bytes(c.try_into().unwrap()).is_finite())
            }
            burn_pack::DType::F64 => {
                data.chunks_exact(8).all(|c| f64::from_le_bytes(c.try_into().unwrap()).is_finite())
            }
            _ => true,
        };
        if !finite {
            return Err(format!("{what}: tensor {} holds a value that is not a finite number", t.name));
        }
    }
    Ok(())
}

pub(crate) fn save(dqn: &Dqn, out: &mut dyn Write) -> Result<(), String> {
    let memory = match &dqn.memory {
        Memory::Replay(r) => MemoryOut::Replay(r),
        Memory::Graph(a) => MemoryOut::Graph {
            graph: &a.graph,
            start: a.state.as_ref().map(|(s, e)| (ByteBuf::from(s.clone()), *e)),
            episodes: a.episodes,
        },
    };
    let optimiser = dqn.optim.into_bytes().map_err(|e| format!("optimiser: {e}"))?;
    let saved = Saved {
        online: network_bytes(dqn.network())?,
        target: network_bytes(&dqn.target)?,
        optimiser: ByteBuf::from(optimiser.to_vec()),
        progress: dqn.progress.clone(),
        memory,
    };
    let mut out = BufWriter::new(out);
    ciborium::into_writer(&saved, &mut out).map_err(|e| e.to_string())?;
    out.flush().map_err(|e| e.to_string())
}

/// Loads onto `dqn` (freshly built from the run's configuration and seed); on an error `dqn` is
/// to be dropped.
pub(crate) fn load(dqn: &mut Dqn, input: &mut dyn Read) -> Result<(), String> {
    let saved: Saved<MemoryIn> = ciborium::from_reader(BufReader::new(input)).map_err(|e| e.to_string())?;
    let Saved { online, target, optimiser, progress, memory } = saved;
    match (memory, &mut dqn.memory) {
        (MemoryIn::Replay(r), Memory::Replay(replay)) => {
            r.check(dqn.cfg.replay_size, IMAGE)?;
            *replay = r;
        }
        (MemoryIn::Graph { graph, start, episodes }, Memory::Graph(a)) => {
            a.graph = (*graph).restored(&a.graph, IMAGE)?;
            a.state = match start {
                Some((s, _)) if s.len() != IMAGE => return Err("erlam: the start frame is not a frame".into()),
                Some((s, e)) => Some((s.into_vec(), e)),
                None => None,
            };
            if episodes > MAX_COUNT {
                return Err(format!("erlam.episodes: {episodes} is out of range 0..={MAX_COUNT}"));
            }
            if let Some((_, e)) = &a.state {
                if let Some(v) = e.iter().find(|v| !v.is_finite()) {
                    return Err(format!("erlam.start: its embedding holds {v}, not a finite number"));
                }
            }
            a.episodes = episodes;
        }
        _ => return Err("the checkpoint is of the other agent (dqn or erlam)".into()),
    }
    let (low, high) = (dqn.cfg.epsilon_end.min(dqn.cfg.epsilon_start), dqn.cfg.epsilon_end.max(dqn.cfg.epsilon_start));
    let Progress { epsilon, pending, entropy, .. } = progress;
    if !(low..=high).contains(&epsilon) {
        return Err(format!("epsilon: {epsilon} is out of range {low}..={high}"));
    }
    if !pending.is_finite() {
        return Err(format!("pending: {pending} is not a finite number"));
    }
    if !(entropy.is_finite() && (0.0..=(sec_playground::arena::Action::COUNT as f64).log2() + 1e-9).contains(&entropy))
    {
        return Err(format!("entropy: {entropy} is out of range [0, log2 9]"));
    }
    if progress.decisions > MAX_COUNT {
        return Err(format!("decisions: {} is out of range 0..={MAX_COUNT}", progress.decisions));
    }
    finite_pack(&online, "online network")?;
    finite_pack(&target, "target network")?;
    finite_pack(&optimiser, "optimiser")?;
    dqn.net = Some(network_from(dqn.network().clone(), online, "online network")?);
    dqn.target = network_from(dqn.target.clone(), target, "target network")?;
    let optim = optimiser_config()
        .init()
        .from_bytes(Bytes::from_bytes_vec(optimiser.to_vec()))
        .map_err(|e| format!("optimiser: {e}"))?;
    // burn skips a parameter whose state it cannot rebuild (re-initialising it at the next step):
    // a state that does not load whole would make another run, so it must write back the same.
    let names = |b: Vec<u8>| -> Result<Vec<String>, String> {
        let reader = burn_pack::Reader::from_bytes(Bytes::from_bytes_vec(b)).map_err(|e| format!("optimiser: {e}"))?;
        Ok(reader.tensor_names().into_iter().map(str::to_string).collect())
    };
    let written = optim.into_bytes().map_err(|e| format!("optimiser: {e}"))?.to_vec();
    if names(written)? != names(optimiser.into_vec())? {
        return Err("optimiser: the state does not load whole (a parameter's averages are missing or foreign)".into());
    }
    dqn.optim = optim;
    dqn.progress = progress;
    Ok(())
}

/// ERLAM's graph as a checkpoint of a run of `cfg` holds it (`input` past the run's header): the
/// benchmark's real graph.
pub fn graph(cfg: &RunConfig, input: &mut dyn Read) -> Result<Graph, String> {
    let saved: Saved<MemoryIn> = ciborium::from_reader(BufReader::new(input)).map_err(|e| e.to_string())?;
    match saved.memory {
        MemoryIn::Graph { graph, .. } => {
            let (dqn, erlam) = (crate::config::dqn(cfg), crate::config::erlam(cfg));
            let (dqn, erlam) = (dqn.map_err(|e| e.to_string())?, erlam.map_err(|e| e.to_string())?);
            (*graph).restored(&Graph::new(erlam, dqn.gamma), IMAGE)
        }
        MemoryIn::Replay(_) => Err("a DQN checkpoint has no graph".into()),
    }
}
