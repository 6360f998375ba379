//! The agent's first-person camera: one ray per pixel, 60 degree field of view, the eye at the
//! agent sphere's centre (0.5 above the floor, or above the box it stands on), no pitch or roll
//! (docs/ARENAS.md section 4).
//!
//! Because the camera never pitches, every pixel of a column shares the horizontal part of its
//! ray. The column's 2-D intersections with the vertical walls and fences are computed once, and
//! each row then only checks its height: still exactly one ray per pixel, at a fraction of the
//! cost. Spheres and arches, which are not vertical extrusions, are intersected per pixel.
//! Each frame first finds, per opaque box, the columns whose rays can meet it (`reach_of`): the
//! others skip its test, which would have missed.

use super::surface::{fence_top, floor_gradient, floor_texel, FenceColumn, FenceSide};
use super::{colours, lit, shade_factor, Frame, Surface, GLASS_ALPHA, HEIGHT, PIXELS, WIDTH};
use crate::arena::{BoxObj, Footprint, ObjectKind, Ramp, Tunnel, World, AGENT_RADIUS, ARENA_SIZE};
use glam::{Vec2, Vec3};

/// tan(30 degrees): half the field of view, horizontally and vertically (the image is square).
const TAN_HALF_FOV: f32 = 0.577_350_26;
/// The eye is at the agent sphere's centre: this high above what the agent stands on.
const EYE: f32 = AGENT_RADIUS;
/// The fence model spans 0 to 7.1; drawn 7 tall (docs/ARENAS.md section 1).
const FENCE_HEIGHT: f32 = 7.0;
/// Hits closer than this are ignored (Unity's near plane is 0.01).
const NEAR: f32 = 1e-3;
/// The angle between neighbouring pixels' rays, as a slope (what a pixel's footprint scales by).
const PIXEL_SLOPE: f32 = 2.0 * TAN_HALF_FOV / WIDTH as f32;

/// Renders 84x84 views. Holds the per-pixel depth buffer so rendering never allocates.
#[derive(Clone, Debug)]
pub struct Camera {
    /// Horizontal offset of each column's ray along the camera's right axis.
    col_offset: [f32; WIDTH],
    /// Vertical slope of each row's ray (positive above the horizon).
    row_slope: [f32; HEIGHT],
    depth: Vec<f32>,
    /// What every frame starts from: the sky above the horizon and the bare floor below, as
    /// RGBA and as depth (the same in every frame from the same eye height, so copied rather than
    /// recomputed), and the eye height its depths are for.
    background: (Vec<u8>, Vec<f32>),
    background_eye: f32,
    /// Per opaque box of the frame being drawn, the column offsets whose rays can meet it.
    reach: Vec<(f32, f32)>,
    /// How the floor and fences are drawn.
    surface: Surface,
    /// The textured floor's base colour per row below the horizon (`surface::floor_gradient`).
    floor_base: Vec<[f32; 3]>,
}

impl Default for Camera {
    fn default() -> Self {
        Self::new()
    }
}

/// One column's ray, horizontally: from `eye` along `h` (whose forward component is 1, so the
/// ray parameter is the view depth); `right` is the camera's right axis (a column step moves the
/// ray along it); `y` is the eye's height.
#[derive(Clone, Copy)]
struct Column {
    c: usize,
    eye: Vec2,
    h: Vec2,
    right: Vec2,
    y: f32,
}

/// An entering crossing of a surface: ray parameter and world normal.
#[derive(Clone, Copy, Debug)]
struct Hit {
    s: f32,
    n: Vec3,
}

impl Camera {
    /// A camera with empty buffers.
    pub fn new() -> Self {
        let n = WIDTH as f32;
        let row_slope = std::array::from_fn(|r| (1.0 - (2 * r + 1) as f32 / n) * TAN_HALF_FOV);
        Camera {
            col_offset: std::array::from_fn(|c| ((2 * c + 1) as f32 / n - 1.0) * TAN_HALF_FOV),
            row_slope,
            depth: vec![f32::INFINITY; PIXELS],
            background: background(&row_slope, EYE),
            background_eye: EYE,
            reach: Vec::new(),
            surface: Surface::Flat,
            floor_base: row_slope[HEIGHT / 2..].iter().map(|&s| floor_gradient(s)).collect(),
        }
    }

    /// A camera that draws the floor and fences as `surface`.
    pub fn with_surface(surface: Surface) -> Self {
        let mut c = Self::new();
        c.set_surface(surface);
        c
    }

    /// Draws the floor and fences as `surface` from the next frame on.
    pub fn set_surface(&mut self, surface: Surface) {
        self.surface = surface;
    }

    /// Renders what the agent sees into `frame`.
    pub fn render(&mut self, w: &World, frame: &mut Frame) {
        let f = w.agent.forward();
        let right = Vec2::new(f.y, -f.x);
        let y = w.agent.y + EYE;
        if y != self.background_eye {
            self.background = background(&self.row_slope, y);
            self.background_eye = y;
        }
        self.depth.copy_from_slice(&self.background.1);
        frame.rgba.copy_from_slice(&self.background.0);
        let px = &mut frame.rgba;
        let mut reach = std::mem::take(&mut self.reach);
        reach.clear();
        reach.extend(w.boxes().filter(|b| !b.transparent).map(|b| reach_of(&b.foot, w.agent.pos, f, right)));
        for c in 0..WIDTH {
            let offset = self.col_offset[c];
            let col = Column { c, eye: w.agent.pos, h: f + right * offset, right, y };
            self.floor_and_fence(w, col, px);
            for (b, &(lo, hi)) in w.boxes().filter(|b| !b.transparent).zip(&reach) {
                if (lo..=hi).contains(&offset) {
                    self.wall(b, col, px, None);
                }
            }
            for r in &w.ramps {
                self.ramp(r, col, px);
            }
            for g in w.goals.iter().filter(|g| !g.collected) {
                self.sphere(g.kind, g.centre, g.radius, col, px);
            }
            for t in w.tunnels.iter().filter(|t| !t.transparent) {
                self.tunnel(t, col, px, false);
            }
            if self.surface == Surface::Textured {
                self.floor_texture(w, col, px);
            }
        }
        self.reach = reach;
        // Transparent surfaces last, farthest first, blended over what is behind them.
        let mut glass: Vec<(f32, usize, bool)> = Vec::new();
        glass.extend(
            w.walls
                .iter()
                .enumerate()
                .filter(|(_, b)| b.transparent)
                .map(|(i, b)| ((b.foot.centre - w.agent.pos).length(), i, true)),
        );
        glass.extend(
            w.tunnels
                .iter()
                .enumerate()
                .filter(|(_, t)| t.transparent)
                .map(|(i, t)| ((t.foot.centre - w.agent.pos).length(), i, false)),
        );
        glass.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (_, i, is_wall) in glass {
            for c in 0..WIDTH {
                let col = Column { c, eye: w.agent.pos, h: f + right * self.col_offset[c], right, y };
                if is_wall {
                    self.wall(&w.walls[i], col, px, Some(()));
                } else {
                    self.tunnel(&w.tunnels[i], col, px, true);
                }
            }
        }
    }

    /// Rows whose slope lies in [lo, hi], widened by one row each side; callers test exactly.
    #[inline]
    fn rows(&self, lo: f32, hi: f32) -> std::ops::Range<usize> {
        let n = HEIGHT as f32;
        let row_of = |slope: f32| ((1.0 - slope / TAN_HALF_FOV) * n - 1.0) / 2.0;
        let r0 = (row_of(hi).floor() - 1.0).max(0.0);
        let r1 = (row_of(lo).ceil() + 2.0).min(n);
        if r0 >= r1 {
            return 0..0;
        }
        r0 as usize..r1 as usize
    }

    /// The textured floor's texel at each row's hit point that still shows bare floor once the
    /// column's opaque surfaces are drawn (the others would be overwritten, so they are not
    /// computed), box-filtered over the pixel's footprint: a column step moves the hit along
    /// `right`, a row step along the ray.
    fn floor_texture(&self, w: &World, col: Column, px: &mut [u8]) {
        let Column { c, eye, h, right, y } = col;
        let (spans, n) = zone_spans(w, eye, h);
        for r in HEIGHT / 2..HEIGHT {
            let i = r * WIDTH + c;
            let s = self.depth[i];
            if s != self.background.1[i] || spans[..n].iter().any(|(s0, s1, _)| (*s0..=*s1).contains(&s)) {
                continue;
            }
            let p = eye + h * s;
            let fx = (right.x.abs() + h.x.abs() * s / y) * s * PIXEL_SLOPE;
            let fz = (right.y.abs() + h.y.abs() * s / y) * s * PIXEL_SLOPE;
            put(px, i, floor_texel(p.x, p.y, fx, fz, &self.floor_base[r - HEIGHT / 2]));
        }
    }

    fn floor_and_fence(&mut self, w: &World, col: Column, px: &mut [u8]) {
        let Column { c, eye, h, right, y: eye_y } = col;
        let textured = self.surface == Surface::Textured;
        let (spans, n) = zone_spans(w, eye, h);
        // The floor's depth and colour are the background's; a zone's colour replaces it.
        if n > 0 {
            for r in HEIGHT / 2..HEIGHT {
                let i = r * WIDTH + c;
                let s = self.depth[i];
                if let Some(z) = spans[..n].iter().find(|(s0, s1, _)| (*s0..=*s1).contains(&s)) {
                    put(px, i, [z.2 .0, z.2 .1, z.2 .2]);
                }
            }
        }
        // The eye is always inside the fence square: the ray leaves it at the nearest exit.
        let exit = |e: f32, d: f32| {
            if d > 0.0 {
                (ARENA_SIZE - e) / d
            } else if d < 0.0 {
                -e / d
            } else {
                f32::INFINITY
            }
        };
        let (sx, sz) = (exit(eye.x, h.x), exit(eye.y, h.y));
        let s = sx.min(sz);
        // Textured: which fence, where along it (u) and how far a column step moves the hit along
        // it, for the planks, posts and rail; flat: one colour up to the panels' top.
        let planks = textured.then(|| {
            let (side, u, along, across, r_along, r_across) = if sx <= sz {
                (if h.x > 0.0 { FenceSide::East } else { FenceSide::West }, eye.y + h.y * s, h.y, h.x, right.y, right.x)
            } else {
                (
                    if h.y > 0.0 { FenceSide::North } else { FenceSide::South },
                    eye.x + h.x * s,
                    h.x,
                    h.y,
                    right.x,
                    right.y,
                )
            };
            let fu = (s * PIXEL_SLOPE * (r_along * across - along * r_across) / across).abs();
            (fence_top(u, FENCE_HEIGHT), FenceColumn::new(side, u, fu))
        });
        let top = planks.as_ref().map_or(FENCE_HEIGHT, |p| p.0);
        let (flat, fy) = ([colours::FENCE.0, colours::FENCE.1, colours::FENCE.2], s * PIXEL_SLOPE);
        for r in self.rows(-eye_y / s, (top - eye_y) / s) {
            let y = eye_y + self.row_slope[r] * s;
            let i = r * WIDTH + c;
            if (0.0..=top).contains(&y) && s < self.depth[i] {
                self.depth[i] = s;
                put(px, i, planks.as_ref().map_or(flat, |p| p.1.texel(y, fy)));
            }
        }
    }

    /// A box: its entering side face, its top when it is below the eye and its bottom when it
    /// is above it. `glass` blends instead of overwriting.
    fn wall(&mut self, b: &BoxObj, col: Column, px: &mut [u8], glass: Option<()>) {
        let Some((s0, s1, n)) = slab(b.foot.to_local(col.eye), local_dir(&b.foot, col.h), b.foot.half) else {
            return;
        };
        let (eye, base, h) = (col.y, b.base, b.top());
        if s0 <= NEAR {
            // The eye is over (or under) the box: only its top (or bottom) shows.
            if h < eye || base > eye {
                self.cap(b, col, s1, px, glass);
            }
            return;
        }
        let n = b.foot.to_world_dir(n);
        // Each face's lighting and colour, once per column (the same for all its pixels).
        let shaded = |n: [f32; 3]| {
            let factor = shade_factor(n);
            (factor, lit(b.colour, factor))
        };
        let (side, top, bottom) = (shaded([n.x, 0.0, n.y]), shaded([0.0, 1.0, 0.0]), shaded([0.0, -1.0, 0.0]));
        let lo = if base > eye { (base - eye) / s1 } else { (base - eye) / s0 };
        let hi = if h < eye { (h - eye) / s1 } else { (h - eye) / s0 };
        for r in self.rows(lo, hi) {
            let slope = self.row_slope[r];
            let y = eye + slope * s0;
            let (s, (factor, rgb)) = if (base..=h).contains(&y) {
                (s0, side)
            } else if h < eye && slope < 0.0 {
                let st = (h - eye) / slope;
                if st < s0 || st > s1 {
                    continue;
                }
                (st, top)
            } else if base > eye && slope > 0.0 {
                let sb = (base - eye) / slope;
                if sb < s0 || sb > s1 {
                    continue;
                }
                (sb, bottom)
            } else {
                continue;
            };
            let i = r * WIDTH + col.c;
            if s < self.depth[i] {
                self.box_pixel(px, i, s, rgb, factor, glass);
            }
        }
    }

    /// One pixel of a box's face at depth `s`, nearer than what is there: opaque, it takes the
    /// face's colour and depth; glass blends over what is behind.
    #[inline]
    fn box_pixel(&mut self, px: &mut [u8], i: usize, s: f32, rgb: [u8; 3], factor: f32, glass: Option<()>) {
        if glass.is_some() {
            blend(px, i, factor);
        } else {
            self.depth[i] = s;
            put(px, i, rgb);
        }
    }

    /// The top of a box the eye is above, or the bottom of one it is under, from the eye out to
    /// where the column's ray leaves the box's footprint (`s1`).
    fn cap(&mut self, b: &BoxObj, col: Column, s1: f32, px: &mut [u8], glass: Option<()>) {
        let (face, normal) = if b.top() < col.y { (b.top(), 1.0) } else { (b.base, -1.0) };
        let factor = shade_factor([0.0, normal, 0.0]);
        let rgb = lit(b.colour, factor);
        let edge = (face - col.y) / s1;
        let rows = if normal > 0.0 { self.rows(f32::NEG_INFINITY, edge) } else { self.rows(edge, f32::INFINITY) };
        for r in rows {
            let slope = self.row_slope[r];
            if slope * normal >= 0.0 {
                continue;
            }
            let s = (face - col.y) / slope;
            let i = r * WIDTH + col.c;
            if s > NEAR && s <= s1 && s < self.depth[i] {
                self.box_pixel(px, i, s, rgb, factor, glass);
            }
        }
    }

    /// A ramp: the wedge's face a pixel's ray enters first, found by clipping the ray against the
    /// wedge's five half-spaces (it is convex), lit by that face's normal.
    fn ramp(&mut self, r: &Ramp, col: Column, px: &mut [u8]) {
        let o = r.foot.to_local(col.eye);
        let d = local_dir(&r.foot, col.h);
        let Some((s0, s1, _)) = slab(o, d, r.foot.half) else {
            return;
        };
        let (hx, hz, h) = (r.foot.half.x, r.foot.half.y, r.height);
        // Local x, height above the base, local z: n . p <= c inside.
        let planes: [([f32; 3], f32); 6] = [
            ([0.0, -1.0, 0.0], 0.0),
            ([0.0, 0.0, -1.0], hz),
            ([0.0, 0.0, 1.0], hz),
            ([1.0, 0.0, 0.0], hx),
            ([-1.0, 0.0, 0.0], hx),
            ([0.0, 2.0 * hz, h], h * hz),
        ];
        let eye = col.y - r.base;
        let near = s0.max(NEAR);
        let lo = -eye / if eye < 0.0 { s1 } else { near };
        let hi = (h - eye) / if h < eye { s1 } else { near };
        for row in self.rows(lo, hi) {
            let d3 = [d.x, self.row_slope[row], d.y];
            let o3 = [o.x, eye, o.y];
            let (mut enter, mut exit, mut normal) = (f32::NEG_INFINITY, f32::INFINITY, [0.0f32; 3]);
            for (n, c) in &planes {
                let along = n[0] * d3[0] + n[1] * d3[1] + n[2] * d3[2];
                let room = c - (n[0] * o3[0] + n[1] * o3[1] + n[2] * o3[2]);
                if along == 0.0 {
                    if room < 0.0 {
                        enter = f32::INFINITY;
                    }
                } else if along < 0.0 {
                    if room / along > enter {
                        (enter, normal) = (room / along, *n);
                    }
                } else {
                    exit = exit.min(room / along);
                }
            }
            let i = row * WIDTH + col.c;
            if enter > exit || enter <= NEAR || enter >= self.depth[i] {
                continue;
            }
            self.depth[i] = enter;
            let n = r.foot.to_world_dir(Vec2::new(normal[0], normal[2]));
            let n = Vec3::new(n.x, normal[1], n.y).normalize();
            put(px, i, lit(r.colour, shade_factor(n.to_array())));
        }
    }

    /// A goal sphere: emissive (flat) except GoodGoalMulti, which is lit.
    fn sphere(&mut self, kind: ObjectKind, centre: Vec3, radius: f32, col: Column, px: &mut [u8]) {
        let Column { c, eye, h, y: eye_y, .. } = col;
        let w2 = Vec2::new(centre.x, centre.z) - eye;
        let hh = h.length_squared();
        let along = w2.dot(h);
        if along <= 0.0 || w2.length_squared() - along * along / hh > radius * radius {
            return;
        }
        let wy = centre.y - eye_y;
        let cc = w2.length_squared() + wy * wy - radius * radius;
        let flat = match kind {
            ObjectKind::GoodGoal => Some(colours::GOOD_GOAL),
            ObjectKind::BadGoal => Some(colours::BAD_GOAL),
            _ => None,
        };
        for r in 0..HEIGHT {
            let slope = self.row_slope[r];
            let a = hh + slope * slope;
            let b = along + slope * wy;
            let disc = b * b - a * cc;
            if disc < 0.0 {
                continue;
            }
            let s = (b - disc.sqrt()) / a;
            let i = r * WIDTH + c;
            if s <= NEAR || s >= self.depth[i] {
                continue;
            }
            self.depth[i] = s;
            let rgb = match flat {
                Some(k) => [k.0, k.1, k.2],
                None => {
                    let p = Vec3::new(eye.x + h.x * s, eye_y + slope * s, eye.y + h.y * s);
                    let n = (p - centre) / radius;
                    lit(colours::MULTI_GOAL, shade_factor(n.to_array()))
                }
            };
            put(px, i, rgb);
        }
    }

    /// An arch (CylinderTunnel). Opaque: the nearest surface. Transparent: every front face,
    /// farthest first, blended.
    fn tunnel(&mut self, t: &Tunnel, col: Column, px: &mut [u8], glass: bool) {
        let o = t.foot.to_local(col.eye);
        let d = local_dir(&t.foot, col.h);
        let Some((s0, _, _)) = slab(o, d, Vec2::new(t.outer_w, t.half_len)) else {
            return;
        };
        let rows = if s0 > NEAR { self.rows(-col.y / s0, (t.outer_h - col.y) / s0) } else { 0..HEIGHT };
        let s_min = s0.max(0.0);
        for r in rows {
            let i = r * WIDTH + col.c;
            if s_min >= self.depth[i] {
                continue;
            }
            let (o3, d3) = ([o.x, col.y, o.y], [d.x, self.row_slope[r], d.y]);
            if glass {
                let mut hits = [Hit { s: 0.0, n: Vec3::ZERO }; 4];
                let k = arch_hits(t, o3, d3, &mut hits);
                for hit in hits[..k].iter().rev().filter(|h| h.s < self.depth[i]) {
                    blend(px, i, shade_factor(hit.n.to_array()));
                }
            } else if let Some((s, nl)) = arch_nearest(t, o3, d3) {
                if s < self.depth[i] {
                    self.depth[i] = s;
                    put(px, i, lit(t.colour, shade_factor(arch_normal(t, nl).to_array())));
                }
            }
        }
    }
}

/// Where a column's ray crosses each floor zone (at most 8), with the zone's colour, so floor
/// pixels test one interval each.
fn zone_spans(w: &World, eye: Vec2, h: Vec2) -> ([(f32, f32, crate::arena::Rgb); 8], usize) {
    let mut spans = [(0.0f32, 0.0f32, colours::FLOOR); 8];
    let mut n = 0;
    for z in &w.zones {
        if let Some((s0, s1, _)) = slab(z.foot.to_local(eye), local_dir(&z.foot, h), z.foot.half) {
            if n == spans.len() {
                break;
            }
            let colour = if z.kind == ObjectKind::DeathZone { colours::DEATH_ZONE } else { colours::HOT_ZONE };
            spans[n] = (s0, s1, colour);
            n += 1;
        }
    }
    (spans, n)
}

/// `Camera::background`: above the horizon the sky at infinite depth, below it the floor at the
/// depth where each row's ray from an eye `eye` high meets it.
fn background(row_slope: &[f32; HEIGHT], eye: f32) -> (Vec<u8>, Vec<f32>) {
    let (sky, floor) = (colours::SKY, colours::FLOOR);
    let mut rgba = Vec::with_capacity(4 * PIXELS);
    let mut depth = Vec::with_capacity(PIXELS);
    for (r, &slope) in row_slope.iter().enumerate() {
        let (colour, s) = if r < HEIGHT / 2 { (sky, f32::INFINITY) } else { (floor, -eye / slope) };
        for _ in 0..WIDTH {
            rgba.extend_from_slice(&[colour.0, colour.1, colour.2, 255]);
            depth.push(s);
        }
    }
    (rgba, depth)
}

#[inline]
fn put(px: &mut [u8], i: usize, rgb: [u8; 3]) {
    px[i * 4..i * 4 + 3].copy_from_slice(&rgb);
}

/// The transparent material over what is behind it: 0.584 behind + 0.416 white, lit.
#[inline]
fn blend(px: &mut [u8], i: usize, factor: f32) {
    let glass = (255.0 * factor).min(255.0);
    for k in 0..3 {
        let v = &mut px[i * 4 + k];
        *v = ((1.0 - GLASS_ALPHA) * *v as f32 + GLASS_ALPHA * glass + 0.5).min(255.0) as u8;
    }
}

/// The column offsets (along the camera's right axis, per unit of depth) whose rays can meet a
/// box on the floor: those between its corners' when all four are in front of the eye (the box
/// is convex), widened far beyond rounding; none when all are behind it; every offset otherwise.
/// A column outside misses the box, so skipping its slab test draws the same pixels.
fn reach_of(foot: &Footprint, eye: Vec2, forward: Vec2, right: Vec2) -> (f32, f32) {
    let corners = foot.corners().map(|p| ((p - eye).dot(right), (p - eye).dot(forward)));
    if corners.iter().all(|&(_, z)| z < 0.0) {
        return (f32::INFINITY, f32::NEG_INFINITY);
    }
    if corners.iter().any(|&(_, z)| z < 0.01) {
        return (f32::NEG_INFINITY, f32::INFINITY);
    }
    let (lo, hi) =
        corners.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &(x, z)| (lo.min(x / z), hi.max(x / z)));
    (lo - 1e-3 - 1e-4 * lo.abs(), hi + 1e-3 + 1e-4 * hi.abs())
}

fn local_dir(foot: &Footprint, h: Vec2) -> Vec2 {
    Vec2::new(h.dot(foot.axis_x()), h.dot(foot.axis_z()))
}

/// 2-D slab test of a ray (local origin `o`, direction `d`) against the rectangle `|x| <= half`.
/// Returns entry and exit parameters and the entering face's outward normal in local axes.
fn slab(o: Vec2, d: Vec2, half: Vec2) -> Option<(f32, f32, Vec2)> {
    let mut t0 = f32::NEG_INFINITY;
    let mut t1 = f32::INFINITY;
    let mut n = Vec2::ZERO;
    for axis in 0..2 {
        let (oa, da, ha) = (o[axis], d[axis], half[axis]);
        if da == 0.0 {
            if oa.abs() > ha {
                return None;
            }
            continue;
        }
        let inv = 1.0 / da;
        let (mut ta, mut tb) = ((-ha - oa) * inv, (ha - oa) * inv);
        if ta > tb {
            std::mem::swap(&mut ta, &mut tb);
        }
        if ta > t0 {
            t0 = ta;
            n = Vec2::ZERO;
            n[axis] = -da.signum();
        }
        t1 = t1.min(tb);
    }
    if t1 < t0 || t1 <= 0.0 {
        return None;
    }
    Some((t0, t1, n))
}

/// The surfaces of the arch solid (outer elliptic shell minus the inner one, y >= 0,
/// |z| <= half length) that a ray enters, as (parameter, local normal, unnormalised), in no
/// particular order; `f` receives each.
#[inline]
fn arch_crossings(t: &Tunnel, o: [f32; 3], d: [f32; 3], mut f: impl FnMut(f32, [f32; 3])) {
    let valid = |s: f32| {
        let y = o[1] + d[1] * s;
        let z = o[2] + d[2] * s;
        s > NEAR && y >= 0.0 && z.abs() <= t.half_len
    };
    // Outer surface: entering the ellipse enters the solid.
    if let Some((s1, _)) = ellipse_roots(o, d, t.outer_ia(), t.outer_ib()) {
        if valid(s1) {
            let (x, y) = (o[0] + d[0] * s1, o[1] + d[1] * s1);
            f(s1, [x * t.outer_ia(), y * t.outer_ib(), 0.0]);
        }
    }
    // Inner surface: leaving the hollow enters the solid; it faces the axis.
    if let Some((_, s2)) = ellipse_roots(o, d, t.inner_ia(), t.inner_ib()) {
        if valid(s2) {
            let (x, y) = (o[0] + d[0] * s2, o[1] + d[1] * s2);
            f(s2, [-x * t.inner_ia(), -y * t.inner_ib(), 0.0]);
        }
    }
    // End faces: the annulus at z = +-half length, entered when moving towards the middle.
    for zc in [t.half_len, -t.half_len] {
        if d[2] == 0.0 || d[2] * zc > 0.0 {
            continue;
        }
        let s = (zc - o[2]) / d[2];
        let (x, y) = (o[0] + d[0] * s, o[1] + d[1] * s);
        let e = |a: f32, b: f32| (x / a) * (x / a) + (y / b) * (y / b);
        if s > NEAR && y >= 0.0 && e(t.outer_w, t.outer_h) <= 1.0 && e(t.inner_w, t.inner_h) >= 1.0 {
            f(s, [0.0, 0.0, zc.signum()]);
        }
    }
}

/// The first surface an opaque arch shows along a ray.
fn arch_nearest(t: &Tunnel, o: [f32; 3], d: [f32; 3]) -> Option<(f32, [f32; 3])> {
    // Fast path: a valid entry into the outer shell is always the nearest crossing, because the
    // ray is outside the outer ellipse (hence outside the solid) until then.
    if let Some((s1, _)) = ellipse_roots(o, d, t.outer_ia(), t.outer_ib()) {
        let (x, y, z) = (o[0] + d[0] * s1, o[1] + d[1] * s1, o[2] + d[2] * s1);
        if s1 > NEAR && y >= 0.0 && z.abs() <= t.half_len {
            return Some((s1, [x * t.outer_ia(), y * t.outer_ib(), 0.0]));
        }
    } else {
        // Missing the outer ellipse misses the whole arch.
        return None;
    }
    let mut best: Option<(f32, [f32; 3])> = None;
    arch_crossings(t, o, d, |s, n| {
        if best.is_none_or(|(b, _)| s < b) {
            best = Some((s, n));
        }
    });
    best
}

/// Every front face of a transparent arch along a ray, nearest first; returns how many.
fn arch_hits(t: &Tunnel, o: [f32; 3], d: [f32; 3], out: &mut [Hit; 4]) -> usize {
    let mut k = 0;
    arch_crossings(t, o, d, |s, n| {
        out[k] = Hit { s, n: arch_normal(t, n) };
        k += 1;
    });
    out[..k].sort_by(|a, b| a.s.total_cmp(&b.s));
    k
}

/// A local arch normal in world axes, unit length: local x is (cos, -sin) and local z is
/// (sin, cos) in world (x, z).
fn arch_normal(t: &Tunnel, nl: [f32; 3]) -> Vec3 {
    let (cos, sin) = (t.foot.cos, t.foot.sin);
    Vec3::new(nl[0] * cos + nl[2] * sin, nl[1], -nl[0] * sin + nl[2] * cos).normalize()
}

/// Both parameters where a ray meets the elliptic cylinder (x/a)^2 + (y/b)^2 = 1.
/// `ia` and `ib` are 1/a^2 and 1/b^2.
#[inline]
fn ellipse_roots(o: [f32; 3], d: [f32; 3], ia: f32, ib: f32) -> Option<(f32, f32)> {
    let qa = d[0] * d[0] * ia + d[1] * d[1] * ib;
    if qa == 0.0 {
        return None;
    }
    let qb = o[0] * d[0] * ia + o[1] * d[1] * ib;
    let qc = o[0] * o[0] * ia + o[1] * o[1] * ib - 1.0;
    let disc = qb * qb - qa * qc;
    if disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    Some(((-qb - sq) / qa, (-qb + sq) / qa))
}
