//! burn's forward pass and the project's hand-written inference agree on the same weights: the
//! bundled trained model of every task, and Glorot weights.

use burn::prelude::*;
use sec_playground::arena::{Task, TASK_NAMES};
use sec_playground::encoder::dataset::{self, FRAME_BYTES};
use sec_playground::encoder::{bundled, Autoencoder, Scratch, EMBEDDING};
use sec_playground::render::Surface;
use sec_train::model::{batch_from_rgb, vec_of, BurnAe};

fn max_diff(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f32::max)
}

fn check(ae: &Autoencoder, task: &str) {
    // burn's model computes the raw bottleneck; the calibrated scale is applied after it.
    let mut ae = ae.clone();
    ae.embedding_scale = 1.0;
    let device = Device::flex();
    let burn = BurnAe::from_autoencoder(&ae, &device);
    let (rgb, _) = dataset::generate(&Task::preset(task).unwrap(), Surface::Flat, 6, 42).unwrap();
    let idx: Vec<usize> = (0..6).collect();
    let x = batch_from_rgb(&rgb, &idx, &device);
    let emb = burn.encode(x);
    let rec = vec_of(burn.decode(emb.clone()));
    let emb = vec_of(emb);
    let mut s = Scratch::default();
    let (mut worst_e, mut worst_r, mut mean_e) = (0.0f32, 0.0f32, 0.0f32);
    for i in 0..6 {
        let img: Vec<f32> = rgb[i * FRAME_BYTES..(i + 1) * FRAME_BYTES].iter().map(|&b| b as f32 / 255.0).collect();
        let mut e = [0.0; EMBEDDING];
        ae.encode(&img, &mut s, &mut e);
        let mut r = Vec::new();
        ae.decode(&e, &mut s, &mut r);
        worst_e = worst_e.max(max_diff(&e, &emb[i * EMBEDDING..(i + 1) * EMBEDDING]));
        mean_e += e.iter().sum::<f32>() / EMBEDDING as f32 / 6.0;
        // burn is channel-first; ours channel-last.
        let burn_r: Vec<f32> = (0..84 * 84 * 3).map(|k| rec[((i * 3 + k % 3) * 84 * 84) + k / 3]).collect();
        worst_r = worst_r.max(max_diff(&r, &burn_r));
    }
    eprintln!("{task}: max |diff| embedding {worst_e:e}, reconstruction {worst_r:e} (mean embedding {mean_e})");
    assert!(mean_e > 0.0, "embeddings all zero: the comparison would be vacuous");
    assert!(worst_e <= 1e-4, "embedding differs by {worst_e}");
    assert!(worst_r <= 1e-4, "reconstruction differs by {worst_r}");
}

#[test]
fn burn_forward_matches_own_inference() {
    for task in TASK_NAMES {
        check(&bundled::autoencoder(task).unwrap(), task);
    }
}

#[test]
fn glorot_weights_match_too() {
    check(&Autoencoder::glorot(7), "detour");
}

#[test]
fn weights_round_trip_through_burn_exactly() {
    let ae = Autoencoder::glorot(11);
    let back = BurnAe::from_autoencoder(&ae, &Device::flex()).to_autoencoder(&ae);
    assert_eq!(ae, back);
}
