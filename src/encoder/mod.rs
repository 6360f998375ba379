//! The perceptual layer: the autoencoder's training data now; inference follows (issue 3).

pub mod dataset;
