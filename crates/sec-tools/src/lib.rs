#![warn(missing_docs)]
//! Shared helpers of the native tools.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

/// Writes an RGBA8 image as a PNG.
pub fn write_png(path: &Path, width: usize, height: usize, rgba: &[u8]) -> Result<(), String> {
    let file = File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut enc = png::Encoder::new(BufWriter::new(file), width as u32, height as u32);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Best);
    enc.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
    let mut w = enc.write_header().map_err(|e| format!("{}: {e}", path.display()))?;
    w.write_image_data(rgba).map_err(|e| format!("{}: {e}", path.display()))
}

/// Nearest-neighbour upscaling, so an 84x84 frame can be looked at.
pub fn upscale(rgba: &[u8], width: usize, height: usize, k: usize) -> Vec<u8> {
    let mut out = vec![0u8; width * height * k * k * 4];
    for y in 0..height * k {
        for x in 0..width * k {
            let s = ((y / k) * width + x / k) * 4;
            let d = (y * width * k + x) * 4;
            out[d..d + 4].copy_from_slice(&rgba[s..s + 4]);
        }
    }
    out
}

pub mod arenas;
pub mod authors;
pub mod frame_match;
// The runner lives in its own light crate (the Python package's Ray driver uses it too).
pub use sec_runner as runner;
pub use sec_runner::manifest;
pub mod matching;
pub mod merge;
pub mod orderings;
pub mod plot;
pub mod quote;
pub mod reference;
pub mod report;
pub mod stats;
pub mod surfaces;
pub mod warmup;
