//! The autoencoders' calibration report (issue 3, docs/ALGORITHM.md D17): per task the held-out
//! reconstruction MSE, the similarity 1 - MAE between embeddings of the same place slightly
//! perturbed and of different places, the nearest-neighbour MAE, a gallery of reconstructions and
//! the training curves. With `--calibrate` it also stores the embedding scale that puts the 0.98
//! threshold where the report says it belongs (see `calibrated_scale`).
//!
//! Usage: `cargo run --release -p sec-tools --bin encoder-report -- [--calibrate] [--pairs N]`
//! (reads assets/encoders and results/encoder/*-curve.csv; writes results/encoder and docs/encoder).

use plotters::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sec_playground::arena::{Task, TASK_NAMES};
use sec_playground::encoder::dataset::{self, first_frame, random_pose, Pose, FRAME_BYTES};
use sec_playground::encoder::{
    model_name, reconstruction_to_rgba, Autoencoder, DType, Scratch, Weights, EMBEDDING, IMAGE,
};
use sec_playground::render::{Camera, Frame, Surface, HEIGHT, WIDTH};
use sec_tools::{upscale, write_png};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The threshold of the contextual layer (1 - MAE > 0.98) as an MAE.
const MAE_THRESHOLD: f64 = 0.02;
/// Largest shift of a "same place" pair: half of what one env step can move or turn the agent.
const JITTER_POS: f32 = 0.25;
const JITTER_DEG: f32 = 3.0;
/// Held-out frames: the seed `sec-train` uses for them (training seed 1 + 1000).
const HELDOUT_SEED: u64 = 1001;
const HELDOUT: usize = 2000;

fn main() {
    if let Err(e) = run() {
        eprintln!("encoder-report: {e}");
        std::process::exit(2);
    }
}

struct Args {
    calibrate: bool,
    textured: bool,
    quote: Option<PathBuf>,
    pairs: usize,
    models: PathBuf,
    results: PathBuf,
    docs: PathBuf,
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        calibrate: false,
        textured: false,
        quote: None,
        pairs: 1000,
        models: "assets/encoders".into(),
        results: "results/encoder".into(),
        docs: "docs/encoder".into(),
    };
    let mut it = std::env::args().skip(1);
    while let Some(x) = it.next() {
        match x.as_str() {
            "--calibrate" => a.calibrate = true,
            "--textured" => a.textured = true,
            "--quote" => a.quote = Some(it.next().ok_or("--quote needs a page")?.into()),
            "--pairs" => {
                let v = it.next().unwrap_or_default();
                a.pairs = match v.parse() {
                    Ok(n) if (10..=100_000).contains(&n) => n,
                    _ => return Err(format!("--pairs: '{v}' is not in 10..=100000")),
                }
            }
            "--models" => a.models = it.next().ok_or("--models needs a folder")?.into(),
            "--results" => a.results = it.next().ok_or("--results needs a folder")?.into(),
            "--docs" => a.docs = it.next().ok_or("--docs needs a folder")?.into(),
            other => return Err(format!("unknown argument '{other}'")),
        }
    }
    Ok(a)
}

/// What the report measures for one task (MAE at the raw scale, i.e. embedding scale 1).
struct TaskReport {
    task: String,
    heldout_mse: f64,
    heldout_mse_max: f64,
    same: Vec<f64>,
    different: Vec<f64>,
    nearest: Vec<f64>,
    mean_abs: f64,
    dead_units: usize,
    scale: f64,
}

fn quantile(sorted: &[f64], q: f64) -> f64 {
    let i = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[i]
}

fn share_below(sorted: &[f64], x: f64) -> f64 {
    sorted.partition_point(|&v| v < x) as f64 / sorted.len() as f64
}

/// The smallest faithful fix of D17: one number per model that maps raw MAE to the authors'
/// units, chosen so that the 0.98 threshold (MAE < 0.02) best separates "same place" pairs (a
/// shift of up to half an env step) from "different place" pairs: it maximises the share of
/// same-place pairs that pass minus the share of different-place pairs that pass (Youden's J),
/// at the geometric middle of the best range. When the raw scale is already within 0.01 of that
/// optimum the model keeps scale 1, the authors' units.
fn calibrated_scale(same: &[f64], different: &[f64]) -> f64 {
    let j = |t: f64| share_below(same, t) - share_below(different, t);
    // J only changes just above a sample, so those are the candidates.
    let candidates: Vec<f64> = same.iter().chain(different).map(|&v| v * (1.0 + 1e-9) + 1e-12).collect();
    let best = candidates.iter().map(|&t| j(t)).fold(f64::MIN, f64::max);
    if j(MAE_THRESHOLD) >= best - 0.01 {
        return 1.0;
    }
    let at_best = candidates.iter().copied().filter(|&t| j(t) >= best - 1e-12);
    let (lo, hi) = at_best.fold((f64::INFINITY, 0.0f64), |(lo, hi), t| (lo.min(t), hi.max(t)));
    // The plateau runs from its first candidate up to the next sample above its last one.
    let next = same.iter().chain(different).copied().filter(|&v| v >= hi).fold(f64::INFINITY, f64::min);
    let hi = if next.is_finite() { next } else { hi };
    MAE_THRESHOLD / (lo * hi).sqrt()
}

fn embed(ae: &Autoencoder, frame: &Frame, s: &mut Scratch, img: &mut [f32]) -> [f32; EMBEDDING] {
    frame.to_rgb_f32(img);
    let mut e = [0.0; EMBEDDING];
    ae.encode(img, s, &mut e);
    e
}

fn mae(a: &[f32; EMBEDDING], b: &[f32; EMBEDDING]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs() as f64).sum::<f64>() / EMBEDDING as f64
}

fn measure(task: &Task, ae: &Autoencoder, pairs: usize) -> Result<TaskReport, String> {
    let mut raw = ae.clone();
    raw.embedding_scale = 1.0;
    let (rgb, _) = dataset::generate(task, Surface::Flat, HELDOUT, HELDOUT_SEED).map_err(|e| e.to_string())?;
    let mut s = Scratch::default();
    let mut img = vec![0.0f32; IMAGE];
    let mut embs = Vec::with_capacity(HELDOUT);
    let (mut sum, mut max) = (0.0f64, 0.0f64);
    for f in rgb.chunks_exact(FRAME_BYTES) {
        for (d, &b) in img.iter_mut().zip(f) {
            *d = b as f32 / 255.0;
        }
        let m = raw.reconstruction_mse(&img, &mut s) as f64;
        sum += m;
        max = max.max(m);
        let mut e = [0.0; EMBEDDING];
        raw.encode(&img, &mut s, &mut e);
        embs.push(e);
    }
    let mean_abs = embs.iter().flatten().map(|v| v.abs() as f64).sum::<f64>() / (HELDOUT * EMBEDDING) as f64;
    let dead_units = (0..EMBEDDING).filter(|&k| embs.iter().all(|e| e[k] == 0.0)).count();
    let mut nearest: Vec<f64> = (0..embs.len())
        .map(|i| (0..embs.len()).filter(|&j| j != i).map(|j| mae(&embs[i], &embs[j])).fold(f64::INFINITY, f64::min))
        .collect();
    nearest.sort_by(f64::total_cmp);

    // Pairs share the world (same spawn seed): only the agent's pose differs.
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut camera, mut fa, mut fb) = (Camera::new(), Frame::new(), Frame::new());
    let (mut same, mut different) = (Vec::with_capacity(pairs), Vec::with_capacity(pairs));
    for i in 0..pairs {
        let layout = &task.layouts[i % task.layouts.len()];
        let world_seed: u64 = rng.gen();
        let p = random_pose(&mut rng);
        let near = Pose {
            x: p.x + rng.gen_range(-JITTER_POS..=JITTER_POS),
            z: p.z + rng.gen_range(-JITTER_POS..=JITTER_POS),
            heading: (p.heading + rng.gen_range(-JITTER_DEG..=JITTER_DEG)).rem_euclid(360.0),
        };
        let far = random_pose(&mut rng);
        first_frame(layout, p, &mut ChaCha8Rng::seed_from_u64(world_seed), &mut camera, &mut fa);
        let ea = embed(&raw, &fa, &mut s, &mut img);
        first_frame(layout, near, &mut ChaCha8Rng::seed_from_u64(world_seed), &mut camera, &mut fb);
        same.push(mae(&ea, &embed(&raw, &fb, &mut s, &mut img)));
        first_frame(layout, far, &mut ChaCha8Rng::seed_from_u64(world_seed), &mut camera, &mut fb);
        different.push(mae(&ea, &embed(&raw, &fb, &mut s, &mut img)));
    }
    same.sort_by(f64::total_cmp);
    different.sort_by(f64::total_cmp);
    Ok(TaskReport {
        task: task.name.clone(),
        heldout_mse: sum / HELDOUT as f64,
        heldout_mse_max: max,
        scale: calibrated_scale(&same, &different),
        same,
        different,
        nearest,
        mean_abs,
        dead_units,
    })
}

/// Six held-out frames above their reconstructions, 2x enlarged.
fn gallery(task: &Task, ae: &Autoencoder, path: &Path) -> Result<(), String> {
    const N: usize = 6;
    let (rgb, _) = dataset::generate(task, Surface::Flat, N, HELDOUT_SEED).map_err(|e| e.to_string())?;
    let (w, h) = (WIDTH * N, HEIGHT * 2);
    let mut out = vec![255u8; w * h * 4];
    let mut s = Scratch::default();
    let mut img = vec![0.0f32; IMAGE];
    for (i, f) in rgb.chunks_exact(FRAME_BYTES).enumerate() {
        for (d, &b) in img.iter_mut().zip(f) {
            *d = b as f32 / 255.0;
        }
        let mut e = [0.0; EMBEDDING];
        ae.encode(&img, &mut s, &mut e);
        let mut rec = Vec::new();
        ae.decode(&e, &mut s, &mut rec);
        let mut rec_rgba = vec![0u8; WIDTH * HEIGHT * 4];
        reconstruction_to_rgba(&rec, &mut rec_rgba);
        for p in 0..WIDTH * HEIGHT {
            let (x, y) = (i * WIDTH + p % WIDTH, p / WIDTH);
            for c in 0..3 {
                out[(y * w + x) * 4 + c] = f[p * 3 + c];
                out[((y + HEIGHT) * w + x) * 4 + c] = rec_rgba[p * 4 + c];
            }
        }
    }
    write_png(path, w * 2, h * 2, &upscale(&out, w, h, 2))
}

/// A training curve as `sec-train` writes it: (epoch, training MSE, held-out MSE) per epoch, and
/// the epoch whose weights were kept (the last one unless the run used `--keep best`).
struct Curve {
    rows: Vec<(f64, f64, f64)>,
    kept: usize,
}

fn read_curve(path: &Path) -> Option<Curve> {
    let text = std::fs::read_to_string(path).ok()?;
    let header: Vec<&str> = text.lines().next()?.split(',').collect();
    let kept_col = header.iter().position(|&h| h == "kept");
    let mut curve = Curve { rows: Vec::new(), kept: 0 };
    for l in text.lines().skip(1) {
        let cols: Vec<&str> = l.split(',').collect();
        let v = |i: usize| cols.get(i).and_then(|x| x.parse::<f64>().ok());
        curve.rows.push((v(0)?, v(1)?, v(2)?));
        if kept_col.is_none_or(|k| v(k) == Some(1.0)) {
            curve.kept = v(0)? as usize;
        }
    }
    Some(curve)
}

const COLOURS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

fn plot_curves(curves: &[(String, Curve)], path: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::new(path, (760, 440)).into_drawing_area();
    root.fill(&WHITE)?;
    let epochs = curves.iter().map(|(_, c)| c.rows.len()).max().unwrap_or(1) as f64;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Autoencoder training: MSE per epoch (solid held-out, dashed training, dot = kept)",
            ("sans-serif", 16),
        )
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(60)
        .build_cartesian_2d(0.5..epochs + 0.5, (0.0005f64..0.1).log_scale())?;
    chart.configure_mesh().x_desc("epoch").y_desc("MSE (inputs in [0, 1])").draw()?;
    chart.draw_series(LineSeries::new([(0.5, 0.003), (epochs + 0.5, 0.003)], BLACK.mix(0.4)))?;
    for (i, (task, c)) in curves.iter().enumerate() {
        let col = COLOURS[i % COLOURS.len()];
        chart
            .draw_series(LineSeries::new(c.rows.iter().map(|p| (p.0, p.2)), col.stroke_width(2)))?
            .label(task.as_str())
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], col.stroke_width(2)));
        chart.draw_series(DashedLineSeries::new(c.rows.iter().map(|p| (p.0, p.1)), 4, 4, col.into()))?;
        if let Some(k) = c.rows.iter().find(|p| p.0 as usize == c.kept) {
            chart.draw_series([Circle::new((k.0, k.2), 4, col.filled())])?;
        }
    }
    chart.configure_series_labels().border_style(BLACK).background_style(WHITE.mix(0.9)).draw()?;
    root.present()?;
    Ok(())
}

/// Histograms of 1 - MAE (raw scale and calibrated) for same-place and different-place pairs.
fn plot_similarity(reports: &[TaskReport], path: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::new(path, (960, 120 + 200 * reports.len() as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(40);
    title.titled(
        "1 - MAE between embeddings: same place (blue, shift <= 0.25, <= 3 deg) vs different places (red); line = 0.98",
        ("sans-serif", 15),
    )?;
    let rows = body.split_evenly((reports.len(), 2));
    for (i, r) in reports.iter().enumerate() {
        for (k, (scale, label)) in [(1.0, "raw"), (r.scale, "calibrated")].into_iter().enumerate() {
            let area = &rows[i * 2 + k];
            let sim = |v: &[f64]| v.iter().map(|m| 1.0 - m * scale).collect::<Vec<_>>();
            let (same, diff) = (sim(&r.same), sim(&r.different));
            let lo = same.iter().chain(&diff).cloned().fold(1.0, f64::min).clamp(-2.0, 0.9);
            let bins = 40;
            let width = (1.0 - lo) / bins as f64;
            let count = |v: &[f64]| {
                let mut h = vec![0u32; bins];
                for &x in v {
                    let b = (((x - lo) / width) as usize).min(bins - 1);
                    h[b] += 1;
                }
                h
            };
            let (hs, hd) = (count(&same), count(&diff));
            let top = *hs.iter().chain(&hd).max().unwrap_or(&1) as f64 * 1.1;
            let mut chart = ChartBuilder::on(area)
                .caption(format!("{} ({label}, scale {:.3})", r.task, scale), ("sans-serif", 13))
                .margin(8)
                .x_label_area_size(24)
                .y_label_area_size(40)
                .build_cartesian_2d(lo..1.0, 0.0..top)?;
            chart.configure_mesh().disable_mesh().x_labels(6).y_labels(3).draw()?;
            for (h, col) in [(&hs, COLOURS[0]), (&hd, COLOURS[3])] {
                chart.draw_series(h.iter().enumerate().map(|(b, &n)| {
                    let x0 = lo + b as f64 * width;
                    Rectangle::new([(x0, 0.0), (x0 + width, n as f64)], col.mix(0.45).filled())
                }))?;
            }
            chart.draw_series(LineSeries::new([(0.98, 0.0), (0.98, top)], BLACK.stroke_width(1)))?;
        }
    }
    root.present()?;
    Ok(())
}

/// Mean and largest reconstruction MSE of `ae` over RGB frames.
fn mse_over(ae: &Autoencoder, rgb: &[u8]) -> (f64, f64) {
    let (mut s, mut img) = (Scratch::default(), vec![0.0f32; IMAGE]);
    let (mut sum, mut max, mut n) = (0.0f64, 0.0f64, 0usize);
    for f in rgb.chunks_exact(FRAME_BYTES) {
        for (d, &b) in img.iter_mut().zip(f) {
            *d = b as f32 / 255.0;
        }
        let m = ae.reconstruction_mse(&img, &mut s) as f64;
        (sum, max, n) = (sum + m, max.max(m), n + 1);
    }
    (sum / n as f64, max)
}

/// `--textured`: each task's textured model (where one is trained) on the held-out poses drawn
/// textured, beside the flat model on the same frames; the table docs/ENCODER.md quotes. Its
/// last columns are the gate rule of results/PROTOCOL.md (amendment of 2026-12-06, second):
/// Fisher's exact test of the frames the textured model's gate passes on textured frames against
/// those the flat model's passes on flat frames, and whether the model may serve the runs (no
/// difference at p < 0.05).
fn textured_report(args: &Args) -> Result<(), String> {
    let mut md = String::from(
        "| model | held-out MSE on textured frames, mean / worst | the flat model on the same frames | frames the gate passes: textured model / flat model | the flat model on flat frames: MSE, frames the gate passes | gate rule: Fisher p, textured on textured against flat on flat | serves the runs |\n|---|---|---|---|---|---|---|\n",
    );
    for name in TASK_NAMES {
        let load = |model: &str| -> Result<Option<Autoencoder>, String> {
            let path = args.models.join(format!("{model}.secae"));
            let Ok(bytes) = std::fs::read(&path) else { return Ok(None) };
            let w = Weights::from_bytes(&bytes).map_err(|e| format!("{}: {e}", path.display()))?;
            Autoencoder::from_weights(&w).map(Some).map_err(|e| format!("{}: {e}", path.display()))
        };
        let textured_name = model_name(name, Surface::Textured);
        let (Some(textured), Some(flat)) = (load(&textured_name)?, load(name)?) else { continue };
        let task = Task::preset(name).map_err(|e| e.to_string())?;
        let (rgb, _) = dataset::generate(&task, Surface::Textured, HELDOUT, HELDOUT_SEED).map_err(|e| e.to_string())?;
        // The default configuration's threshold, as a run's gate uses it.
        let threshold = sec_playground::agent::SecConfig::default().gate.ok_or("the gate is off by default")?;
        let open = |ae: &Autoencoder, rgb: &[u8]| {
            let (mut s, mut img) = (Scratch::default(), vec![0.0f32; IMAGE]);
            let passing = rgb
                .chunks_exact(FRAME_BYTES)
                .filter(|f| {
                    for (d, &b) in img.iter_mut().zip(f.iter()) {
                        *d = b as f32 / 255.0;
                    }
                    ae.reconstruction_mse(&img, &mut s) < threshold
                })
                .count();
            passing
        };
        let share = |passing: usize| 100.0 * passing as f64 / HELDOUT as f64;
        let (t, f) = (mse_over(&textured, &rgb), mse_over(&flat, &rgb));
        let (flat_rgb, _) =
            dataset::generate(&task, Surface::Flat, HELDOUT, HELDOUT_SEED).map_err(|e| e.to_string())?;
        let flat_on_flat = mse_over(&flat, &flat_rgb);
        let (ours, theirs, baseline) = (open(&textured, &rgb), open(&flat, &rgb), open(&flat, &flat_rgb));
        let p = sec_tools::stats::fisher_exact(ours, HELDOUT - ours, baseline, HELDOUT - baseline);
        writeln!(
            md,
            "| {textured_name} | {:.5} / {:.5} | {:.5} / {:.5} | {:.1} % / {:.1} % | {:.5}, {:.1} % | {p:.3} | {} |",
            t.0,
            t.1,
            f.0,
            f.1,
            share(ours),
            share(theirs),
            flat_on_flat.0,
            share(baseline),
            if p >= 0.05 { "yes" } else { "no" }
        )
        .map_err(|e| e.to_string())?;
    }
    let path = args.results.join("textured.md");
    std::fs::write(&path, &md).map_err(|e| format!("{}: {e}", path.display()))?;
    if let Some(page) = &args.quote {
        sec_tools::quote::quote_required(page, "encoder/textured", &md)?;
    }
    print!("{md}");
    Ok(())
}

fn run() -> Result<(), String> {
    let args = parse_args()?;
    if args.textured {
        std::fs::create_dir_all(&args.results).map_err(|e| e.to_string())?;
        return textured_report(&args);
    }
    sec_tools::plot::register_font();
    std::fs::create_dir_all(&args.results).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(&args.docs).map_err(|e| e.to_string())?;
    let mut reports = Vec::new();
    let mut curves = Vec::new();
    for name in TASK_NAMES {
        let path = args.models.join(format!("{name}.secae"));
        let Ok(bytes) = std::fs::read(&path) else {
            eprintln!("{name}: no model at {}, skipped", path.display());
            continue;
        };
        let weights = Weights::from_bytes(&bytes).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut ae = Autoencoder::from_weights(&weights).map_err(|e| format!("{}: {e}", path.display()))?;
        let task = Task::preset(name).map_err(|e| e.to_string())?;
        let r = measure(&task, &ae, args.pairs)?;
        if args.calibrate {
            ae.embedding_scale = r.scale as f32;
            std::fs::write(&path, ae.to_weights().to_bytes(DType::F16Planes)).map_err(|e| e.to_string())?;
        }
        gallery(&task, &ae, &args.docs.join(format!("{name}-gallery.png")))?;
        eprintln!(
            "{name}: held-out MSE {:.5}, same-place MAE median {:.4}, different-place MAE median {:.4}, scale {:.4}",
            r.heldout_mse,
            quantile(&r.same, 0.5),
            quantile(&r.different, 0.5),
            r.scale
        );
        if let Some(c) = read_curve(&args.results.join(format!("{name}-curve.csv"))) {
            curves.push((name.to_string(), c));
        }
        reports.push(r);
    }
    if !curves.is_empty() {
        plot_curves(&curves, &args.docs.join("training-curves.svg")).map_err(|e| e.to_string())?;
    }
    if !reports.is_empty() {
        plot_similarity(&reports, &args.docs.join("similarity.svg")).map_err(|e| e.to_string())?;
    }
    std::fs::write(args.results.join("calibration.md"), table(&reports, &curves, args.pairs))
        .map_err(|e| e.to_string())?;
    Ok(())
}

fn table(reports: &[TaskReport], curves: &[(String, Curve)], pairs: usize) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "<!-- written by `cargo run --release -p sec-tools --bin encoder-report`; {HELDOUT} held-out frames, {pairs} pairs per task -->\n"
    );
    let _ = writeln!(t, "| task | epochs (kept) | held-out MSE | worst frame | mean \\|e\\| | dead units | scale |");
    let _ = writeln!(t, "|---|---|---|---|---|---|---|");
    for r in reports {
        let epochs = curves
            .iter()
            .find(|(n, _)| *n == r.task)
            .map_or("?".to_string(), |(_, c)| format!("{} ({})", c.rows.len(), c.kept));
        let _ = writeln!(
            t,
            "| {} | {epochs} | {:.5} | {:.5} | {:.3} | {} | {:.4} |",
            r.task, r.heldout_mse, r.heldout_mse_max, r.mean_abs, r.dead_units, r.scale
        );
    }
    let _ = writeln!(t, "\nMAE between embeddings at the raw scale (quantiles 5 / 50 / 95 %) and the share of pairs");
    let _ = writeln!(t, "that pass the 0.98 threshold (MAE < 0.02) raw and after calibration:\n");
    let _ = writeln!(
        t,
        "| task | same place MAE | different places MAE | nearest neighbour MAE | same pass raw | different pass raw | same pass calibrated | different pass calibrated | nearest pass calibrated | J raw | J calibrated |"
    );
    let _ = writeln!(t, "|---|---|---|---|---|---|---|---|---|---|---|");
    let q = |v: &[f64]| format!("{:.4} / {:.4} / {:.4}", quantile(v, 0.05), quantile(v, 0.5), quantile(v, 0.95));
    let pct = |v: &[f64], x: f64| format!("{:.1} %", 100.0 * share_below(v, x));
    for r in reports {
        let cal = MAE_THRESHOLD / r.scale;
        let _ = writeln!(
            t,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.3} | {:.3} |",
            r.task,
            q(&r.same),
            q(&r.different),
            q(&r.nearest),
            pct(&r.same, MAE_THRESHOLD),
            pct(&r.different, MAE_THRESHOLD),
            pct(&r.same, cal),
            pct(&r.different, cal),
            pct(&r.nearest, cal),
            share_below(&r.same, MAE_THRESHOLD) - share_below(&r.different, MAE_THRESHOLD),
            share_below(&r.same, cal) - share_below(&r.different, cal)
        );
    }
    t
}
