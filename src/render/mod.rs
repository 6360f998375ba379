//! Rendering: the agent's 84x84 first-person camera and the top-down view for the page.
//! Both write RGBA8 buffers that a canvas `ImageData` takes as they are.

mod camera;
mod surface;
mod topdown;

pub use camera::Camera;
pub use surface::Surface;
pub use topdown::{render_top_down, TopDown, Trail};

use crate::arena::Rgb;

/// The camera image side, pixels (`Learner.asset`).
pub const WIDTH: usize = 84;
/// The camera image height, pixels.
pub const HEIGHT: usize = 84;
/// Pixels per camera image.
pub const PIXELS: usize = WIDTH * HEIGHT;

/// Colours of docs/ARENAS.md section 4 (measured on a real v1 frame, or Unity materials).
pub mod colours {
    use super::Rgb;
    /// The camera background: there is no skybox in v1.
    pub const SKY: Rgb = Rgb(49, 77, 121);
    /// The floor.
    pub const FLOOR: Rgb = Rgb(200, 173, 130);
    /// The arena's fence.
    pub const FENCE: Rgb = Rgb(116, 95, 70);
    /// GoodGoal (emissive).
    pub const GOOD_GOAL: Rgb = Rgb(129, 191, 65);
    /// BadGoal (emissive).
    pub const BAD_GOAL: Rgb = Rgb(159, 25, 25);
    /// DeathZone.
    pub const DEATH_ZONE: Rgb = Rgb(159, 25, 25);
    /// HotZone.
    pub const HOT_ZONE: Rgb = Rgb(255, 144, 44);
    /// GoodGoalMulti's albedo: it is lit, unlike the emissive goals.
    pub const MULTI_GOAL: Rgb = Rgb(163, 114, 7);
    /// The agent's emission, for the top-down view only.
    pub const AGENT: Rgb = Rgb(29, 154, 214);
}

/// Alpha of the transparent material (`Tranparent.mat`).
pub const GLASS_ALPHA: f32 = 0.416;
/// Flat shading: ambient 0.537 plus a white directional light of 0.9 towards `LIGHT`.
pub const AMBIENT: f32 = 0.537;
/// See `AMBIENT`.
pub const DIFFUSE: f32 = 0.9;
/// Direction towards the light (Euler (45, 45, 0) reversed), unit length.
pub const LIGHT: [f32; 3] = [-0.5, core::f32::consts::FRAC_1_SQRT_2, -0.5];

/// The lighting factor for a surface normal (x, y, z).
#[inline]
pub fn shade_factor(n: [f32; 3]) -> f32 {
    AMBIENT + DIFFUSE * (n[0] * LIGHT[0] + n[1] * LIGHT[1] + n[2] * LIGHT[2]).max(0.0)
}

/// Albedo times a lighting factor, rounded and clamped to 8 bits.
#[inline]
pub fn lit(c: Rgb, factor: f32) -> [u8; 3] {
    // `x.min(255.0)` as a compare (the same value for every x, NaN included: it is IEEE minNum,
    // a call per channel in wasm).
    let f = |v: u8| {
        let x = v as f32 * factor + 0.5;
        (if x < 255.0 { x } else { 255.0 }) as u8
    };
    [f(c.0), f(c.1), f(c.2)]
}

/// An 84x84 RGBA8 image, row 0 at the top.
#[derive(Clone, PartialEq, Eq)]
pub struct Frame {
    /// The pixels, 4 bytes each.
    pub rgba: Vec<u8>,
}

impl Default for Frame {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for Frame {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Frame({}x{}, fnv {:016x})", WIDTH, HEIGHT, self.hash())
    }
}

/// v / 255 for every byte v, computed once (the same division, so the same bits): a table
/// lookup instead of a division per channel.
static UNIT: [f32; 256] = {
    let mut t = [0.0; 256];
    let mut v = 0;
    while v < 256 {
        t[v] = v as f32 / 255.0;
        v += 1;
    }
    t
};

impl Frame {
    /// A white image.
    pub fn new() -> Self {
        Frame { rgba: vec![255; PIXELS * 4] }
    }
    /// (r, g, b) at column `c`, row `r`.
    pub fn pixel(&self, c: usize, r: usize) -> [u8; 3] {
        let i = (r * WIDTH + c) * 4;
        [self.rgba[i], self.rgba[i + 1], self.rgba[i + 2]]
    }
    /// RGB in [0, 1], channel-last, as the v1 Python API returns observations.
    pub fn to_rgb_f32(&self, out: &mut [f32]) {
        assert_eq!(out.len(), PIXELS * 3, "output must hold 84x84x3 floats");
        for (o, p) in out.chunks_exact_mut(3).zip(self.rgba.chunks_exact(4)) {
            for k in 0..3 {
                o[k] = UNIT[p[k] as usize];
            }
        }
    }
    /// FNV-1a over the pixels: a compact fingerprint for traces and golden tests.
    pub fn hash(&self) -> u64 {
        fnv1a(&self.rgba)
    }
}

pub use crate::util::fnv1a;
