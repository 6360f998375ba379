//! The autoencoder: architecture, inference against an independent f64 reference, the weights
//! file (round trip, f16 accuracy, every kind of bad file), the reconstruction gate, and a golden
//! embedding that `tests/wasm.rs` checks bit for bit under Node, and the bundled trained models.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::arena::{Task, TASK_NAMES};
use sec_playground::encoder::{
    bundled, Autoencoder, DType, FrameCache, ReconstructionGate, Scratch, Weights, EMBEDDING, IMAGE, PARAMETERS,
};
use sec_playground::env::{Env, EnvConfig};
use sec_playground::render::{fnv1a, Surface};

fn frame(task: &str) -> Vec<f32> {
    let mut env = Env::new(EnvConfig::new(Task::preset(task).unwrap()), 1).unwrap();
    let mut rgb = vec![0.0; IMAGE];
    env.observation().to_rgb_f32(&mut rgb);
    rgb
}

/// Straightforward f64 NHWC layers, written independently of the kernels.
#[allow(clippy::too_many_arguments)]
mod reference {
    pub fn conv(
        x: &[f64],
        h: usize,
        w: usize,
        ci: usize,
        wt: &[f32],
        b: &[f32],
        co: usize,
        same: bool,
    ) -> (Vec<f64>, usize, usize) {
        let (oh, ow, pad) = if same { (h, w, 1i64) } else { (h - 2, w - 2, 0) };
        let mut out = vec![0.0; oh * ow * co];
        for oy in 0..oh {
            for ox in 0..ow {
                for o in 0..co {
                    let mut s = b[o] as f64;
                    for ky in 0..3i64 {
                        for kx in 0..3i64 {
                            let (iy, ix) = (oy as i64 + ky - pad, ox as i64 + kx - pad);
                            if iy < 0 || ix < 0 || iy >= h as i64 || ix >= w as i64 {
                                continue;
                            }
                            for i in 0..ci {
                                let wi = ((ky as usize * 3 + kx as usize) * ci + i) * co + o;
                                s += x[(iy as usize * w + ix as usize) * ci + i] * wt[wi] as f64;
                            }
                        }
                    }
                    out[(oy * ow + ox) * co + o] = s.max(0.0);
                }
            }
        }
        (out, oh, ow)
    }
    pub fn pool(x: &[f64], h: usize, w: usize, c: usize) -> (Vec<f64>, usize, usize) {
        let (oh, ow) = (h.div_ceil(2), w.div_ceil(2));
        let mut out = vec![f64::MIN; oh * ow * c];
        for y in 0..h {
            for xx in 0..w {
                for k in 0..c {
                    let o = &mut out[((y / 2) * ow + xx / 2) * c + k];
                    *o = o.max(x[(y * w + xx) * c + k]);
                }
            }
        }
        (out, oh, ow)
    }
    pub fn up(x: &[f64], h: usize, w: usize, c: usize) -> (Vec<f64>, usize, usize) {
        let mut out = vec![0.0; 4 * h * w * c];
        for y in 0..2 * h {
            for xx in 0..2 * w {
                for k in 0..c {
                    out[(y * 2 * w + xx) * c + k] = x[((y / 2) * w + xx / 2) * c + k];
                }
            }
        }
        (out, 2 * h, 2 * w)
    }
    pub fn dense(x: &[f64], wt: &[f32], b: &[f32], relu: bool) -> Vec<f64> {
        (0..b.len())
            .map(|j| {
                let s = b[j] as f64 + x.iter().enumerate().map(|(i, v)| v * wt[i * b.len() + j] as f64).sum::<f64>();
                if relu {
                    s.max(0.0)
                } else {
                    s
                }
            })
            .collect()
    }
}

fn reference_forward(ae: &Autoencoder, image: &[f32]) -> (Vec<f64>, Vec<f64>) {
    use reference::*;
    let w = ae.to_weights();
    let t = |i: usize| w.tensors[i].data.as_slice();
    let x: Vec<f64> = image.iter().map(|&v| v as f64).collect();
    let (x, h, wd) = conv(&x, 84, 84, 3, t(0), t(1), 16, true);
    let (x, h, wd) = pool(&x, h, wd, 16);
    let (x, h, wd) = conv(&x, h, wd, 16, t(2), t(3), 32, true);
    let (x, h, wd) = pool(&x, h, wd, 32);
    let (x, h, wd) = conv(&x, h, wd, 32, t(4), t(5), 32, true);
    let (x, _, _) = pool(&x, h, wd, 32);
    let emb = dense(&x, t(6), t(7), true);
    let x = dense(&emb, t(8), t(9), false);
    let (x, h, wd) = conv(&x, 11, 11, 32, t(10), t(11), 32, true);
    let (x, h, wd) = up(&x, h, wd, 32);
    let (x, h, wd) = conv(&x, h, wd, 32, t(12), t(13), 32, true);
    let (x, h, wd) = up(&x, h, wd, 32);
    let (x, h, wd) = conv(&x, h, wd, 32, t(14), t(15), 16, false);
    let (x, h, wd) = up(&x, h, wd, 16);
    let (rec, _, _) = conv(&x, h, wd, 16, t(16), t(17), 3, true);
    (emb, rec)
}

#[test]
fn the_architecture_has_the_papers_parameter_count() {
    assert_eq!(Autoencoder::glorot(1).parameter_count(), PARAMETERS);
    assert_eq!(PARAMETERS, 196_663);
}

#[test]
fn inference_matches_an_f64_reference() {
    let ae = Autoencoder::glorot(3);
    for task in ["double-t-maze", "cylinder"] {
        let img = frame(task);
        let (emb_ref, rec_ref) = reference_forward(&ae, &img);
        let mut s = Scratch::default();
        let mut emb = [0.0; EMBEDDING];
        ae.encode(&img, &mut s, &mut emb);
        let mut rec = Vec::new();
        ae.decode(&emb, &mut s, &mut rec);
        let de = emb.iter().zip(&emb_ref).map(|(a, b)| (*a as f64 - b).abs()).fold(0.0, f64::max);
        let dr = rec.iter().zip(&rec_ref).map(|(a, b)| (*a as f64 - b).abs()).fold(0.0, f64::max);
        assert!(de <= 1e-5 && dr <= 1e-5, "{task}: embedding off by {de}, reconstruction by {dr}");
        assert!(emb.iter().any(|&v| v > 0.0), "{task}: a dead embedding proves nothing");
        assert_eq!(rec.len(), IMAGE);
    }
}

#[test]
fn f16_byte_planes_load_the_same_values_as_plain_f16() {
    let w = sec_playground::encoder::bundled::autoencoder("double-t-maze").unwrap().to_weights();
    let plain = w.to_bytes(DType::F16);
    let planes = w.to_bytes(DType::F16Planes);
    assert_eq!(plain.len(), planes.len());
    assert_ne!(plain, planes);
    assert_eq!(Weights::from_bytes(&plain).unwrap(), Weights::from_bytes(&planes).unwrap());
    // The committed models are stored in planes (what the page downloads).
    assert_eq!(
        include_bytes!("../assets/encoders/double-t-maze.secae")[12..16],
        (DType::F16Planes as u32).to_le_bytes()
    );
}

#[test]
fn weights_round_trip_and_f16_keeps_embeddings_within_1e_3() {
    let mut ae = Autoencoder::glorot(4);
    ae.task = "cylinder".into();
    let w = ae.to_weights();
    let back = Weights::from_bytes(&w.to_bytes(DType::F32)).unwrap();
    assert_eq!(back, w);
    let half_bytes = w.to_bytes(DType::F16);
    assert!(half_bytes.len() < 2 * PARAMETERS + 1024, "{} bytes", half_bytes.len());
    let ae16 = Autoencoder::from_weights(&Weights::from_bytes(&half_bytes).unwrap()).unwrap();
    assert_eq!(ae16.task, "cylinder");
    let img = frame("detour");
    let mut s = Scratch::default();
    let (mut a, mut b) = ([0.0; EMBEDDING], [0.0; EMBEDDING]);
    ae.encode(&img, &mut s, &mut a);
    ae16.encode(&img, &mut s, &mut b);
    let d = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f32::max);
    assert!(d <= 1e-3, "f16 storage moves the embedding by {d}");
}

#[test]
fn bad_weight_files_are_clear_errors() {
    let w = Autoencoder::glorot(5).to_weights();
    let good = w.to_bytes(DType::F16);
    let msg = |b: &[u8]| Weights::from_bytes(b).unwrap_err().to_string();
    assert!(msg(b"PNG....").contains("bad magic"));
    assert_eq!(Weights::from_bytes(b"PNG....").unwrap_err().file, "weights");
    let mut flipped = good.clone();
    flipped[200] ^= 0x10;
    assert!(msg(&flipped).contains("checksum mismatch"));
    assert!(
        msg(&good[..good.len() / 2]).contains("checksum mismatch")
            || msg(&good[..good.len() / 2]).contains("truncated")
    );
    let mut v2 = good.clone();
    v2[8] = 2;
    assert!(msg(&v2).contains("version 2 is not supported"));
    // A well-formed file for another architecture.
    let mut other = w.clone();
    other.tensors[0].shape = vec![3, 3, 3, 8];
    other.tensors[0].data.truncate(3 * 3 * 3 * 8);
    let e = Autoencoder::from_weights(&Weights::from_bytes(&other.to_bytes(DType::F32)).unwrap()).unwrap_err();
    assert!(e.to_string().contains("enc.conv1.w has shape [3, 3, 3, 8], expected [3, 3, 3, 16]"), "{e}");
    let mut missing = w;
    missing.tensors.pop();
    assert!(Autoencoder::from_weights(&missing).unwrap_err().to_string().contains("dec.conv4.b is missing"));
}

#[test]
fn the_gate_starts_closed_and_measures_every_16th_step() {
    let ae = Autoencoder::glorot(6);
    let img = frame("detour");
    let mut s = Scratch::default();
    let mut gate = ReconstructionGate::new();
    let mut c = FrameCache::new();
    for _ in 0..15 {
        gate.watch(&img, None);
        assert_eq!(gate.mse(&ae, &mut s, &mut c), 100.0);
        assert!(!gate.open(0.01, &ae, &mut s, &mut c));
    }
    gate.watch(&img, None);
    assert_eq!(gate.last_mse(), 100.0, "measured lazily");
    let mse = ae.reconstruction_mse(&img, &mut s);
    assert_eq!(gate.mse(&ae, &mut s, &mut c), mse);
    assert!(mse < 100.0 && mse > 0.0);
    // Later frames do not change the value until the next 16th step, which measures its own.
    let other = frame("cylinder");
    for _ in 0..15 {
        gate.watch(&other, None);
    }
    assert_eq!(gate.mse(&ae, &mut s, &mut c), mse);
    gate.watch(&other, None);
    // With the frame's embedding shared, the same value without a second encoder pass.
    let mut e = [0.0; EMBEDDING];
    ae.encode(&other, &mut s, &mut e);
    assert!(gate.measured_now());
    gate.share_embedding(&e);
    assert_eq!(gate.mse(&ae, &mut s, &mut c), ae.reconstruction_mse(&other, &mut s));
    assert!(!gate.measured_now());
}

/// The embedding of the T-maze's first frame under the bundled T-maze model, as raw bits, and a
/// fingerprint of its reconstruction's bits: the wasm test compares the same numbers. `SEC_UPDATE_GOLDEN=1` rewrites the file.
#[test]
fn a_fixed_frame_gives_the_golden_embedding() {
    let ae = bundled::autoencoder("double-t-maze").unwrap();
    let mut e = [0.0; EMBEDDING];
    ae.encode(&frame("double-t-maze"), &mut Scratch::default(), &mut e);
    assert!(e.iter().filter(|&&v| v > 0.0).count() >= 5, "a mostly dead embedding proves little: {e:?}");
    let mut rec = Vec::new();
    ae.decode(&e, &mut Scratch::default(), &mut rec);
    let bytes: Vec<u8> = rec.iter().flat_map(|v| v.to_le_bytes()).collect();
    let mut text: String = e.iter().map(|v| format!("{:08x}\n", v.to_bits())).collect();
    text += &format!("reconstruction fnv1a {:016x}\n", fnv1a(&bytes));
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden/embedding.txt");
    if std::env::var("SEC_UPDATE_GOLDEN").is_ok_and(|v| v == "1") {
        std::fs::write(path, &text).unwrap();
    }
    assert_eq!(text, std::fs::read_to_string(path).unwrap());
}

/// The bound on held-out reconstruction MSE (inputs in [0, 1]).
const BOUND: f64 = 0.003;

/// Every task has a bundled model that names its task, carries a usable scale, and reconstructs
/// the first 400 of its held-out frames (the set `sec-train` reports, seed 1001) within the bound.
#[test]
fn every_bundled_model_reconstructs_its_held_out_frames() {
    use sec_playground::encoder::dataset;
    for task in TASK_NAMES {
        let ae = bundled::autoencoder(task).unwrap();
        assert_eq!(ae.task, task);
        assert!(ae.embedding_scale.is_finite() && ae.embedding_scale > 0.0, "{task}: scale {}", ae.embedding_scale);
        let (rgb, _) = dataset::generate(&Task::preset(task).unwrap(), Surface::Flat, 400, 1001).unwrap();
        let mut s = Scratch::default();
        let mut img = vec![0.0; IMAGE];
        let mut sum = 0.0f64;
        for f in rgb.chunks_exact(dataset::FRAME_BYTES) {
            for (d, &b) in img.iter_mut().zip(f) {
                *d = b as f32 / 255.0;
            }
            sum += ae.reconstruction_mse(&img, &mut s) as f64;
        }
        let mse = sum / 400.0;
        assert!(mse <= BOUND, "{task}: held-out reconstruction MSE {mse:.5} > {BOUND}");
    }
    let e = bundled::autoencoder("maze").unwrap_err().to_string();
    assert!(e.contains("task") && e.contains("double-t-maze"), "{e}");
}

/// The textured models (docs/ENCODER.md, "Textured frames") reconstruct textured frames better
/// than their task's flat model does and pass the gate on more of them; a task without one
/// refuses a textured run by name.
#[test]
fn textured_models_fit_textured_frames_better_than_the_flat_ones() {
    use sec_playground::encoder::{dataset, model_name};
    use sec_playground::experiment::{Run, RunConfig};
    let gate = f64::from(sec_playground::agent::SecConfig::default().gate.unwrap());
    let mut trained = 0;
    for task in TASK_NAMES {
        let name = model_name(task, Surface::Textured);
        let Ok(textured) = bundled::autoencoder(&name) else {
            let cfg = RunConfig { task: task.to_string(), surface: Surface::Textured, ..RunConfig::default() };
            let e = Run::new(cfg, 1).err().expect("no textured model, no textured run").to_string();
            assert!(e.contains(&format!("no model '{name}' is trained yet")), "{e}");
            continue;
        };
        trained += 1;
        assert_eq!(textured.task, name);
        let flat = bundled::autoencoder(task).unwrap();
        let (rgb, _) = dataset::generate(&Task::preset(task).unwrap(), Surface::Textured, 200, 1001).unwrap();
        let (mut s, mut img) = (Scratch::default(), vec![0.0; IMAGE]);
        let (mut mse, mut open) = ([0.0f64; 2], [0usize; 2]);
        for f in rgb.chunks_exact(dataset::FRAME_BYTES) {
            for (d, &b) in img.iter_mut().zip(f) {
                *d = b as f32 / 255.0;
            }
            for (k, ae) in [&textured, &flat].into_iter().enumerate() {
                let m = ae.reconstruction_mse(&img, &mut s) as f64;
                mse[k] += m / 200.0;
                open[k] += (m < gate) as usize;
            }
        }
        assert!(mse[0] < mse[1] && open[0] > open[1], "{name}: MSE {mse:?}, frames under the gate {open:?}");
    }
    assert!(trained >= 1, "the double T-maze has a textured model");
}

/// Registered models (the wasm page's fetched files) are checked like bundled ones, must name a
/// known task, and take the place of the task's model; a refused file changes nothing.
#[test]
fn registered_models_are_checked_and_used() {
    let bytes = sec_playground::arena::TaskInfo::find("detour").unwrap().model;
    let mut w = Weights::from_bytes(bytes).unwrap();
    w.task = "maze".into();
    let e = bundled::register(&w.to_bytes(DType::F16)).unwrap_err().to_string();
    assert!(e.starts_with("weights:") && e.contains("'maze'") && e.contains("double-t-maze"), "{e}");
    let mut corrupt = bytes.to_vec();
    corrupt[500] ^= 1;
    assert!(bundled::register(&corrupt).unwrap_err().to_string().contains("checksum"));
    // A detour model with another scale, registered: the task's model is now that one.
    let mut w = Weights::from_bytes(bytes).unwrap();
    w.embedding_scale *= 2.0;
    assert_eq!(bundled::register(&w.to_bytes(DType::F16)).unwrap(), "detour");
    assert!(bundled::has("detour"));
    let ae = bundled::autoencoder("detour").unwrap();
    assert_eq!(ae.embedding_scale, w.embedding_scale);
    assert_ne!(
        ae.fingerprint(),
        Autoencoder::from_weights(&Weights::from_bytes(bytes).unwrap()).unwrap().fingerprint()
    );
    // Back to the committed file, as the other tests expect.
    bundled::register(bytes).unwrap();
    assert_eq!(
        bundled::autoencoder("detour").unwrap().embedding_scale,
        Weights::from_bytes(bytes).unwrap().embedding_scale
    );
}

#[test]
fn the_untrained_encoder_is_keras_glorot_uniform_with_zero_biases() {
    use sec_playground::encoder::model::{glorot_limit, TENSORS};
    use sec_playground::encoder::{Perception, PerceptionKind};
    let p = Perception::new(PerceptionKind::Untrained, "double-t-maze", None, 11).unwrap();
    let w = p.embedder().to_weights();
    assert_eq!(w.embedding_scale, 1.0, "raw units, as the authors' encoder");
    for (t, (name, shape)) in w.tensors.iter().zip(TENSORS) {
        if !name.starts_with("enc.") || shape.len() == 1 {
            assert!(t.data.iter().all(|&v| v == 0.0), "{name}: biases and the unused decoder are zero");
            continue;
        }
        let (limit, (fan_in, fan_out)) = glorot_limit(shape);
        // Keras: fan = kernel area x channels, limit sqrt(6 / (fan_in + fan_out)).
        let area: usize = shape[..shape.len() - 2].iter().product();
        assert_eq!((fan_in, fan_out), (area * shape[shape.len() - 2], area * shape[shape.len() - 1]), "{name}");
        let n = t.data.len() as f64;
        let mean = t.data.iter().map(|&v| v as f64).sum::<f64>() / n;
        let var = t.data.iter().map(|&v| (v as f64 - mean).powi(2)).sum::<f64>() / n;
        let max = t.data.iter().fold(0.0f32, |m, v| m.max(v.abs()));
        let want_var = (limit as f64).powi(2) / 3.0;
        assert!(max < limit && max > 0.98 * limit, "{name}: max |w| {max} vs limit {limit}");
        // U(-l, l): mean 0 with sd l / sqrt(3n); variance l^2 / 3 with relative sd sqrt(0.8 / n).
        assert!(mean.abs() < 5.0 * (want_var / n).sqrt(), "{name}: mean {mean}");
        assert!((var / want_var - 1.0).abs() < 5.0 * (0.8 / n).sqrt(), "{name}: variance {var} vs {want_var}");
    }
    // The conv1 limit by hand: fan_in 3 x 3 x 3 = 27, fan_out 3 x 3 x 16 = 144.
    assert_eq!(glorot_limit(&[3, 3, 3, 16]).0, (6.0f32 / 171.0).sqrt());
}

#[test]
fn the_untrained_encoder_is_drawn_from_the_runs_seed() {
    use sec_playground::encoder::{Perception, PerceptionKind};
    let fp = |seed, kind| Perception::new(kind, "detour", None, seed).unwrap().embedder().fingerprint();
    assert_eq!(fp(3, PerceptionKind::Untrained), fp(3, PerceptionKind::Untrained));
    assert_ne!(fp(3, PerceptionKind::Untrained), fp(4, PerceptionKind::Untrained));
    // The trained perception embeds with the task's model, whatever the seed.
    assert_eq!(fp(3, PerceptionKind::Trained), fp(4, PerceptionKind::Trained));
    assert_eq!(fp(3, PerceptionKind::Trained), bundled::autoencoder("detour").unwrap().fingerprint());
    // Either way the gate's model is the trained one, and an embedding is finite and >= 0.
    let p = Perception::new(PerceptionKind::Untrained, "detour", Some(2.0), 3).unwrap();
    assert_eq!(p.trained().unwrap().fingerprint(), bundled::autoencoder("detour").unwrap().fingerprint());
    let mut e = [0.0; EMBEDDING];
    p.embed(&frame("detour"), &mut Scratch::default(), &mut e);
    assert!(e.iter().all(|v| v.is_finite() && *v >= 0.0) && e.iter().any(|&v| v > 0.0), "{e:?}");
    let mut raw = [0.0; EMBEDDING];
    Perception::new(PerceptionKind::Untrained, "detour", None, 3).unwrap().embed(
        &frame("detour"),
        &mut Scratch::default(),
        &mut raw,
    );
    assert_eq!(e, raw.map(|v| v * 2.0), "the scale multiplies the raw outputs");
}

#[test]
fn bad_embedding_scales_are_refused_by_name() {
    use sec_playground::encoder::{Perception, PerceptionKind};
    for s in [0.0, -1.0, f32::NAN, f32::INFINITY, 2e6] {
        let e = Perception::new(PerceptionKind::Trained, "detour", Some(s), 1).unwrap_err();
        assert_eq!(e.field(), "embeddingScale", "{s}");
        assert!(matches!(e, sec_playground::Error::Config(_)), "a value, not a file");
    }
}

/// The frame cache remembers per frame, finds a frame again only when every pixel is the same,
/// keeps the `CAPACITY` most recently used frames, and never answers for a dropped entry.
#[test]
fn the_frame_cache_remembers_equal_frames_only() {
    use sec_playground::encoder::cache::CAPACITY;
    use sec_playground::render::Frame;
    let numbered = |n: usize| {
        let mut f = Frame::new();
        f.rgba[..8].copy_from_slice(&(n as u64).to_le_bytes());
        f
    };
    let mut c = FrameCache::new();
    let mut computed = 0;
    let mut mse = |c: &mut FrameCache, slot, v: f32| {
        c.mse(slot, || {
            computed += 1;
            v
        })
    };
    let first = c.find(&numbered(0));
    assert_eq!(mse(&mut c, first, 0.5), 0.5);
    // The same pixels: remembered (the closure's value is not used); one pixel off: a new frame.
    let again = c.find(&numbered(0));
    assert_eq!(again, first);
    assert_eq!(mse(&mut c, again, 9.0), 0.5);
    let mut other = numbered(0);
    other.rgba[4 * 7055 + 2] ^= 1;
    let other = c.find(&other);
    assert_ne!(other, first);
    assert_eq!(mse(&mut c, other, 0.25), 0.25);
    // Embeddings likewise.
    let mut e = [0.0; EMBEDDING];
    c.embedding(first, &mut e, |e| e[3] = 1.5);
    let mut e2 = [0.0; EMBEDDING];
    c.embedding(first, &mut e2, |e| e[3] = 7.0);
    assert_eq!((e[3], e2[3]), (1.5, 1.5));
    // Filling it drops the least recently used: `other` (frame 0 was used after it).
    c.find(&numbered(0));
    for n in 1..CAPACITY {
        c.find(&numbered(n));
    }
    assert_eq!(c.len(), CAPACITY);
    assert_eq!(mse(&mut c, other, 0.75), 0.75, "a dropped entry is measured again");
    assert_eq!(mse(&mut c, first, 9.0), 0.5, "frame 0 was used recently and is kept");
    assert_eq!(computed, 3);
    assert_eq!(c.hit_rate(), (2, CAPACITY as u64 + 3));
}

/// One pixel changed anywhere in a flat frame, inside a long run (where the key is built eight
/// pixels at a time) or at its edges, is another frame; the same change again is found; alpha is
/// not part of a frame.
#[test]
fn the_frame_cache_tells_apart_frames_that_differ_in_one_pixel() {
    use sec_playground::render::Frame;
    let flat = || {
        let mut f = Frame::new();
        f.rgba.chunks_exact_mut(4).for_each(|p| p.copy_from_slice(&[10, 20, 30, 255]));
        f
    };
    let mut c = FrameCache::new();
    let base = c.find(&flat());
    let positions = [0, 1, 7, 8, 9, 15, 16, 17, 3000, 7047, 7048, 7054, 7055];
    let slots: Vec<_> = positions
        .iter()
        .flat_map(|&p| {
            (0..3).map(move |channel| {
                let mut f = flat();
                f.rgba[4 * p + channel] ^= 1;
                f
            })
        })
        .map(|f| c.find(&f))
        .collect();
    let mut all = slots.clone();
    all.push(base);
    all.sort_by_key(|s| format!("{s:?}"));
    all.dedup();
    assert_eq!(all.len(), slots.len() + 1, "every changed frame is a new one");
    let mut f = flat();
    f.rgba[4 * 3000 + 1] ^= 1;
    assert_eq!(c.find(&f), slots[8 * 3 + 1]);
    let mut alpha = flat();
    alpha.rgba[4 * 20 + 3] = 0;
    assert_eq!(c.find(&alpha), base);
}
