//! How the floor and the fences are drawn (docs/ARENAS.md section 4): `Flat`, one measured colour
//! each, or `Textured`, v1's tiled floor and planked fences made procedurally from numbers measured
//! on the real v1 frames. Every texel is a pure function of the hit point (and, for filtering, of
//! the pixel's footprint), with only +, -, *, / and floor, so every target draws the same bits.

/// The floor and fence drawing: a perception option (`RunConfig.surface`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Surface {
    /// One colour for the floor and one for the fences (the project's renderer until issue 51).
    #[default]
    Flat,
    /// Tiled floor with v1's distance gradient, planked fences with posts and a rail.
    Textured,
}

impl Surface {
    /// Every surface with its name.
    pub const ALL: [(&'static str, Surface); 2] = [("flat", Surface::Flat), ("textured", Surface::Textured)];

    /// A surface by name, or an error listing the names (the caller names the parameter).
    pub fn from_name(name: &str) -> Result<Surface, String> {
        Self::ALL.iter().find(|(n, _)| *n == name).map(|&(_, s)| s).ok_or_else(|| {
            format!("'{}' is not one of {}", crate::util::shown(name), Self::ALL.map(|(n, _)| n).join(", "))
        })
    }

    /// Whether it is `Flat` (the default, which a configuration's JSON leaves out).
    pub fn is_flat(&self) -> bool {
        *self == Surface::Flat
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Surface::Flat => "flat",
            Surface::Textured => "textured",
        }
    }
}

// The textured surfaces' numbers (docs/ARENAS.md section 4, "Textured surfaces": what was
// measured on the real frames and what was chosen).

/// Floor colour far from the eye (at the horizon) and close to it (under the camera), 8-bit RGB.
pub const FLOOR_FAR: [f32; 3] = [236.0, 203.0, 152.0];
/// See `FLOOR_FAR`.
pub const FLOOR_NEAR: [f32; 3] = [172.0, 148.0, 111.0];
/// How fast the floor's colour goes from far to near with the ray's downward slope:
/// far + (near - far) (1 - exp(-k slope)).
pub const FLOOR_GRADIENT_K: f32 = 5.0;
/// Slab size along x and along z (m): slabs are laid in rows along x, each row offset by half a
/// slab from the one before (running bond).
pub const SLAB: [f32; 2] = [2.0, 1.0];
/// Seam width (m) and the share of light a seam keeps.
pub const FLOOR_SEAM: (f32, f32) = (0.04, 0.7);
/// Each slab's brightness varies by up to this share either way.
pub const SLAB_TINT: f32 = 0.06;
/// The fence's albedo on its brightest sides.
pub const FENCE_ALBEDO: [f32; 3] = [117.0, 95.0, 70.0];
/// The fence's brightness seen from inside the arena, by the side's inward normal: -x (the
/// fence at x = 40), +x (x = 0), -z (z = 40), +z (z = 0).
pub const FENCE_SIDE: [f32; 4] = [1.0, 0.45, 1.0, 1.0];
/// Plank width (m), seam width (m) and the share of light a plank seam keeps.
pub const PLANK: (f32, f32, f32) = (0.8, 0.04, 0.55);
/// Each plank's brightness varies by up to this share either way.
pub const PLANK_TINT: f32 = 0.1;
/// The rail: from `RAIL.0` to `RAIL.1` m up, brightness `RAIL.2`; a lit top edge `RAIL_EDGE.0` m
/// tall at `RAIL_EDGE.1`; its shadow below, `RAIL_SHADOW.0` m at `RAIL_SHADOW.1`.
pub const RAIL: (f32, f32, f32) = (1.0, 1.25, 0.95);
/// See `RAIL`.
pub const RAIL_EDGE: (f32, f32) = (0.04, 1.15);
/// See `RAIL`.
pub const RAIL_SHADOW: (f32, f32) = (0.08, 0.55);
/// Posts: wide boards reaching above the fence, centred every `POSTS.0` m from `POSTS.1` along
/// each fence (its x or z), `POSTS.2` wide, `POSTS.3` m tall, brightness `POSTS.4`.
pub const POSTS: (f32, f32, f32, f32, f32) = (16.667, 6.667, 2.4, 8.7, 0.93);

/// The share of [u - f/2, u + f/2] covered by seams of width `w` centred on the multiples of
/// `period`: the pixel's footprint box-filters the seams (`f` > 0), so distant ones fade to their
/// average instead of aliasing.
#[inline]
pub(crate) fn seam_cover(u: f32, f: f32, period: f32, w: f32) -> f32 {
    // Seam length in [0, x): whole periods, then the part of the last seam (shifted so seams
    // start at the multiples).
    let acc = |x: f32| {
        let x = x + 0.5 * w;
        let k = (x / period).floor();
        k * w + (x - k * period).min(w)
    };
    ((acc(u + 0.5 * f) - acc(u - 0.5 * f)) / f).clamp(0.0, 1.0)
}

/// The share of [y - f/2, y + f/2] inside [lo, hi].
#[inline]
pub(crate) fn band_cover(y: f32, f: f32, lo: f32, hi: f32) -> f32 {
    let a = (y - 0.5 * f).max(lo);
    let b = (y + 0.5 * f).min(hi);
    ((b - a) / f).clamp(0.0, 1.0)
}

/// A number in [-1, 1] for integer cell (i, j) and a salt: a fixed integer hash, so the same on
/// every target.
#[inline]
pub(crate) fn cell_noise(i: i32, j: i32, salt: u32) -> f32 {
    let mut h =
        (i as u32).wrapping_mul(0x9E37_79B1) ^ (j as u32).wrapping_mul(0x85EB_CA77) ^ salt.wrapping_mul(0xC2B2_AE3D);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^= h >> 12;
    h = h.wrapping_mul(0x297A_2D39);
    h ^= h >> 15;
    (h >> 8) as f32 / 8_388_607.5 - 1.0
}

/// The floor's base colour for a ray going down with `slope` (the row's), before the slabs.
pub(crate) fn floor_gradient(slope: f32) -> [f32; 3] {
    let t = 1.0 - libm::expf(-FLOOR_GRADIENT_K * slope.abs());
    std::array::from_fn(|k| FLOOR_FAR[k] + (FLOOR_NEAR[k] - FLOOR_FAR[k]) * t)
}

/// The textured floor at (x, z), seen through a pixel whose footprint spans `fx` by `fz` metres.
#[inline]
pub(crate) fn floor_texel(x: f32, z: f32, fx: f32, fz: f32, base: &[f32; 3]) -> [u8; 3] {
    let row = (z / SLAB[1]).floor();
    let shift = if (row as i32) & 1 == 1 { 0.5 * SLAB[0] } else { 0.0 };
    let col = ((x - shift) / SLAB[0]).floor();
    let seam_z = seam_cover(z, fz, SLAB[1], FLOOR_SEAM.0);
    let seam_x = seam_cover(x - shift, fx, SLAB[0], FLOOR_SEAM.0);
    let seam = 1.0 - (1.0 - seam_x) * (1.0 - seam_z);
    // A slab's own tint shows only while the footprint is smaller than a slab.
    let seen = (1.0 - (fx / SLAB[0]).max(fz / SLAB[1])).clamp(0.0, 1.0);
    let tint = 1.0 + SLAB_TINT * cell_noise(col as i32, row as i32, 1) * seen;
    let f = tint * (1.0 - (1.0 - FLOOR_SEAM.1) * seam);
    base.map(|v| (v * f + 0.5).min(255.0) as u8)
}

/// Which fence a ray leaves the arena through, by its inward normal (the index of `FENCE_SIDE`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FenceSide {
    /// The fence at x = 40.
    East = 0,
    /// x = 0.
    West = 1,
    /// z = 40.
    North = 2,
    /// z = 0.
    South = 3,
}

/// Whether `u` (a position along a fence) lies on a post.
#[inline]
pub(crate) fn on_post(u: f32) -> bool {
    let k = ((u - POSTS.1) / POSTS.0).round();
    (u - POSTS.1 - k * POSTS.0).abs() <= 0.5 * POSTS.2
}

/// The fence's top at `u` along it: a post's or the panels'.
#[inline]
pub(crate) fn fence_top(u: f32, panel: f32) -> f32 {
    if on_post(u) {
        POSTS.3
    } else {
        panel
    }
}

/// One column of the textured fence: what depends on the position `u` along it (the side, the
/// plank, its seams, a post), seen through pixels whose footprint spans `fu` along it; the rows
/// then add only the rail (`texel`).
pub(crate) struct FenceColumn {
    /// The brightness before the rail.
    f: f32,
    post: bool,
    /// The colour of a row the rail's bands do not reach.
    plain: [u8; 3],
}

impl FenceColumn {
    #[inline]
    pub(crate) fn new(side: FenceSide, u: f32, fu: f32) -> Self {
        let post = on_post(u);
        let plank = (u / PLANK.0).floor();
        let seen = (1.0 - fu / PLANK.0).clamp(0.0, 1.0);
        let mut f = FENCE_SIDE[side as usize] * (1.0 + PLANK_TINT * cell_noise(plank as i32, side as i32, 2) * seen);
        f *= 1.0 - (1.0 - PLANK.2) * seam_cover(u, fu, PLANK.0, PLANK.1);
        if post {
            f *= POSTS.4;
        }
        FenceColumn { f, post, plain: fence_colour(f) }
    }

    /// The texel `y` up, seen through a pixel whose footprint spans `fy` up. Outside the rail's
    /// bands their factor is exactly 1, so those rows take the column's colour.
    #[inline]
    pub(crate) fn texel(&self, y: f32, fy: f32) -> [u8; 3] {
        if self.post || y + 0.5 * fy <= RAIL.0 - RAIL_SHADOW.0 || y - 0.5 * fy >= RAIL.1 + RAIL_EDGE.0 {
            return self.plain;
        }
        let rail = band_cover(y, fy, RAIL.0, RAIL.1);
        let edge = band_cover(y, fy, RAIL.1, RAIL.1 + RAIL_EDGE.0);
        let shadow = band_cover(y, fy, RAIL.0 - RAIL_SHADOW.0, RAIL.0);
        fence_colour(
            self.f * (1.0 + (RAIL.2 - 1.0) * rail + (RAIL_EDGE.1 - 1.0) * edge + (RAIL_SHADOW.1 - 1.0) * shadow),
        )
    }
}

#[inline]
fn fence_colour(f: f32) -> [u8; 3] {
    FENCE_ALBEDO.map(|v| (v * f + 0.5).min(255.0) as u8)
}
