//! Where a run's embeddings come from (docs/ALGORITHM.md, "Perception").
//!
//! The authors' code built its encoder and autoencoder from the same freshly initialised Keras
//! layers, then replaced only the autoencoder with the trained model it loaded. So every
//! embedding their SEC and MFEC-ae stored and compared came from an untrained, Glorot-initialised
//! encoder, while the trained model fed only the reconstruction gate. `Untrained` does the same
//! (the "code" preset, the default); `Trained` embeds with the trained model as the paper's text
//! says (the "paper" preset).

use super::{bundled, Autoencoder, Scratch, EMBEDDING};
use crate::error::Error;
use crate::seed::Stream;

/// Which encoder makes the embeddings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PerceptionKind {
    /// A Glorot-initialised, never-trained encoder drawn from the run's seed (the authors' code).
    #[default]
    Untrained,
    /// The task's trained encoder with its calibrated scale (the paper's text).
    Trained,
}

impl PerceptionKind {
    /// Every perception with its name.
    pub const ALL: [(&'static str, PerceptionKind); 2] =
        [("untrained", PerceptionKind::Untrained), ("trained", PerceptionKind::Trained)];
}

pub use super::weights::{check_scale, SCALE_RANGE};

/// A run's perceptual layer: the trained autoencoder (it runs the reconstruction gate and the
/// page's reconstruction; an arena file has none, `without_model`) and, for `Untrained`, the
/// encoder that embeds.
#[derive(Clone, Debug)]
pub struct Perception {
    kind: PerceptionKind,
    trained: Option<Autoencoder>,
    untrained: Option<Autoencoder>,
}

impl Perception {
    /// The perception of a run of `task` with `seed`; `scale` replaces the embedding scale
    /// (`None`: the trained model's calibrated scale, or 1 for the untrained encoder, whose raw
    /// units are the authors').
    pub fn new(kind: PerceptionKind, task: &str, scale: Option<f32>, seed: u64) -> Result<Self, Error> {
        if let Some(s) = scale {
            check_scale(s)?;
        }
        let mut trained = bundled::autoencoder(task)?;
        let untrained = match kind {
            PerceptionKind::Trained => {
                if let Some(s) = scale {
                    trained.embedding_scale = s;
                }
                None
            }
            PerceptionKind::Untrained => Some(untrained_encoder(task, scale, seed)),
        };
        Ok(Perception { kind, trained: Some(trained), untrained })
    }

    /// The untrained perception of an arena no model was trained on (an arena file): it embeds
    /// with the untrained encoder drawn from `seed`, as `new` does, and has no gate model.
    pub fn without_model(name: &str, scale: Option<f32>, seed: u64) -> Result<Self, Error> {
        if let Some(s) = scale {
            check_scale(s)?;
        }
        let untrained = Some(untrained_encoder(name, scale, seed));
        Ok(Perception { kind: PerceptionKind::Untrained, trained: None, untrained })
    }

    /// Which encoder it is.
    pub fn kind(&self) -> PerceptionKind {
        self.kind
    }

    /// The trained autoencoder: the gate's model (`None` for an arena file's run).
    pub fn trained(&self) -> Option<&Autoencoder> {
        self.trained.as_ref()
    }

    /// The encoder whose outputs are the embeddings.
    pub fn embedder(&self) -> &Autoencoder {
        match (&self.untrained, &self.trained) {
            (Some(e), _) | (None, Some(e)) => e,
            (None, None) => unreachable!("a perception has an encoder that embeds"),
        }
    }

    /// The embedding of an image, times the embedding scale.
    pub fn embed(&self, image: &[f32], s: &mut Scratch, out: &mut [f32; EMBEDDING]) {
        self.embedder().encode(image, s, out);
    }

    /// Whether an embedding is also the gate model's (then the gate need not encode again).
    pub fn embeds_with_gate_model(&self) -> bool {
        self.untrained.is_none()
    }
}

/// The Glorot-initialised encoder of the run with `seed`, labelled `name`.
fn untrained_encoder(name: &str, scale: Option<f32>, seed: u64) -> Autoencoder {
    let mut rng = crate::seed::rng(seed, Stream::UntrainedEncoder);
    let mut e = Autoencoder::untrained_encoder(&mut rng);
    e.task = name.to_string();
    e.embedding_scale = scale.unwrap_or(1.0);
    e
}
