//! `sec-train`: trains the paper's autoencoder for a task and writes its weights.
//!
//! ```text
//! sec-train train --task double-t-maze [--surface flat|textured] [--epochs 50] [--seed 1]
//!                 [--frames 10000] [--heldout 2000] [--keep last|best] [--resume | --init FILE]
//!                 [--out assets/encoders] [--log results/encoder]
//! sec-train bench [STEPS]
//! ```
//! The training frames are `dataset::generate(task, frames, seed)`, the held-out frames the same
//! with seed + 1000, and a validation set of the same size with seed + 2000. After every epoch
//! the training curve (CSV) is rewritten, and the weights (f16) too: always with `--keep last`
//! (the authors' procedure, the default), only when the validation MSE improved with
//! `--keep best`. `--surface textured` draws the frames with the textured renderer and names the
//! model `<task>-textured` (`encoder::model_name`); `--init FILE` starts from that weights file
//! (the task's flat model, for a textured one) instead of Glorot weights. Either way an interrupted run keeps what it has finished, and `--resume`
//! continues it (same seed and data) from the weights file and its curve, up to `--epochs`.

use sec_playground::arena::{Task, TASK_NAMES};
use sec_playground::encoder::dataset;
use sec_playground::encoder::{model_name, Autoencoder, DType, Weights};
use sec_playground::render::Surface;
use sec_train::{heldout_mse, train, Start, TrainConfig};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn main() {
    // One thread: burn's CPU backend trains no faster with two here (measured, BENCHMARKS.md),
    // and a single thread keeps every sum in one order, so the weights are a function of the seed.
    std::env::set_var("RAYON_NUM_THREADS", "1");
    if let Err(e) = run() {
        eprintln!("sec-train: {e}");
        std::process::exit(2);
    }
}

fn parse<T: std::str::FromStr + PartialOrd + std::fmt::Display + Copy>(
    name: &str,
    v: Option<String>,
    min: T,
    max: T,
) -> Result<T, String> {
    let v = v.ok_or(format!("{name} needs a value in {min}..={max}"))?;
    match v.parse::<T>() {
        Ok(x) if x >= min && x <= max => Ok(x),
        _ => Err(format!("{name}: '{v}' is not in {min}..={max}")),
    }
}

fn run() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    match args.next().as_deref() {
        Some("train") => {}
        Some("bench") => {
            let steps = parse("STEPS", Some(args.next().unwrap_or("5".into())), 1usize, 1000)?;
            let task = Task::preset("double-t-maze").map_err(|e| e.to_string())?;
            let (rgb, _) = dataset::generate(&task, Surface::Flat, 64, 1).map_err(|e| e.to_string())?;
            let s = sec_train::bench_steps(&rgb, 64, steps);
            println!("burn flex: {s:.3} s per batch of 64 = {:.1} frames/s", 64.0 / s);
            return Ok(());
        }
        _ => return Err("usage: sec-train train --task NAME [--surface flat|textured] [--init FILE] [--epochs N] [--seed N] [--frames N] [--heldout N] [--keep last|best] [--resume] [--out DIR] [--log DIR] | sec-train bench [STEPS]".into()),
    }
    let mut task_name = None;
    let mut surface = Surface::Flat;
    let mut init: Option<PathBuf> = None;
    let mut cfg = TrainConfig::default();
    let (mut frames, mut held) = (10_000usize, 2_000usize);
    let (mut keep_best, mut resume) = (false, false);
    let (mut out, mut log_dir) = (PathBuf::from("assets/encoders"), PathBuf::from("results/encoder"));
    while let Some(a) = args.next() {
        match a.as_str() {
            "--task" => {
                let v = args.next().unwrap_or_default();
                if !TASK_NAMES.contains(&v.as_str()) {
                    return Err(format!("--task: '{v}' is not one of {}", TASK_NAMES.join(", ")));
                }
                task_name = Some(v);
            }
            "--epochs" => cfg.epochs = parse("--epochs", args.next(), 1, 1000)?,
            "--seed" => cfg.seed = parse("--seed", args.next(), 0, u64::MAX)?,
            "--frames" => frames = parse("--frames", args.next(), 64, 1_000_000)?,
            "--heldout" => held = parse("--heldout", args.next(), 1, 100_000)?,
            "--keep" => {
                keep_best = match args.next().as_deref() {
                    Some("last") => false,
                    Some("best") => true,
                    v => return Err(format!("--keep: '{}' is not one of last, best", v.unwrap_or(""))),
                }
            }
            "--surface" => {
                surface =
                    Surface::from_name(&args.next().unwrap_or_default()).map_err(|e| format!("--surface: {e}"))?;
            }
            "--resume" => resume = true,
            "--init" => init = Some(args.next().ok_or("--init needs a weights file")?.into()),
            "--out" => out = args.next().ok_or("--out needs a folder")?.into(),
            "--log" => log_dir = args.next().ok_or("--log needs a folder")?.into(),
            other => return Err(format!("unknown argument '{other}'")),
        }
    }
    let task_name = task_name.ok_or(format!("--task is required: one of {}", TASK_NAMES.join(", ")))?;
    let task = Task::preset(&task_name).map_err(|e| e.to_string())?;
    let name = model_name(&task_name, surface);
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    std::fs::create_dir_all(&log_dir).map_err(|e| format!("{}: {e}", log_dir.display()))?;
    let t0 = std::time::Instant::now();
    let (rgb, _) = dataset::generate(&task, surface, frames, cfg.seed).map_err(|e| e.to_string())?;
    let (heldout, _) = dataset::generate(&task, surface, held, cfg.seed + 1000).map_err(|e| e.to_string())?;
    let (validation, _) = dataset::generate(&task, surface, held, cfg.seed + 2000).map_err(|e| e.to_string())?;
    eprintln!("{name}: {frames} + {held} + {held} frames rendered in {:.1} s", t0.elapsed().as_secs_f64());
    let weights_path = out.join(format!("{name}.secae"));
    let curve_path = log_dir.join(format!("{name}-curve.csv"));
    let mut csv = String::from("epoch,train_mse,heldout_mse,seconds,validation_mse,kept\n");
    let mut best = f64::INFINITY;
    if resume && init.is_some() {
        return Err("--resume and --init exclude each other: a resumed run starts from its own weights".into());
    }
    let start = if let Some(path) = &init {
        // A weights file is a few hundred KiB; 64 MiB is far beyond any.
        let bytes = sec_playground::util::read_regular_file(path, "--init", 64 << 20)?;
        let weights = Weights::from_bytes(&bytes)
            .and_then(|w| Autoencoder::from_weights(&w))
            .map_err(|e| format!("--init: {}: {e}", path.display()))?;
        // With --keep best, an epoch is kept only if it improves on where training started.
        best = heldout_mse(&weights, &validation);
        eprintln!(
            "{name}: from {} (held-out MSE {:.5}, validation MSE {best:.5})",
            path.display(),
            heldout_mse(&weights, &heldout)
        );
        Start::Resume { weights: Box::new(weights), epoch: 0 }
    } else if resume {
        let (weights, epoch, rows) = resume_from(&weights_path, &curve_path, &name)?;
        if epoch >= cfg.epochs {
            return Err(format!(
                "--resume: {} already holds epoch {epoch}; ask for more --epochs",
                weights_path.display()
            ));
        }
        csv += &rows;
        best = heldout_mse(&weights, &validation);
        eprintln!("{name}: resuming after epoch {epoch} (validation MSE {best:.5})");
        Start::Resume { weights: Box::new(weights), epoch }
    } else {
        Start::Fresh
    };
    let mut kept = None;
    train(&name, &rgb, &heldout, &validation, &cfg, start, |e, ae| {
        let keep = !keep_best || e.validation_mse < best;
        eprintln!(
            "{name} epoch {}/{}: train MSE {:.5}, held-out MSE {:.5}, validation MSE {:.5} ({:.0} s){}",
            e.epoch,
            cfg.epochs,
            e.train_mse,
            e.heldout_mse,
            e.validation_mse,
            e.seconds,
            if keep { ", kept" } else { "" }
        );
        let _ = writeln!(
            csv,
            "{},{:.6},{:.6},{:.1},{:.6},{}",
            e.epoch, e.train_mse, e.heldout_mse, e.seconds, e.validation_mse, keep as u8
        );
        if keep {
            best = best.min(e.validation_mse);
            kept = Some(ae.clone());
            let _ = std::fs::write(&weights_path, ae.to_weights().to_bytes(DType::F16Planes));
        }
        let _ = std::fs::write(&curve_path, &csv);
    });
    let Some(ae) = kept else {
        eprintln!("{name}: no epoch improved on the resumed weights; {} unchanged", weights_path.display());
        return Ok(());
    };
    let stored =
        sec_playground::encoder::Weights::from_bytes(&std::fs::read(&weights_path).map_err(|e| e.to_string())?)
            .and_then(|w| sec_playground::encoder::Autoencoder::from_weights(&w))
            .map_err(|e| e.to_string())?;
    eprintln!(
        "{name}: held-out MSE {:.5} (f32), {:.5} (as stored, f16); {} written",
        heldout_mse(&ae, &heldout),
        heldout_mse(&stored, &heldout),
        weights_path.display()
    );
    Ok(())
}

/// The weights a run kept, the epoch they are from, and the curve's rows up to that epoch (later
/// rows belong to epochs that `--keep best` did not keep, which the resumed run redoes).
fn resume_from(weights: &Path, curve: &Path, task: &str) -> Result<(Autoencoder, usize, String), String> {
    let bytes = std::fs::read(weights).map_err(|e| format!("--resume: {}: {e}", weights.display()))?;
    let ae = Weights::from_bytes(&bytes)
        .and_then(|w| Autoencoder::from_weights(&w))
        .map_err(|e| format!("--resume: {}: {e}", weights.display()))?;
    if ae.task != task {
        return Err(format!("--resume: {} holds the model of '{}'", weights.display(), ae.task));
    }
    let text = std::fs::read_to_string(curve).map_err(|e| format!("--resume: {}: {e}", curve.display()))?;
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default();
    let kept_col = header.split(',').position(|h| h == "kept");
    let mut rows: Vec<(usize, bool, String)> = Vec::new();
    for (i, l) in lines.enumerate() {
        let cols: Vec<&str> = l.split(',').collect();
        let epoch = cols[0].parse().map_err(|_| format!("--resume: {} line {}: bad epoch", curve.display(), i + 2))?;
        // Curves from before the `kept` column kept every epoch.
        let kept = kept_col.is_none_or(|k| cols.get(k) == Some(&"1"));
        // Older curves lack the last two columns: fill them so the file stays rectangular.
        let line = if cols.len() < 6 { format!("{l},,{}", kept as u8) } else { l.to_string() };
        rows.push((epoch, kept, line));
    }
    let epoch = rows
        .iter()
        .filter(|r| r.1)
        .map(|r| r.0)
        .max()
        .ok_or(format!("--resume: {} has no kept epoch", curve.display()))?;
    let text = rows.iter().filter(|r| r.0 <= epoch).map(|r| format!("{}\n", r.2)).collect();
    Ok((ae, epoch, text))
}
