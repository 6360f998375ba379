//! A run's memo of what its encoders made of each frame: half of a run's decision frames are
//! byte-identical to one seen before (the agent pressed against a wall, a turn on the spot), and
//! an encoder pass is a pure function of the frame, so a frame seen again takes its embedding and
//! its reconstruction error from here, the same bits.
//!
//! Entries are keyed by the frame itself, run-length encoded (rendered frames are flat-shaded:
//! a few hundred runs of equal pixels), found through a hash of that key and confirmed by
//! comparing the whole key, so a hash collision is a miss, never a wrong value. The cache holds
//! at most `CAPACITY` frames and `BYTES` of keys, dropping the least recently used. It is not
//! part of a run's state: a run resumed with an empty cache computes the same values.

use super::EMBEDDING;
use crate::render::Frame;
use std::collections::HashMap;

/// Frames kept (an LRU of 1,000 catches nearly every repeat of a T-maze run).
pub const CAPACITY: usize = 1024;
/// The most key bytes kept: a frame of noise (no runs) takes 35 KB, a rendered one 1-3 KB.
pub const BYTES: usize = 8 << 20;

/// Which entry holds the current frame: its slot and the entry's serial number, so that an
/// entry dropped and its slot reused is not mistaken for the frame's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Slot {
    index: usize,
    serial: u64,
}

#[derive(Clone, Debug)]
struct Entry {
    key: Vec<u8>,
    hash: u64,
    serial: u64,
    used: u64,
    embedding: Option<[f32; EMBEDDING]>,
    mse: Option<f32>,
}

/// The memo (see the module's comment).
#[derive(Clone, Debug, Default)]
pub struct FrameCache {
    entries: Vec<Entry>,
    by_hash: HashMap<u64, usize>,
    bytes: usize,
    clock: u64,
    key: Vec<u8>,
    hits: u64,
    lookups: u64,
}

/// The frame's pixels as runs: per run its length (u16) and its RGB bytes. Two frames are equal
/// exactly when their keys are. Returns the key's hash: FNV-1a over one word per run, made in
/// the same pass (a byte at a time over the key was a second pass, and slower).
fn run_length(frame: &Frame, key: &mut Vec<u8>) -> u64 {
    key.clear();
    let mut hash = crate::util::FNV_OFFSET;
    let mut end_run = |n: u16, rgb: u32| {
        key.extend_from_slice(&n.to_le_bytes());
        key.extend_from_slice(&rgb.to_le_bytes()[..3]);
        hash = (hash ^ (u64::from(rgb) << 16 | u64::from(n))).wrapping_mul(crate::util::FNV_PRIME);
    };
    // Each pixel's RGB as one word (alpha dropped).
    let rgb = |p: &[u8]| u32::from_le_bytes([p[0], p[1], p[2], 0]);
    let pixels = &frame.rgba;
    let count = pixels.len() / 4;
    if count == 0 {
        return hash;
    }
    let (mut current, mut n, mut i) = (rgb(&pixels[..4]), 1u16, 1);
    while i < count {
        // Eight pixels at a time while they continue the run (a compare that vectorises).
        if i + 8 <= count && n <= u16::MAX - 8 {
            let same = pixels[4 * i..4 * i + 32].chunks_exact(4).fold(true, |all, p| all & (rgb(p) == current));
            if same {
                (n, i) = (n + 8, i + 8);
                continue;
            }
        }
        let p = rgb(&pixels[4 * i..4 * i + 4]);
        if p == current && n < u16::MAX {
            n += 1;
        } else {
            end_run(n, current);
            (current, n) = (p, 1);
        }
        i += 1;
    }
    end_run(n, current);
    hash
}

impl FrameCache {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// The entry of `frame`, made (empty) if the frame is new; `None` when the cache is off.
    pub fn find(&mut self, frame: &Frame) -> Option<Slot> {
        if !crate::reuse::on() {
            return None;
        }
        let hash = run_length(frame, &mut self.key);
        self.clock += 1;
        self.lookups += 1;
        if let Some(&index) = self.by_hash.get(&hash) {
            let e = &mut self.entries[index];
            if e.key == self.key {
                e.used = self.clock;
                self.hits += 1;
                return Some(Slot { index, serial: e.serial });
            }
        }
        Some(self.insert(hash))
    }

    /// `find` of the frame whose entry is `slot`, when the caller knows the frame is that one
    /// (the same view as last time): the same bookkeeping, without encoding and hashing the frame.
    pub fn refind(&mut self, slot: Slot) -> Option<Slot> {
        self.clock += 1;
        self.lookups += 1;
        let e = self.entries.get_mut(slot.index).filter(|e| e.serial == slot.serial)?;
        e.used = self.clock;
        self.hits += 1;
        Some(slot)
    }

    fn insert(&mut self, hash: u64) -> Slot {
        let serial = self.clock;
        let entry = Entry { key: self.key.clone(), hash, serial, used: self.clock, embedding: None, mse: None };
        while !self.entries.is_empty() && (self.entries.len() >= CAPACITY || self.bytes + entry.key.len() > BYTES) {
            self.drop_oldest();
        }
        self.bytes += entry.key.len();
        self.entries.push(entry);
        let index = self.entries.len() - 1;
        // A colliding frame replaces the older one in the index (that one stays until dropped).
        self.by_hash.insert(hash, index);
        Slot { index, serial }
    }

    /// Drops the least recently used entry (the last entry takes its slot).
    fn drop_oldest(&mut self) {
        let (oldest, _) = self.entries.iter().enumerate().min_by_key(|(_, e)| e.used).expect("not empty");
        let gone = self.entries.swap_remove(oldest);
        self.bytes -= gone.key.len();
        if self.by_hash.get(&gone.hash) == Some(&oldest) {
            self.by_hash.remove(&gone.hash);
        }
        if let Some(moved) = self.entries.get(oldest) {
            if self.by_hash.get(&moved.hash) == Some(&self.entries.len()) {
                self.by_hash.insert(moved.hash, oldest);
            }
        }
    }

    fn entry(&mut self, slot: Option<Slot>) -> Option<&mut Entry> {
        let s = slot?;
        self.entries.get_mut(s.index).filter(|e| e.serial == s.serial)
    }

    /// The frame's embedding: remembered, or made by `compute` (and remembered).
    pub fn embedding(
        &mut self,
        slot: Option<Slot>,
        out: &mut [f32; EMBEDDING],
        compute: impl FnOnce(&mut [f32; EMBEDDING]),
    ) {
        if let Some(e) = self.entry(slot).and_then(|e| e.embedding) {
            *out = e;
            return;
        }
        compute(out);
        if let Some(e) = self.entry(slot) {
            e.embedding = Some(*out);
        }
    }

    /// The frame's reconstruction error: remembered, or measured by `compute` (and remembered).
    pub fn mse(&mut self, slot: Option<Slot>, compute: impl FnOnce() -> f32) -> f32 {
        if let Some(v) = self.entry(slot).and_then(|e| e.mse) {
            return v;
        }
        let v = compute();
        if let Some(e) = self.entry(slot) {
            e.mse = Some(v);
        }
        v
    }

    /// Frames held.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether it holds no frame.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// (lookups that found their frame, all lookups) so far.
    pub fn hit_rate(&self) -> (u64, u64) {
        (self.hits, self.lookups)
    }
}
