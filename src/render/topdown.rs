//! The top-down view for the page: footprints in their colours, the agent, its heading and trail.

use super::colours;
use crate::arena::{ConfigError, Footprint, ObjectKind, Rgb, World, AGENT_RADIUS, ARENA_SIZE};
use glam::Vec2;
use std::collections::VecDeque;

/// World margin drawn around the arena, metres (the fences).
const MARGIN: f32 = 1.0;

/// A square RGBA8 image of the arena seen from above, +z up and +x to the right.
#[derive(Clone, Debug)]
pub struct TopDown {
    /// Its side, pixels.
    pub size: usize,
    /// The pixels, 4 bytes each.
    pub rgba: Vec<u8>,
}

impl TopDown {
    /// A white image of side `size`.
    pub fn new(size: usize) -> Self {
        TopDown { size, rgba: vec![255; size * size * 4] }
    }
    /// Draws `w` and the agent's `trail`.
    pub fn render(&mut self, w: &World, trail: &[Vec2]) {
        render_top_down(w, trail, self.size, &mut self.rgba);
    }
}

/// The agent's recent positions (about 30 s of simulated time), drawn as its trail on the
/// top-down view, and the image that view is rendered into: the page's arena and run views.
#[derive(Clone, Debug)]
pub struct Trail {
    points: VecDeque<Vec2>,
    rgba: Vec<u8>,
}

impl Trail {
    /// Positions kept.
    pub const LENGTH: usize = 500;
    /// Image sizes (pixels per side) `render` accepts.
    pub const SIZES: std::ops::RangeInclusive<u32> = 32..=2048;

    /// A trail starting at `at`.
    pub fn new(at: Vec2) -> Self {
        let mut t = Trail { points: VecDeque::with_capacity(Self::LENGTH), rgba: Vec::new() };
        t.restart(at);
        t
    }

    /// A new episode: the trail starts again at `at`.
    pub fn restart(&mut self, at: Vec2) {
        self.points.clear();
        self.points.push_back(at);
    }

    /// The agent is now at `at`; the oldest position falls out of a full trail.
    pub fn push(&mut self, at: Vec2) {
        if self.points.len() == Self::LENGTH {
            self.points.pop_front();
        }
        self.points.push_back(at);
    }

    /// The top-down view of `w` with the trail, `size` x `size` RGBA.
    pub fn render(&mut self, w: &World, size: u32) -> Result<&[u8], ConfigError> {
        if !Self::SIZES.contains(&size) {
            let (lo, hi) = (Self::SIZES.start(), Self::SIZES.end());
            return Err(ConfigError::new("size", format!("{size} is out of range {lo}..={hi}")));
        }
        let n = size as usize;
        self.rgba.resize(n * n * 4, 0);
        render_top_down(w, self.points.make_contiguous(), n, &mut self.rgba);
        Ok(&self.rgba)
    }
}

/// Pixel <-> world mapping for a square canvas showing [-1, 41] in x and z.
struct View {
    size: usize,
    scale: f32,
}

impl View {
    fn world(&self, px: usize, py: usize) -> Vec2 {
        Vec2::new((px as f32 + 0.5) / self.scale - MARGIN, ARENA_SIZE + MARGIN - (py as f32 + 0.5) / self.scale)
    }
    /// Pixel bounds (inclusive start, exclusive end) of a world rectangle.
    fn bounds(&self, lo: Vec2, hi: Vec2) -> (usize, usize, usize, usize) {
        let clamp = |v: f32| v.clamp(0.0, self.size as f32) as usize;
        let x0 = clamp(((lo.x + MARGIN) * self.scale).floor());
        let x1 = clamp(((hi.x + MARGIN) * self.scale).ceil());
        let y0 = clamp(((ARENA_SIZE + MARGIN - hi.y) * self.scale).floor());
        let y1 = clamp(((ARENA_SIZE + MARGIN - lo.y) * self.scale).ceil());
        (x0, x1, y0, y1)
    }
}

/// Draws `w` into `out` (size x size RGBA8). `trail` holds the agent's recent positions, oldest
/// first; it is drawn fading in.
pub fn render_top_down(w: &World, trail: &[Vec2], size: usize, out: &mut [u8]) {
    assert_eq!(out.len(), size * size * 4, "top-down buffer must be size*size*4 bytes");
    let v = View { size, scale: size as f32 / (ARENA_SIZE + 2.0 * MARGIN) };
    let fence = colours::FENCE;
    for (i, px) in out.chunks_exact_mut(4).enumerate() {
        let p = v.world(i % size, i / size);
        let inside = (0.0..=ARENA_SIZE).contains(&p.x) && (0.0..=ARENA_SIZE).contains(&p.y);
        let c = if inside { colours::FLOOR } else { fence };
        px.copy_from_slice(&[c.0, c.1, c.2, 255]);
    }
    for z in &w.zones {
        let c = if z.kind == ObjectKind::DeathZone { colours::DEATH_ZONE } else { colours::HOT_ZONE };
        fill_rect(&v, out, &z.foot, c, 1.0);
    }
    for t in &w.tunnels {
        // The roof at half opacity over the hollow, the legs solid.
        fill_rect(&v, out, &t.foot, t.colour, if t.transparent { 0.2 } else { 0.45 });
        for leg in t.legs() {
            fill_rect(&v, out, &leg, t.colour, if t.transparent { 0.5 } else { 1.0 });
        }
    }
    for r in &w.ramps {
        fill_rect(&v, out, &r.foot, r.colour, 0.8);
    }
    for b in w.boxes() {
        if b.transparent {
            fill_rect(&v, out, &b.foot, Rgb(220, 235, 255), 0.6);
        } else {
            fill_rect(&v, out, &b.foot, b.colour, 1.0);
        }
    }
    for g in w.goals.iter().filter(|g| !g.collected) {
        let c = match g.kind {
            ObjectKind::GoodGoal => colours::GOOD_GOAL,
            ObjectKind::BadGoal => colours::BAD_GOAL,
            _ => colours::MULTI_GOAL,
        };
        // A goal still in the air is drawn lighter.
        let alpha = if g.resting || g.centre.y <= g.radius + 0.02 { 1.0 } else { 0.5 };
        fill_disc(&v, out, Vec2::new(g.centre.x, g.centre.z), g.radius, c, alpha);
    }
    let n = trail.len().max(1) as f32;
    for (k, p) in trail.iter().enumerate() {
        fill_disc(&v, out, *p, 0.18, colours::AGENT, 0.15 + 0.6 * (k as f32 + 1.0) / n);
    }
    let a = &w.agent;
    fill_disc(&v, out, a.pos, AGENT_RADIUS, colours::AGENT, 1.0);
    // Heading tick: a thin white bar from the centre to 1.2 m ahead.
    let f = a.forward();
    let tick = Footprint { centre: a.pos + f * 0.6, half: Vec2::new(0.12, 0.6), cos: f.y, sin: f.x };
    fill_rect(&v, out, &tick, Rgb(255, 255, 255), 1.0);
}

fn paint(out: &mut [u8], i: usize, c: Rgb, alpha: f32) {
    let px = &mut out[i * 4..i * 4 + 3];
    for (k, v) in [c.0, c.1, c.2].into_iter().enumerate() {
        px[k] = (px[k] as f32 * (1.0 - alpha) + v as f32 * alpha + 0.5) as u8;
    }
}

fn fill_rect(v: &View, out: &mut [u8], f: &Footprint, c: Rgb, alpha: f32) {
    let r = f.half.length();
    let (x0, x1, y0, y1) = v.bounds(f.centre - Vec2::splat(r), f.centre + Vec2::splat(r));
    for py in y0..y1 {
        for px in x0..x1 {
            if f.contains(v.world(px, py), 0.0) {
                paint(out, py * v.size + px, c, alpha);
            }
        }
    }
}

fn fill_disc(v: &View, out: &mut [u8], centre: Vec2, r: f32, c: Rgb, alpha: f32) {
    let (x0, x1, y0, y1) = v.bounds(centre - Vec2::splat(r), centre + Vec2::splat(r));
    for py in y0..y1 {
        for px in x0..x1 {
            if (v.world(px, py) - centre).length_squared() <= r * r {
                paint(out, py * v.size + px, c, alpha);
            }
        }
    }
}
