//! The perceptual layer: the paper's autoencoder (training data, weights file, inference) and
//! the reconstruction-error gate that lets the contextual layer act only on familiar views.

pub mod bundled;
pub mod dataset;
pub mod kernels;
pub mod model;
pub mod weights;

pub use model::{Autoencoder, Scratch, EMBEDDING, IMAGE, PARAMETERS};
pub use weights::{DType, Weights};

/// The gate of sec-algorithm.md section 4: the reconstruction MSE of the current frame,
/// re-measured on every 16th env step, starting at 100 so the contextual layer stays off until
/// the first measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct ReconstructionGate {
    /// The last measured MSE (100 before the first).
    pub mse: f32,
    steps: u64,
}

impl Default for ReconstructionGate {
    fn default() -> Self {
        Self::new()
    }
}

impl ReconstructionGate {
    pub const INITIAL: f32 = 100.0;
    pub const PERIOD: u64 = 16;

    pub fn new() -> Self {
        ReconstructionGate { mse: Self::INITIAL, steps: 0 }
    }

    /// Called once per env step with the current image; re-measures on every 16th call.
    pub fn advance(&mut self, ae: &Autoencoder, image: &[f32], scratch: &mut Scratch) {
        self.steps += 1;
        if self.steps % Self::PERIOD == 0 {
            self.mse = ae.reconstruction_mse(image, scratch);
        }
    }

    /// Whether the next `advance` measures (so the caller must pass the current image).
    pub fn due(&self) -> bool {
        (self.steps + 1) % Self::PERIOD == 0
    }

    /// Whether the contextual layer may act: MSE strictly below the threshold (0.01 by default).
    pub fn open(&self, threshold: f32) -> bool {
        self.mse < threshold
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
