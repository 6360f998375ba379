//! The perceptual layer: the paper's autoencoder (training data, weights file, inference) and
//! the reconstruction-error gate that lets the contextual layer act only on familiar views.

pub mod bundled;
pub mod cache;
pub mod dataset;
pub mod kernels;
pub mod model;
pub mod perception;
pub mod weights;

pub use cache::FrameCache;
pub use model::{Autoencoder, Scratch, EMBEDDING, IMAGE, PARAMETERS};
pub use perception::{Perception, PerceptionKind};
pub use weights::{DType, Weights};

use crate::render::Surface;

/// The name of a task's trained model for frames of `surface`: the task's own name for the flat
/// frames, `<task>-textured` for the textured ones (`assets/encoders/<name>.secae`; the weights
/// file records it as its task).
pub fn model_name(task: &str, surface: Surface) -> String {
    match surface {
        Surface::Flat => task.to_string(),
        Surface::Textured => format!("{task}-textured"),
    }
}

/// The reconstruction gate (docs/ALGORITHM.md, "Perception"): the reconstruction MSE of the current frame,
/// re-measured on every 16th env step, starting at 100 so the contextual layer stays off until
/// the first measurement.
///
/// The measurement is lazy: on a measuring step the gate keeps a copy of the frame, and the
/// autoencoder runs only when someone reads the value before the next measuring step (the
/// arbitration reads it only when the contextual layer selected something). When the step's
/// embedding is already known (a decision on the same frame), the encoder is not run twice. The
/// value read is the same, bit for bit, as measuring eagerly.
#[derive(Clone, Debug, PartialEq)]
pub struct ReconstructionGate {
    /// The last computed MSE (100 before the first measurement).
    mse: f32,
    steps: u64,
    /// A measurement taken but not yet computed: its frame, and its embedding if known.
    pending: bool,
    image: Vec<f32>,
    embedding: Option<[f32; EMBEDDING]>,
    /// The measured frame's entry in the run's `FrameCache` (not part of the saved state: a
    /// cache entry is only a memo).
    slot: Option<cache::Slot>,
}

impl Default for ReconstructionGate {
    fn default() -> Self {
        Self::new()
    }
}

impl ReconstructionGate {
    /// The value before the first measurement (above any reconstruction error of [0, 1] pixels).
    pub const INITIAL: f32 = 100.0;
    /// Env steps between measurements.
    pub const PERIOD: u64 = 16;
    /// The most steps a checkpoint's gate may have counted (far beyond any run).
    pub const MAX_STEPS: u64 = 1 << 50;

    /// A gate that has measured nothing yet.
    pub fn new() -> Self {
        ReconstructionGate {
            mse: Self::INITIAL,
            steps: 0,
            pending: false,
            image: vec![0.0; IMAGE],
            embedding: None,
            slot: None,
        }
    }

    /// The gate's state for a run checkpoint: the last MSE, the step count and a pending
    /// measurement's frame and embedding.
    pub(crate) fn put_state(&self, b: &mut Vec<u8>) {
        b.extend_from_slice(&self.mse.to_le_bytes());
        b.extend_from_slice(&self.steps.to_le_bytes());
        b.push(self.pending as u8);
        crate::util::put_f32s(b, &self.image);
        b.push(self.embedding.is_some() as u8);
        for v in self.embedding.unwrap_or([0.0; EMBEDDING]) {
            b.extend_from_slice(&v.to_le_bytes());
        }
    }

    pub(crate) fn take_state(&mut self, r: &mut crate::util::ByteReader) -> Result<(), crate::error::FileError> {
        let field = |what: &str, rule: String| crate::error::FileError::field("checkpoint", what.to_string(), rule);
        let (mse, steps, pending) = (r.f32()?, r.u64()?, r.bool()?);
        if !(mse.is_finite() && mse >= 0.0) {
            return Err(field("gate.mse", format!("{mse} is not a finite number >= 0")));
        }
        if steps > Self::MAX_STEPS {
            return Err(field("gate.steps", format!("{steps} is out of range 0..={}", Self::MAX_STEPS)));
        }
        let image = r.f32s(IMAGE, "gate.image")?;
        if image.len() != IMAGE {
            return Err(field("gate.image", "is not a frame".into()));
        }
        if !image.iter().all(|v| (0.0..=1.0).contains(v)) {
            return Err(field("gate.image", "holds a pixel outside [0, 1]".into()));
        }
        let known = r.bool()?;
        let mut e = [0.0f32; EMBEDDING];
        for v in &mut e {
            *v = r.f32()?;
        }
        if !e.iter().all(|v| v.is_finite()) {
            return Err(field("gate.embedding", "holds a value that is not a finite number".into()));
        }
        *self = ReconstructionGate { mse, steps, pending, image, embedding: known.then_some(e), slot: None };
        Ok(())
    }

    /// Whether it has taken a measurement (before, its value is `INITIAL`, which no reconstruction
    /// passes).
    pub fn has_measured(&self) -> bool {
        self.steps >= Self::PERIOD
    }

    /// Called once per env step with the current image (and its entry in the run's frame
    /// cache); measures on every 16th call.
    pub fn watch(&mut self, image: &[f32], slot: Option<cache::Slot>) {
        // Saturating: a checkpoint's count is at most MAX_STEPS, and no run lives 2^50 steps.
        self.steps = self.steps.saturating_add(1);
        if self.steps % Self::PERIOD == 0 {
            self.image.copy_from_slice(image);
            self.pending = true;
            self.embedding = None;
            self.slot = slot;
        }
    }

    /// Whether the next `watch` measures (so the caller must pass the current image).
    pub fn due(&self) -> bool {
        (self.steps + 1) % Self::PERIOD == 0
    }

    /// Whether the last `watch` measured: then `share_embedding` may pass that frame's
    /// embedding.
    pub fn measured_now(&self) -> bool {
        self.pending && self.steps % Self::PERIOD == 0
    }

    /// The embedding `ae.encode` gave for the frame of the measuring step just taken, which
    /// saves the encoder pass when the value is read.
    pub fn share_embedding(&mut self, e: &[f32; EMBEDDING]) {
        if self.measured_now() {
            self.embedding = Some(*e);
        }
    }

    /// The gate's value: the MSE of the last measured frame (computed now if it was not yet,
    /// or taken from `cache` if the frame was measured before).
    pub fn mse(&mut self, ae: &Autoencoder, scratch: &mut Scratch, cache: &mut FrameCache) -> f32 {
        if self.pending {
            let (image, embedding) = (&self.image, self.embedding);
            self.mse = cache.mse(self.slot, || match embedding {
                Some(e) => ae.reconstruction_mse_of(image, &e, scratch),
                None => ae.reconstruction_mse(image, scratch),
            });
            self.pending = false;
        }
        self.mse
    }

    /// The last computed value, without computing a pending one (for display).
    pub fn last_mse(&self) -> f32 {
        self.mse
    }

    /// Whether the contextual layer may act: MSE strictly below the threshold (0.01 by default).
    pub fn open(&mut self, threshold: f32, ae: &Autoencoder, scratch: &mut Scratch, cache: &mut FrameCache) -> bool {
        self.mse(ae, scratch, cache) < threshold
    }
}

/// A reconstruction (84x84x3 floats) as RGBA8 for display: clamped to [0, 1], rounded, opaque.
pub fn reconstruction_to_rgba(rec: &[f32], out: &mut [u8]) {
    assert_eq!(rec.len() / 3, out.len() / 4, "one RGBA pixel per reconstructed pixel");
    for (o, p) in out.chunks_exact_mut(4).zip(rec.chunks_exact(3)) {
        for k in 0..3 {
            o[k] = (p[k].clamp(0.0, 1.0) * 255.0).round() as u8;
        }
        o[3] = 255;
    }
}
