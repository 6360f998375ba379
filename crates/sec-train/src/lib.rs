#![warn(missing_docs)]
//! Training of the paper's autoencoder with burn (docs/ENCODER.md): RMSprop
//! (Keras' defaults: rho 0.9, no momentum, epsilon 1e-7), lr 1e-3, MSE, batch 64, Glorot-uniform
//! initialisation, data reshuffled every epoch. Deterministic given the seed: the initial weights
//! and the shuffles come from the project's ChaCha generator, not from burn's.

pub mod model;

use burn::optim::{GradientsParams, RmsPropConfig};
use burn::prelude::*;
use model::{batch_from_rgb, BurnAe};
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use sec_playground::encoder::dataset::FRAME_BYTES;
use sec_playground::encoder::{Autoencoder, Scratch};

/// How a model is trained (the authors' settings by default).
#[derive(Clone, Debug)]
pub struct TrainConfig {
    /// Epochs to train up to (a resumed run counts the ones it continues).
    pub epochs: usize,
    /// Frames per RMSprop step.
    pub batch: usize,
    /// RMSprop's learning rate.
    pub lr: f64,
    /// Draws the initial weights and each epoch's shuffle.
    pub seed: u64,
}

impl Default for TrainConfig {
    fn default() -> Self {
        TrainConfig { epochs: 50, batch: 64, lr: 1e-3, seed: 1 }
    }
}

/// One epoch's numbers, as the training curve shows them.
#[derive(Clone, Debug)]
pub struct EpochLog {
    /// Its number, from 1.
    pub epoch: usize,
    /// Mean MSE over the epoch's training batches.
    pub train_mse: f64,
    /// MSE on the held-out frames, with the project's own inference.
    pub heldout_mse: f64,
    /// MSE on a third set, used only to choose the epoch to keep (`--keep best`).
    pub validation_mse: f64,
    /// Wall seconds the epoch took.
    pub seconds: f64,
}

/// The training device: burn's pure-Rust CPU backend with autodiff.
pub fn train_device() -> Device {
    Device::flex().autodiff()
}

/// Held-out reconstruction MSE measured with the project's own inference (what the agent runs).
pub fn heldout_mse(ae: &Autoencoder, rgb: &[u8]) -> f64 {
    let mut s = Scratch::default();
    let mut img = vec![0.0f32; FRAME_BYTES];
    let n = rgb.len() / FRAME_BYTES;
    let mut sum = 0.0f64;
    for f in rgb.chunks_exact(FRAME_BYTES) {
        for (d, &b) in img.iter_mut().zip(f) {
            *d = b as f32 / 255.0;
        }
        sum += ae.reconstruction_mse(&img, &mut s) as f64;
    }
    sum / n.max(1) as f64
}

/// Where training starts: from Glorot weights drawn with the seed, or from the weights an earlier
/// run kept after `epoch` epochs.
pub enum Start {
    /// Glorot weights drawn with the seed.
    Fresh,
    /// The weights an earlier run kept, and the epoch they are from.
    Resume {
        /// The kept weights.
        weights: Box<Autoencoder>,
        /// The epoch they were kept after.
        epoch: usize,
    },
}

/// Trains up to epoch `cfg.epochs`; calls `log` after every epoch. A resumed run replays the
/// earlier epochs' shuffles, so it sees the data in the order an uninterrupted run would; the
/// optimiser's running averages are not in the weights file and restart from zero.
pub fn train(
    task: &str,
    rgb: &[u8],
    heldout: &[u8],
    validation: &[u8],
    cfg: &TrainConfig,
    start: Start,
    mut log: impl FnMut(&EpochLog, &Autoencoder),
) -> Autoencoder {
    let device = train_device();
    let (init, done) = match start {
        Start::Fresh => (Autoencoder::glorot(cfg.seed), 0),
        Start::Resume { weights, epoch } => (*weights, epoch),
    };
    let mut init = init;
    init.task = task.to_string();
    let mut model = BurnAe::from_autoencoder(&init, &device);
    let mut optim = RmsPropConfig::new().with_alpha(0.9).with_momentum(0.0).with_epsilon(1e-7).init();
    let n = rgb.len() / FRAME_BYTES;
    let mut order: Vec<usize> = (0..n).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed ^ 0x5EC0_AE00);
    for _ in 0..done {
        order.shuffle(&mut rng);
    }
    let mut current = init.clone();
    for epoch in done + 1..=cfg.epochs {
        let t0 = std::time::Instant::now();
        order.shuffle(&mut rng);
        let mut sum = 0.0f64;
        for chunk in order.chunks(cfg.batch) {
            let x = batch_from_rgb(rgb, chunk, &device);
            let loss = (model.forward(x.clone()) - x).square().mean();
            sum += loss.clone().into_scalar::<f32>() as f64 * chunk.len() as f64;
            let grads = GradientsParams::from_grads(loss.backward(), &model);
            model = optim.step(cfg.lr, model, grads);
        }
        current = model.to_autoencoder(&init);
        let entry = EpochLog {
            epoch,
            train_mse: sum / n as f64,
            heldout_mse: heldout_mse(&current, heldout),
            validation_mse: heldout_mse(&current, validation),
            seconds: t0.elapsed().as_secs_f64(),
        };
        log(&entry, &current);
    }
    current
}

/// Seconds per training step of `batch` random-pose frames (for choosing the framework).
pub fn bench_steps(rgb: &[u8], batch: usize, steps: usize) -> f64 {
    let device = train_device();
    let init = Autoencoder::glorot(1);
    let mut model = BurnAe::from_autoencoder(&init, &device);
    let mut optim = RmsPropConfig::new().with_alpha(0.9).with_momentum(0.0).with_epsilon(1e-7).init();
    let idx: Vec<usize> = (0..batch).collect();
    let mut run = |model: BurnAe| {
        let x = batch_from_rgb(rgb, &idx, &device);
        let loss = (model.forward(x.clone()) - x).square().mean();
        let _ = loss.clone().into_scalar::<f32>();
        let grads = GradientsParams::from_grads(loss.backward(), &model);
        optim.step(1e-3, model, grads)
    };
    model = run(model);
    let t0 = std::time::Instant::now();
    for _ in 0..steps {
        model = run(model);
    }
    t0.elapsed().as_secs_f64() / steps as f64
}
