//! The agent's memory as a file, so a learnt LTM can be kept, shared and loaded into another run
//! of the same task and model. Versioned and checked like the weights file: a corrupt, foreign
//! or mismatched file is a clear error and the memory it was meant for is left as it was.
//!
//! Layout, little-endian:
//! - magic `SECMEMRY` (8 bytes), format version (u32, now 1);
//! - what the embeddings mean: the task (u16 length + UTF-8), the encoder's fingerprint (u64,
//!   `Autoencoder::fingerprint`, scale included) and the embedding size (u32, 20);
//! - the STM length n (u32) and the number of LTM sequences (u32);
//! - the STM, oldest couplet first: per couplet 20 f32 then its action (u8);
//! - per sequence its reward (f64), then its n couplets as in the STM;
//! - an FNV-1a 64 checksum (u64) of all the bytes before it.
//!
//! T and the selection masks are not kept: they restart at 1 and empty, as after an episode.

use super::{Couplet, Memory, Selected};
use crate::arena::Action;
use crate::encoder::EMBEDDING;
use crate::error::FileError;
use crate::memory::ACTIONS;
use crate::util::{fnv1a, put_bytes, put_f32s, put_f64s, put_str, ByteReader};

/// A memory file's first bytes.
pub const MAGIC: [u8; 8] = *b"SECMEMRY";
/// The format version this build reads and writes.
pub const VERSION: u32 = 1;

/// What a memory's embeddings were made with: a file loads only into a run that agrees.
#[derive(Clone, Debug, PartialEq)]
pub struct Identity {
    /// The task the embeddings were made in.
    pub task: String,
    /// The encoder's fingerprint (`Autoencoder::fingerprint`).
    pub model: u64,
}

fn err(message: impl Into<String>) -> FileError {
    FileError::new("memory", message)
}

fn put_couplet(b: &mut Vec<u8>, c: &Couplet) {
    for v in c.embedding {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.push(c.action.into());
}

fn couplet(r: &mut ByteReader) -> Result<Couplet, FileError> {
    let mut embedding = [0.0f32; EMBEDDING];
    for v in &mut embedding {
        *v = r.f32()?;
        if !v.is_finite() {
            return Err(err("an embedding value is not a finite number"));
        }
    }
    let index = r.take(1)?[0];
    let action =
        Action::new(index.into()).map_err(|_| err(format!("action {index} is out of range 0..={}", ACTIONS - 1)))?;
    Ok(Couplet { embedding, action })
}

impl Memory {
    /// The STM and the LTM as a file (see the module's doc).
    pub fn to_file(&self, id: &Identity) -> Vec<u8> {
        let n = self.cfg.n;
        let mut b = Vec::with_capacity(64 + (self.len() + 1) * (8 + n * (4 * EMBEDDING + 1)));
        b.extend_from_slice(&MAGIC);
        b.extend_from_slice(&VERSION.to_le_bytes());
        put_str(&mut b, &id.task);
        b.extend_from_slice(&id.model.to_le_bytes());
        b.extend_from_slice(&(EMBEDDING as u32).to_le_bytes());
        b.extend_from_slice(&(n as u32).to_le_bytes());
        b.extend_from_slice(&(self.len() as u32).to_le_bytes());
        for c in self.stm() {
            put_couplet(&mut b, c);
        }
        for (i, r) in self.rewards.iter().enumerate() {
            b.extend_from_slice(&r.to_le_bytes());
            for j in 0..n {
                put_couplet(&mut b, &Couplet { embedding: self.ltm_embedding(i, j), action: self.ltm_action(i, j) });
            }
        }
        let sum = fnv1a(&b);
        b.extend_from_slice(&sum.to_le_bytes());
        b
    }

    /// Replaces the STM and the LTM with a file's, after checking all of it against `id` and
    /// this memory's n and m; on error nothing changes. Returns the number of sequences loaded.
    pub fn load_file(&mut self, bytes: &[u8], id: &Identity) -> Result<usize, FileError> {
        if bytes.len() < MAGIC.len() || bytes[..MAGIC.len()] != MAGIC {
            return Err(err("not a SEC memory file (bad magic number)"));
        }
        if bytes.len() < MAGIC.len() + 4 + 8 {
            return Err(err("file is truncated"));
        }
        let (body, tail) = bytes.split_at(bytes.len() - 8);
        let mut r = ByteReader { b: body, at: MAGIC.len(), what: "memory" };
        let version = r.u32()?;
        if version != VERSION {
            return Err(err(format!("format version {version} is not supported (this build reads {VERSION})")));
        }
        if fnv1a(body) != u64::from_le_bytes(tail.try_into().unwrap()) {
            return Err(err("checksum mismatch: the file is corrupt"));
        }
        let task = r.string()?;
        if task != id.task {
            return Err(err(format!("the file holds a memory of '{task}', this run is in '{}'", id.task)));
        }
        let model = r.u64()?;
        if model != id.model {
            return Err(err(format!(
                "the file was made with another encoder of '{task}' (fingerprint {model:016x}, this run's {:016x}), \
                 so its embeddings mean something else (the untrained perception draws an encoder per seed)",
                id.model
            )));
        }
        let dim = r.u32()? as usize;
        if dim != EMBEDDING {
            return Err(err(format!("embedding size {dim}, this build's is {EMBEDDING}")));
        }
        let n = r.u32()? as usize;
        if n != self.cfg.n {
            return Err(FileError::field(
                "memory",
                "n",
                format!("the file's sequences have {n} couplets, this run's STM length n is {}", self.cfg.n),
            ));
        }
        let rows = r.u32()? as usize;
        if rows > self.cfg.m {
            return Err(FileError::field(
                "memory",
                "m",
                format!("the file holds {rows} sequences, more than this run's LTM capacity m = {}", self.cfg.m),
            ));
        }
        let expected = n * (4 * EMBEDDING + 1) * (rows + 1) + 8 * rows;
        if body.len() - r.at != expected {
            return Err(err(format!("{} bytes of couplets, expected {expected}", body.len() - r.at)));
        }
        let stm = (0..n).map(|_| couplet(&mut r)).collect::<Result<Vec<_>, _>>()?;
        let mut seqs = Vec::with_capacity(rows);
        for _ in 0..rows {
            let reward = r.f64()?;
            if !(reward.is_finite() && reward > 0.0 && reward <= super::MAX_REWARD) {
                let max = super::MAX_REWARD;
                return Err(err(format!("a sequence's reward {reward} is out of range (0, {max}]")));
            }
            seqs.push((reward, (0..n).map(|_| couplet(&mut r)).collect::<Result<Vec<_>, _>>()?));
        }
        // Checked: now replace.
        self.stm.copy_from_slice(&stm);
        self.stm_head = 0;
        self.finish_similarity();
        self.coarse.clear();
        self.ltm.clear();
        self.actions.clear();
        self.rewards.clear();
        for (reward, seq) in &seqs {
            let row = self.ltm.len();
            self.ltm.resize(row + EMBEDDING * n, 0.0);
            for (j, c) in seq.iter().enumerate() {
                for k in 0..EMBEDDING {
                    self.ltm[row + k * n + j] = c.embedding[k];
                }
                self.actions.push(c.action);
            }
            self.rewards.push(*reward);
        }
        self.t.clear();
        self.t.resize(rows * n, 1.0);
        self.sel.clear();
        self.sel_prev.clear();
        self.raised.clear();
        self.g.clear();
        self.last_g = super::LastG::Full;
        self.sim_for = None;
        self.selected.clear();
        Ok(rows)
    }
}

/// The whole memory for a run checkpoint (`experiment::checkpoint`): besides what a memory file
/// holds, T, the selection masks, the last retrieval (its G, similarities and selection) and the
/// values and entropy the next decision may reuse (D14), so a resumed run continues exactly.
/// The settings are the run's own and not written.
impl Memory {
    pub(crate) fn put_state(&self, b: &mut Vec<u8>) {
        b.extend_from_slice(&(self.stm_head as u64).to_le_bytes());
        for c in &self.stm {
            put_couplet(b, c);
        }
        put_f32s(b, &self.ltm);
        put_bytes(b, &self.actions.iter().map(|&a| a.into()).collect::<Vec<u8>>());
        put_f64s(b, &self.rewards);
        put_f64s(b, &self.t);
        for sel in [&self.sel, &self.sel_prev] {
            let mut mask = vec![0u8; self.t.len()];
            sel.iter().for_each(|&i| mask[i as usize] = 1);
            put_bytes(b, &mask);
        }
        put_f64s(b, &self.biased_similarity());
        b.push(self.forgot as u8);
        put_f32s(b, &self.sim_in_full());
        b.extend_from_slice(&(self.selected.len() as u64).to_le_bytes());
        for s in &self.selected {
            b.extend_from_slice(&s.row.to_le_bytes());
            b.extend_from_slice(&s.col.to_le_bytes());
            for v in [s.g, s.t, s.rr, s.d, s.value] {
                b.extend_from_slice(&v.to_le_bytes());
            }
            b.push(s.action.into());
        }
        for v in self.q.iter().chain(&self.p).chain([&self.entropy]) {
            b.extend_from_slice(&v.to_le_bytes());
        }
    }

    /// Reads what `put_state` wrote onto a memory of the same settings; refused (and the memory
    /// to be dropped) unless its sizes fit them.
    pub(crate) fn take_state(&mut self, r: &mut ByteReader) -> Result<(), FileError> {
        let (n, m) = (self.cfg.n, self.cfg.m);
        let cells = n * m;
        let bad = |what: &str| FileError::field("checkpoint", what.to_string(), "does not fit the memory's n and m");
        let head = r.u64()? as usize;
        if head >= n {
            return Err(bad("stmHead"));
        }
        let stm = (0..n).map(|_| couplet(r)).collect::<Result<Vec<_>, _>>()?;
        let ltm = r.f32s(cells * EMBEDDING, "ltm")?;
        let rows = ltm.len() / (n * EMBEDDING);
        let actions = r.bytes(cells, "actions")?;
        let rewards = r.f64s(m, "rewards")?;
        let t = r.f64s(cells, "t")?;
        let sel = r.bytes(cells, "sel")?;
        let sel_prev = r.bytes(cells, "selPrev")?;
        let g = r.f64s(cells, "g")?;
        let forgot = r.bool()?;
        let sim = r.f32s(cells, "sim")?;
        let count = r.count(cells, "selected")?;
        let mut selected = Vec::with_capacity(count);
        for _ in 0..count {
            let (row, col) = (r.u32()?, r.u32()?);
            let [g, t, rr, d, value] = [r.f64()?, r.f64()?, r.f64()?, r.f64()?, r.f64()?];
            let action = Action::new(r.take(1)?[0].into()).map_err(|_| bad("selected"))?;
            if row as usize >= rows || col as usize >= n {
                return Err(bad("selected"));
            }
            selected.push(Selected { row, col, g, t, rr, d, action, value });
        }
        let mut q = [0.0; ACTIONS];
        let mut p = [0.0; ACTIONS];
        for v in q.iter_mut().chain(p.iter_mut()) {
            *v = r.f64()?;
        }
        let entropy = r.f64()?;
        if sel.iter().chain(&sel_prev).any(|&b| b > 1) {
            return Err(FileError::field("checkpoint", "sel", "a selection mask holds a byte other than 0 or 1"));
        }
        let sound = ltm.len() == rows * n * EMBEDDING
            && actions.len() == rows * n
            && rewards.len() == rows
            && [t.len(), sel.len(), sel_prev.len()].iter().all(|&l| l == rows * n)
            && g.len() <= cells
            && sim.len() <= cells
            && actions.iter().all(|&a| (a as usize) < ACTIONS);
        if !sound {
            return Err(bad("ltm"));
        }
        // Every value as a live run could hold it (the memory files' rules for rewards).
        let value = |what: &str, rule: &str| FileError::field("checkpoint", what.to_string(), rule.to_string());
        if !ltm.iter().all(|v| v.is_finite()) {
            return Err(value("ltm", "holds a value that is not a finite number"));
        }
        if let Some(r) = rewards.iter().find(|r| !(r.is_finite() && **r > 0.0 && **r <= super::MAX_REWARD)) {
            return Err(value(
                "rewards",
                &format!("a sequence's reward {r} is out of range (0, {}]", super::MAX_REWARD),
            ));
        }
        if !t.iter().all(|v| v.is_finite() && *v >= 0.0) {
            return Err(value("t", "holds a value that is not a finite number >= 0"));
        }
        if !g.iter().all(|v| v.is_finite()) || !sim.iter().all(|v| v.is_finite()) {
            return Err(value("g", "holds a value that is not a finite number"));
        }
        if !selected.iter().all(|s| [s.g, s.t, s.rr, s.d, s.value].iter().all(|v| v.is_finite())) {
            return Err(value("selected", "holds a value that is not a finite number"));
        }
        if !q.iter().all(|v| v.is_finite() && *v >= 0.0) {
            return Err(value("q", "holds a value that is not a finite number >= 0"));
        }
        if !p.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)) {
            return Err(value("p", "holds a value outside [0, 1]"));
        }
        if !(entropy.is_finite() && (0.0..=(ACTIONS as f64).log2() + 1e-9).contains(&entropy)) {
            return Err(value("entropy", &format!("{entropy} is out of range [0, log2 9]")));
        }
        let actions = actions.into_iter().map(|a| Action::ALL[a as usize]).collect();
        (self.stm, self.stm_head, self.ltm, self.actions, self.rewards) = (stm, head, ltm, actions, rewards);
        let set = |mask: Vec<u8>| (0..mask.len() as u32).filter(|&i| mask[i as usize] != 0).collect();
        (self.sel, self.sel_prev) = (set(sel), set(sel_prev));
        (self.raised, self.t, self.g, self.forgot, self.sim) = (super::raised_of(&t), t, g, forgot, sim);
        self.coarse.clear();
        (self.selected, self.q, self.p, self.entropy) = (selected, q, p, entropy);
        self.last_g = super::LastG::Full;
        self.sim_for = None;
        Ok(())
    }
}
