//! How our camera's frames compare with the real Animal-AI v1 observations the authors' repository
//! stores (`tests/reference-frames/`, recovered by `scripts/reference-frames.py`).
//!
//! Each real frame is a data-set image of the authors' autoencoder notebooks: a first frame at a
//! whole-number pose (x, z in 5..=34, heading 0..=358) of a known task. The pose is found by
//! rendering every such pose of the task and keeping the one with the smallest mean absolute
//! error; then each surface (`flat`, `textured`) is rendered there and compared: per-row mean
//! colour error, local contrast per region (floor, fence, wall, sky), mean absolute pixel error and
//! SSIM.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use sec_playground::arena::Task;
use sec_playground::encoder::dataset::{first_frame, Pose};
use sec_playground::render::{colours, Camera, Frame, Surface, HEIGHT, WIDTH};
use std::fmt::Write as _;
use std::path::Path;

/// One real frame and the task its data set was drawn in.
#[derive(Clone, Debug)]
pub struct Reference {
    /// File stem, e.g. `permanence-58`.
    pub name: String,
    /// Our task of the authors' data set.
    pub task: String,
    /// 84 x 84 RGB, row 0 at the top.
    pub rgb: Vec<u8>,
}

/// The authors' data-set names and our tasks.
const DATASETS: [(&str, &str); 3] =
    [("detour", "detour"), ("permanence", "object-permanence"), ("cylinder", "cylinder")];

/// Reads the frames `provenance.json` in `dir` lists.
pub fn load(dir: &Path) -> Result<Vec<Reference>, String> {
    let path = dir.join("provenance.json");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut out: Vec<Reference> = Vec::new();
    for s in v["sources"].as_array().ok_or("provenance.json: no sources")? {
        let name = s["frame"].as_str().ok_or("provenance.json: a source without frame")?.to_string();
        if out.iter().any(|r| r.name == name) {
            continue;
        }
        let dataset = s["dataset"].as_str().ok_or("provenance.json: a source without dataset")?;
        let task = DATASETS
            .iter()
            .find(|(d, _)| *d == dataset)
            .map(|(_, t)| t.to_string())
            .ok_or_else(|| format!("provenance.json: unknown data set '{dataset}'"))?;
        let rgb = read_rgb(&dir.join(format!("{name}.png")))?;
        out.push(Reference { name, task, rgb });
    }
    Ok(out)
}

fn read_rgb(path: &Path) -> Result<Vec<u8>, String> {
    let file = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut reader =
        png::Decoder::new(std::io::BufReader::new(file)).read_info().map_err(|e| format!("{}: {e}", path.display()))?;
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).map_err(|e| format!("{}: {e}", path.display()))?;
    if (info.width as usize, info.height as usize) != (WIDTH, HEIGHT) || info.bit_depth != png::BitDepth::Eight {
        return Err(format!("{}: not an 84x84 8-bit image", path.display()));
    }
    let channels = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        _ => return Err(format!("{}: not RGB", path.display())),
    };
    Ok(buf[..info.buffer_size()].chunks_exact(channels).flat_map(|p| [p[0], p[1], p[2]]).collect())
}

/// Our first frame of `task` at a pose, as RGB.
pub fn render(task: &Task, layout: usize, pose: Pose, surface: Surface, camera: &mut Camera) -> Vec<u8> {
    let mut frame = Frame::new();
    camera.set_surface(surface);
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    first_frame(&task.layouts[layout], pose, &mut rng, camera, &mut frame);
    frame.rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect()
}

/// Mean absolute error over every pixel and channel, in 8-bit levels.
pub fn mae(a: &[u8], b: &[u8]) -> f64 {
    a.iter().zip(b).map(|(&x, &y)| (x as i32 - y as i32).unsigned_abs() as u64).sum::<u64>() as f64 / a.len() as f64
}

/// A found pose: layout index, pose and its error.
#[derive(Clone, Copy, Debug)]
pub struct Fit {
    /// The task layout's index.
    pub layout: usize,
    /// Where the agent stands and looks.
    pub pose: Pose,
    /// The mean absolute error (0-255) of the frame rendered there against the real one.
    pub mae: f64,
}

/// Which poses `best_pose` tries: every whole-number pose of the authors' data sets (x, z in
/// 5..=34, heading 0..=358, every layout), or those within one step of a given one.
#[derive(Clone, Copy, Debug)]
pub enum Search {
    /// Every whole-number pose of every layout.
    Full,
    /// The poses of layout `.0` within one step of `.1`.
    Around(usize, Pose),
}

/// The pose whose `surface` frame is nearest `rgb` (mean absolute error) among `search`'s; ties
/// go to the first in (layout, x, z, heading) order. On two threads: each takes every other x.
pub fn best_pose(task: &Task, rgb: &[u8], surface: Surface, search: Search) -> Fit {
    let (layouts, xs, zs, hs): (Vec<usize>, Vec<u32>, Vec<u32>, Vec<u32>) = match search {
        Search::Full => ((0..task.layouts.len()).collect(), (5..35).collect(), (5..35).collect(), (0..359).collect()),
        Search::Around(l, p) => {
            let near = |v: f32, lo: u32, hi: u32| ((v as u32).max(lo + 1) - 1..=(v as u32 + 1).min(hi)).collect();
            (vec![l], near(p.x, 5, 34), near(p.z, 5, 34), near(p.heading, 0, 358))
        }
    };
    let search = |parity: usize| {
        let mut camera = Camera::new();
        let mut best = Fit { layout: 0, pose: Pose { x: 0.0, z: 0.0, heading: 0.0 }, mae: f64::INFINITY };
        for &layout in &layouts {
            for &x in xs.iter().skip(parity).step_by(2) {
                for &z in &zs {
                    for &h in &hs {
                        let pose = Pose { x: x as f32, z: z as f32, heading: h as f32 };
                        let e = mae(&render(task, layout, pose, surface, &mut camera), rgb);
                        if e < best.mae {
                            best = Fit { layout, pose, mae: e };
                        }
                    }
                }
            }
        }
        best
    };
    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(|| search(0));
        let b = search(1);
        (a.join().expect("the search thread"), b)
    });
    let order = |f: &Fit| (f.layout, f.pose.x as u32, f.pose.z as u32, f.pose.heading as u32);
    if b.mae < a.mae || (b.mae == a.mae && order(&b) < order(&a)) {
        b
    } else {
        a
    }
}

/// The regions a frame's pixels are compared in, found on our flat frame at the same pose (each
/// surface there has one colour).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Region {
    /// The arena's floor.
    Floor,
    /// The fence around it.
    Fence,
    /// Walls and other objects inside.
    Wall,
    /// Above the fence.
    Sky,
}

impl Region {
    /// The table's order.
    pub const ALL: [Region; 4] = [Region::Floor, Region::Fence, Region::Wall, Region::Sky];
}

fn regions(flat: &[u8]) -> Vec<Region> {
    let is = |p: &[u8], c: sec_playground::arena::Rgb| p == [c.0, c.1, c.2];
    flat.chunks_exact(3)
        .map(|p| {
            if is(p, colours::SKY) {
                Region::Sky
            } else if is(p, colours::FLOOR) {
                Region::Floor
            } else if is(p, colours::FENCE) {
                Region::Fence
            } else {
                Region::Wall
            }
        })
        .collect()
}

fn luma(rgb: &[u8]) -> Vec<f64> {
    rgb.chunks_exact(3).map(|p| 0.299 * p[0] as f64 + 0.587 * p[1] as f64 + 0.114 * p[2] as f64).collect()
}

/// Local contrast ("texture energy") of a region: the mean over its pixels whose 3 x 3
/// neighbourhood lies wholly inside it of |Y - the neighbourhood's mean Y|; `None` if it has none.
pub fn contrast(rgb: &[u8], region: &[Region], which: Region) -> Option<f64> {
    let y = luma(rgb);
    let (mut sum, mut n) = (0.0, 0usize);
    for r in 1..HEIGHT - 1 {
        for c in 1..WIDTH - 1 {
            let around = || (r - 1..=r + 1).flat_map(move |rr| (c - 1..=c + 1).map(move |cc| rr * WIDTH + cc));
            if around().all(|i| region[i] == which) {
                let m = around().map(|i| y[i]).sum::<f64>() / 9.0;
                sum += (y[r * WIDTH + c] - m).abs();
                n += 1;
            }
        }
    }
    (n > 0).then(|| sum / n as f64)
}

/// Mean SSIM of the luminance over every 7 x 7 window (uniform weights; C1 = (0.01 L)^2,
/// C2 = (0.03 L)^2, L = 255).
pub fn ssim(a: &[u8], b: &[u8]) -> f64 {
    const K: usize = 7;
    let (ya, yb) = (luma(a), luma(b));
    let (c1, c2) = ((0.01f64 * 255.0).powi(2), (0.03f64 * 255.0).powi(2));
    let (mut total, mut n) = (0.0, 0usize);
    for r in 0..=HEIGHT - K {
        for c in 0..=WIDTH - K {
            let idx = || (r..r + K).flat_map(move |rr| (c..c + K).map(move |cc| rr * WIDTH + cc));
            let k = (K * K) as f64;
            let (ma, mb) = (idx().map(|i| ya[i]).sum::<f64>() / k, idx().map(|i| yb[i]).sum::<f64>() / k);
            let va = idx().map(|i| (ya[i] - ma).powi(2)).sum::<f64>() / (k - 1.0);
            let vb = idx().map(|i| (yb[i] - mb).powi(2)).sum::<f64>() / (k - 1.0);
            let cov = idx().map(|i| (ya[i] - ma) * (yb[i] - mb)).sum::<f64>() / (k - 1.0);
            total += ((2.0 * ma * mb + c1) * (2.0 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
            n += 1;
        }
    }
    total / n as f64
}

/// Per row, the absolute difference of the two frames' mean colour, averaged over the channels.
pub fn row_colour_error(a: &[u8], b: &[u8]) -> Vec<f64> {
    (0..HEIGHT)
        .map(|r| {
            let row =
                |x: &[u8], k: usize| (0..WIDTH).map(|c| x[(r * WIDTH + c) * 3 + k] as f64).sum::<f64>() / WIDTH as f64;
            (0..3).map(|k| (row(a, k) - row(b, k)).abs()).sum::<f64>() / 3.0
        })
        .collect()
}

/// One real frame against each surface.
#[derive(Clone, Debug)]
pub struct Match {
    /// The real frame's name (its file's stem).
    pub name: String,
    /// The task it was taken in.
    pub task: String,
    /// The pose found with the flat renderer (the geometry does not depend on the surface).
    pub fit: Fit,
    /// Per surface (`Surface::ALL` order): MAE, SSIM, per-row colour error.
    pub scores: Vec<(Surface, f64, f64, Vec<f64>)>,
    /// Local contrast per region (`Region::ALL` order): the real frame's, then each surface's.
    pub contrast: Vec<[Option<f64>; 3]>,
}

/// Compares every frame in `dir` with our renderers at its best pose; `around` gives poses to
/// search near instead of searching every pose (by frame name).
pub fn compare(dir: &Path, around: &[(String, usize, Pose)]) -> Result<Vec<Match>, String> {
    let mut out = Vec::new();
    for r in load(dir)? {
        let task = Task::preset(&r.task).map_err(|e| e.to_string())?;
        let search = match around.iter().find(|a| a.0 == r.name) {
            Some(&(_, l, p)) => Search::Around(l, p),
            None => Search::Full,
        };
        let fit = best_pose(&task, &r.rgb, Surface::Flat, search);
        let mut camera = Camera::new();
        let frames: Vec<(Surface, Vec<u8>)> =
            Surface::ALL.iter().map(|&(_, s)| (s, render(&task, fit.layout, fit.pose, s, &mut camera))).collect();
        let region = regions(&frames[0].1);
        let scores =
            frames.iter().map(|(s, f)| (*s, mae(f, &r.rgb), ssim(f, &r.rgb), row_colour_error(f, &r.rgb))).collect();
        let contrast = Region::ALL
            .iter()
            .map(|&g| {
                [contrast(&r.rgb, &region, g), contrast(&frames[0].1, &region, g), contrast(&frames[1].1, &region, g)]
            })
            .collect();
        out.push(Match { name: r.name, task: r.task, fit, scores, contrast });
    }
    Ok(out)
}

/// The report's table (markdown), as docs/ARENAS.md quotes it.
pub fn table(matches: &[Match]) -> String {
    let mut md = String::from(
        "| frame | task, pose (x, z, heading) | surface | MAE | SSIM | row colour error, mean / max | local contrast floor | fence | wall and objects | sky |\n\
         |---|---|---|---:|---:|---|---|---|---|---|\n",
    );
    let f = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.2}"));
    for m in matches {
        let p = m.fit.pose;
        for (k, (s, mae, ssim, rows)) in m.scores.iter().enumerate() {
            let mean = rows.iter().sum::<f64>() / rows.len() as f64;
            let max = rows.iter().copied().fold(0.0, f64::max);
            let cells: Vec<String> = m.contrast.iter().map(|c| format!("{} / {}", f(c[0]), f(c[k + 1]))).collect();
            let _ = writeln!(
                md,
                "| {} | {} layout {}, ({}, {}, {}) | {} | {:.2} | {:.3} | {:.2} / {:.2} | {} |",
                m.name,
                m.task,
                m.fit.layout,
                p.x,
                p.z,
                p.heading,
                s.name(),
                mae,
                ssim,
                mean,
                max,
                cells.join(" | ")
            );
        }
    }
    md
}

/// Per-row colour errors as CSV: frame, surface, row, error.
pub fn rows_csv(matches: &[Match]) -> String {
    let mut csv = String::from("frame,surface,row,colour_error\n");
    for m in matches {
        for (s, _, _, rows) in &m.scores {
            for (r, e) in rows.iter().enumerate() {
                let _ = writeln!(csv, "{},{},{r},{e:.3}", m.name, s.name());
            }
        }
    }
    csv
}

/// The poses a table found, by frame: what a rerun searches around.
pub fn poses_of(table: &str) -> Vec<(String, usize, Pose)> {
    let mut out: Vec<(String, usize, Pose)> = Vec::new();
    for line in table.lines().skip(2) {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let (Some(name), Some(pose)) = (cells.get(1), cells.get(2)) else { continue };
        if out.iter().any(|o| o.0 == *name) {
            continue;
        }
        let Some((head, tuple)) = pose.split_once(", (") else { continue };
        let layout = head.rsplit(' ').next().and_then(|v| v.parse().ok());
        let v: Vec<f32> = tuple.trim_end_matches(')').split(", ").filter_map(|x| x.parse().ok()).collect();
        if let (Some(layout), [x, z, h]) = (layout, v.as_slice()) {
            out.push((name.to_string(), layout, Pose { x: *x, z: *z, heading: *h }));
        }
    }
    out
}

/// What the report's table shows, written above it.
pub const PREAMBLE: &str = "# Our frames against the real v1 frames\n\n\
Written by `sec-experiment frame-match` from the real Animal-AI v1 observations in \
`tests/reference-frames/` (recovered from the authors' notebooks by `scripts/reference-frames.py`; \
provenance in `provenance.json` there). Each is a first frame of the authors' autoencoder data set at a \
whole-number pose; the pose is the one whose flat frame has the smallest mean absolute error among all \
such poses of the task (x, z in 5..=34, heading 0..=358, every layout), and both surfaces are drawn \
there. MAE: mean absolute error over pixels and channels (8-bit levels). SSIM: mean over 7 x 7 windows \
of the luminance. Row colour error: per row, |our mean colour - the real one|, averaged over channels; \
mean and largest over the 84 rows (`frame-match-rows.csv` has every row). Local contrast: per region, \
the mean |Y - mean Y of the 3 x 3 neighbourhood| over pixels whose neighbourhood lies wholly in the \
region (a texture-energy measure), real / ours; regions from our flat frame at the pose; \"-\": no \
such pixel.\n";
