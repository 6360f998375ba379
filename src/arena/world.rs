//! A layout instantiated: concrete objects, the agent, and the collision footprints.

use super::{AgentSpec, Layout, ObjectKind, ObjectSpec, Rgb, ARENA_SIZE, SIZE_ADJUST};
use glam::{Vec2, Vec3};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// The agent sphere's radius; its centre is this high above the floor.
pub const AGENT_RADIUS: f32 = 0.5;

/// Unity's tunnel mesh: inner radius / outer radius / 2 = 0.818 / 1.04 / 2 (docs/ARENAS.md section 5).
pub const TUNNEL_INNER: f32 = 0.3933;
/// Random spawns retry this many times before the object is left out (as Animal-AI does).
const SPAWN_TRIES: u32 = 100;
/// Footprints touching within this margin do not count as overlapping (adjacent T-maze walls).
const OVERLAP_EPS: f32 = 1e-3;

/// An oriented rectangle on the floor: centre, half extents along local x and z, rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Centre on the floor (x, z).
    pub centre: Vec2,
    /// Half extents along local x and z.
    pub half: Vec2,
    /// cos and sin of the rotation; local +x is (cos, -sin) and local +z is (sin, cos) in (x, z).
    pub cos: f32,
    /// See `cos`.
    pub sin: f32,
}

impl Footprint {
    /// A rectangle at `centre` with half extents `half`, rotated `degrees` clockwise seen from above.
    pub fn new(centre: Vec2, half: Vec2, degrees: f32) -> Self {
        let r = degrees.to_radians();
        let (sin, cos) = (libm::sinf(r), libm::cosf(r));
        // Snap the exact quarter turns, so axis-aligned layouts stay exactly axis aligned.
        let snap = |v: f32| {
            if v.abs() < 1e-6 {
                0.0
            } else if (v.abs() - 1.0).abs() < 1e-6 {
                v.signum()
            } else {
                v
            }
        };
        Footprint { centre, half, cos: snap(cos), sin: snap(sin) }
    }
    /// Local +x in world (x, z).
    pub fn axis_x(&self) -> Vec2 {
        Vec2::new(self.cos, -self.sin)
    }
    /// Local +z in world (x, z).
    pub fn axis_z(&self) -> Vec2 {
        Vec2::new(self.sin, self.cos)
    }
    /// World point to local (x, z).
    pub fn to_local(&self, p: Vec2) -> Vec2 {
        let d = p - self.centre;
        Vec2::new(d.dot(self.axis_x()), d.dot(self.axis_z()))
    }
    /// A local direction in world (x, z).
    pub fn to_world_dir(&self, l: Vec2) -> Vec2 {
        self.axis_x() * l.x + self.axis_z() * l.y
    }
    /// Whether `p` lies inside, grown by `margin` on every side.
    pub fn contains(&self, p: Vec2, margin: f32) -> bool {
        let l = self.to_local(p);
        l.x.abs() <= self.half.x + margin && l.y.abs() <= self.half.y + margin
    }
    /// The rectangle's four corners in world (x, z).
    pub fn corners(&self) -> [Vec2; 4] {
        let (ax, az) = (self.axis_x() * self.half.x, self.axis_z() * self.half.y);
        [self.centre + ax + az, self.centre + ax - az, self.centre - ax - az, self.centre - ax + az]
    }
    /// Separating-axis test between two rectangles.
    pub fn overlaps(&self, other: &Footprint) -> bool {
        let axes = [self.axis_x(), self.axis_z(), other.axis_x(), other.axis_z()];
        let (ca, cb) = (self.corners(), other.corners());
        axes.iter().all(|&ax| {
            let proj = |c: &[Vec2; 4]| {
                c.iter().fold((f32::MAX, f32::MIN), |(lo, hi), p| (lo.min(p.dot(ax)), hi.max(p.dot(ax))))
            };
            let ((a0, a1), (b0, b1)) = (proj(&ca), proj(&cb));
            a0 < b1 - OVERLAP_EPS && b0 < a1 - OVERLAP_EPS
        })
    }
    /// Whether a disc overlaps the rectangle.
    pub fn overlaps_disc(&self, c: Vec2, r: f32) -> bool {
        let l = self.to_local(c);
        let q = l.clamp(-self.half, self.half);
        (l - q).length_squared() < (r - OVERLAP_EPS).max(0.0).powi(2)
    }
}

/// A wall: a box on the floor or on the top of another box.
#[derive(Clone, Debug, PartialEq)]
pub struct BoxObj {
    /// Where it stands.
    pub foot: Footprint,
    /// The height of its bottom: 0 on the floor, else the top of the box it rests on.
    pub base: f32,
    /// Its height.
    pub height: f32,
    /// Its colour.
    pub colour: Rgb,
    /// Drawn see-through.
    pub transparent: bool,
}

/// An object the agent pushes (`Cardbox1`, `Cardbox2`, `UObject`, `LObject`, `LObject2`): one
/// rigid body made of upright boxes of the same height, where the body now is (it moves with it:
/// `physics::RigidBodies`).
#[derive(Clone, Debug, PartialEq)]
pub struct Pushable {
    /// Its boxes at their current pose: one for a cardboard box, two or three for an L or a U.
    pub parts: Vec<BoxObj>,
    /// Each box's centre in the body's own frame (local x, z), in the order of `parts`.
    pub offsets: Vec<Vec2>,
    /// The body's origin (the prefab's pivot) and turn now; its half extents are those of the
    /// box v1's spawn check tests.
    pub pose: Footprint,
    /// Its mass, kg.
    pub mass: f32,
    /// Its friction (averaged with what it touches).
    pub friction: f32,
}

impl Pushable {
    /// Its boxes' footprints and heights now, as a goal rolling into it meets them.
    pub fn colliders(&self) -> impl Iterator<Item = Collider> + '_ {
        self.parts.iter().map(|b| Collider { foot: b.foot, bottom: b.base, top: b.top(), wall: None, ramp: None })
    }

    /// The height of its bottom.
    pub fn base(&self) -> f32 {
        self.parts[0].base
    }

    /// Its height.
    pub fn height(&self) -> f32 {
        self.parts[0].height
    }

    /// Moves it to `pose` with its bottom at `base`: each box follows the body.
    pub fn move_to(&mut self, pose: Footprint, base: f32) {
        for (part, &offset) in self.parts.iter_mut().zip(&self.offsets) {
            part.foot.centre = pose.centre + pose.to_world_dir(offset);
            (part.foot.cos, part.foot.sin) = (pose.cos, pose.sin);
            part.base = base;
        }
        self.pose = pose;
    }
}

/// The pushable boxes' colour: v1 draws them with a cardboard texture, which this renderer
/// stands for by one brown.
pub const CARDBOARD: Rgb = Rgb(170, 130, 85);
/// The U and L objects' colour: v1's wooden texture, as one darker brown.
pub const WOOD: Rgb = Rgb(125, 85, 50);

/// A CylinderTunnel: the upper half of an elliptic tube lying along local z (an arch).
#[derive(Clone, Debug, PartialEq)]
pub struct Tunnel {
    /// Where it stands (local z along the tube).
    pub foot: Footprint,
    /// Outer half-width (local x), outer height, inner half-width, inner height, half-length.
    pub outer_w: f32,
    /// See `outer_w`.
    pub outer_h: f32,
    /// See `outer_w`.
    pub inner_w: f32,
    /// See `outer_w`.
    pub inner_h: f32,
    /// See `outer_w`.
    pub half_len: f32,
    /// Its colour.
    pub colour: Rgb,
    /// Drawn see-through.
    pub transparent: bool,
    /// 1/outer_w^2, 1/outer_h^2, 1/inner_w^2, 1/inner_h^2, for the renderer's per-pixel tests.
    pub inv_sq: [f32; 4],
}

impl Tunnel {
    /// 1/outer_w^2.
    pub fn outer_ia(&self) -> f32 {
        self.inv_sq[0]
    }
    /// 1/outer_h^2.
    pub fn outer_ib(&self) -> f32 {
        self.inv_sq[1]
    }
    /// 1/inner_w^2.
    pub fn inner_ia(&self) -> f32 {
        self.inv_sq[2]
    }
    /// 1/inner_h^2.
    pub fn inner_ib(&self) -> f32 {
        self.inv_sq[3]
    }

    /// The two legs, which are what the agent collides with (docs/ARENAS.md section 5).
    pub fn legs(&self) -> [Footprint; 2] {
        let w = (self.outer_w - self.inner_w) / 2.0;
        let off = (self.outer_w + self.inner_w) / 2.0;
        let ax = self.foot.axis_x();
        let leg = |side: f32| Footprint {
            centre: self.foot.centre + ax * (side * off),
            half: Vec2::new(w, self.half_len),
            ..self.foot
        };
        [leg(1.0), leg(-1.0)]
    }
}

impl BoxObj {
    /// The height of its top.
    pub fn top(&self) -> f32 {
        self.base + self.height
    }
}

/// A ramp: a wedge on its footprint, `height` tall at its local -z edge and 0 at its +z edge
/// (v1's `Ramp` mesh; docs/ARENAS.md section 5).
#[derive(Clone, Debug, PartialEq)]
pub struct Ramp {
    /// Where it stands.
    pub foot: Footprint,
    /// The height of its bottom.
    pub base: f32,
    /// Its height at the high edge.
    pub height: f32,
    /// Its colour.
    pub colour: Rgb,
}

impl Ramp {
    /// The height of its sloped top above `local` (a point in its footprint's axes), clamped to
    /// the footprint's z extent.
    pub fn surface_local(&self, local: Vec2) -> f32 {
        let hz = self.foot.half.y;
        self.base + self.height * (hz - local.y.clamp(-hz, hz)) / (2.0 * hz)
    }

    /// The height of its top at `p`, if `p` is over it.
    pub fn surface(&self, p: Vec2) -> Option<f32> {
        self.foot.contains(p, 0.0).then(|| self.surface_local(self.foot.to_local(p)))
    }

    /// The highest its slope reaches over `f` (where they overlap): a linear height over two
    /// convex shapes peaks at a corner of one inside the other, or where their edges cross; the
    /// corners of `f` moved into the footprint stand for the crossings.
    pub fn top_over(&self, f: &Footprint) -> f32 {
        let own = self.foot.corners().into_iter().filter(|p| f.contains(*p, 0.0)).map(|p| self.foot.to_local(p));
        let theirs = f.corners().map(|p| self.foot.to_local(p).clamp(-self.foot.half, self.foot.half));
        own.chain(theirs).map(|l| self.surface_local(l)).fold(f32::NEG_INFINITY, f32::max)
    }

    /// Downhill, horizontally (a unit vector: its local +z), and the slope's rise per metre.
    pub fn downhill(&self) -> (Vec2, f32) {
        (self.foot.axis_z(), self.height / (2.0 * self.foot.half.y))
    }
}

/// Something solid the agent collides with: a footprint and the heights it spans.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Collider {
    /// Where it stands.
    pub foot: Footprint,
    /// The height of its bottom.
    pub bottom: f32,
    /// The height of its top.
    pub top: f32,
    /// The wall it belongs to (an index into `World::walls`), if it is one.
    pub wall: Option<usize>,
    /// The ramp it bounds (an index into `World::ramps`), if it is one: the agent collides with
    /// a ramp's slope, not its box (`physics`).
    pub ramp: Option<usize>,
}

impl Collider {
    /// Whether it spans some of the heights strictly between `lo` and `hi` (touching does not
    /// count: a box under the agent or above it is not in its way).
    pub fn spans(&self, (lo, hi): (f32, f32)) -> bool {
        self.bottom < hi - OVERLAP_EPS && self.top > lo + OVERLAP_EPS
    }
}

/// What a body at `p` whose bottom is at `y` rests on: the highest top under its centre, of a
/// box (`boxes`: the walls, and the pushable boxes where they are now) or a ramp's slope, that is at most `climb` above `y` (a body's centre is over a box only
/// if the box let it pass, so one a little higher is a step it is climbing); or the floor.
pub fn support<'a>(
    boxes: impl IntoIterator<Item = &'a BoxObj>,
    ramps: &[Ramp],
    p: Vec2,
    y: f32,
    climb: f32,
) -> Support {
    let wall = boxes
        .into_iter()
        .filter(|b| b.top() <= y + climb.max(OVERLAP_EPS) && b.foot.contains(p, 0.0))
        .fold(0.0f32, |best, b| best.max(b.top()));
    let mut out = Support { height: wall, ramp: None };
    for (i, r) in ramps.iter().enumerate() {
        if let Some(h) = r.surface(p).filter(|&h| h <= y + climb && h > out.height) {
            out = Support { height: h, ramp: Some(i) };
        }
    }
    out
}

/// What a body rests on (`support`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Support {
    /// The height of the surface under it.
    pub height: f32,
    /// The ramp whose slope that is, if it is one.
    pub ramp: Option<usize>,
}

/// A goal sphere; it falls under gravity until it rests on the floor or a box.
#[derive(Clone, Debug, PartialEq)]
pub struct Goal {
    /// Good, bad or multi (a bouncing goal's unbounced kind: it pays and looks the same).
    pub kind: ObjectKind,
    /// Centre (x, y, z).
    pub centre: Vec3,
    /// Its radius.
    pub radius: f32,
    /// Vertical speed while falling.
    pub vy: f32,
    /// A bouncing goal's horizontal velocity (x, z); zero for the others, which never move
    /// sideways.
    pub vel: Vec2,
    /// A bouncing goal's spin as the velocity of its lowest point's rolling (angular velocity
    /// times radius, in x and z): it rolls without slipping when this equals `vel`.
    pub spin: Vec2,
    /// Launched as it starts (v1's `BallGoalBounce`): bounces off everything with 0.8, rolls.
    pub bouncing: bool,
    /// The direction a bouncing goal is launched along in its first physics frame (its
    /// rotation's forward), until then.
    pub launch: Option<Vec2>,
    /// Whether it has come to rest.
    pub resting: bool,
    /// Reward on touch: +size*0.999 for good goals, minus that for BadGoal.
    pub reward: f64,
    /// GoodGoalMulti are removed once collected.
    pub collected: bool,
}

/// A DeathZone or HotZone: a flat rectangle on the floor.
#[derive(Clone, Debug, PartialEq)]
pub struct Zone {
    /// Death or hot zone.
    pub kind: ObjectKind,
    /// Where it lies.
    pub foot: Footprint,
}

/// The agent's physical state.
#[derive(Clone, Debug, PartialEq)]
pub struct Agent {
    /// Centre on the floor plane (x, z).
    pub pos: Vec2,
    /// The height of the sphere's bottom: 0 on the floor (its centre is 0.5 above it).
    pub y: f32,
    /// World-frame velocity (x, z), m/s.
    pub vel: Vec2,
    /// Vertical velocity while falling, m/s.
    pub vy: f32,
    /// Heading in degrees, clockwise from +z seen from above, in [0, 360).
    pub heading: f32,
    /// Standing on the floor or a box (false in the first physics frame after spawn and while
    /// falling): only then does a move push it.
    pub grounded: bool,
}

impl Agent {
    /// Unit heading (sin, cos) in (x, z).
    pub fn forward(&self) -> Vec2 {
        let r = self.heading.to_radians();
        Vec2::new(libm::sinf(r), libm::cosf(r))
    }
}

/// Everything in the arena for one episode.
#[derive(Clone, Debug, PartialEq)]
pub struct World {
    /// Wall blocks.
    pub walls: Vec<BoxObj>,
    /// Ramps.
    pub ramps: Vec<Ramp>,
    /// Arches.
    pub tunnels: Vec<Tunnel>,
    /// Goal spheres.
    pub goals: Vec<Goal>,
    /// Floor zones.
    pub zones: Vec<Zone>,
    /// What the agent collides with: walls and tunnel legs (fences are the bounds).
    pub colliders: Vec<Collider>,
    /// Boxes the agent pushes (empty in every preset task); their rigid bodies are the env's
    /// (`push`).
    pub pushed: Vec<Pushable>,
    /// The agent's body.
    pub agent: Agent,
}

impl World {
    /// The bits of everything the camera reads that can move: the agent's position and heading,
    /// each goal's centre and whether it is collected, each pushable box's pose (walls, arches and
    /// zones never move). Equal keys render equal frames.
    pub fn view_key(&self, key: &mut Vec<u32>) {
        key.clear();
        key.extend([self.agent.pos.x, self.agent.pos.y, self.agent.y, self.agent.heading].map(f32::to_bits));
        for g in &self.goals {
            key.extend([g.centre.x, g.centre.y, g.centre.z].map(f32::to_bits));
            key.push(g.collected as u32);
        }
        for p in &self.pushed {
            let f = &p.pose;
            key.extend([f.centre.x, f.centre.y, f.cos, f.sin, p.base()].map(f32::to_bits));
        }
    }

    /// Every opaque box the camera draws: the walls, then the pushable objects' boxes.
    pub fn boxes(&self) -> impl Iterator<Item = &BoxObj> {
        self.walls.iter().chain(self.pushed.iter().flat_map(|p| &p.parts))
    }

    /// Spawns a layout. Objects spawn in file order after a user-placed agent; an object whose
    /// footprint overlaps something already spawned is left out (Animal-AI's `IsSpotFree`), and a
    /// random agent spawns last on a free spot.
    pub fn spawn(layout: &Layout, rng: &mut ChaCha8Rng) -> World {
        Self::spawn_counting(layout, rng).0
    }

    /// `spawn`, and the indices (in `layout.objects`) of the objects it could not place: a fixed
    /// one whose spot is taken, or a random one with no free spot in its tries. Animal-AI leaves
    /// those out, and so does a reset; the env refuses a layout that does so at construction.
    fn spawn_counting(layout: &Layout, rng: &mut ChaCha8Rng) -> (World, Vec<usize>) {
        let mut w = World {
            walls: Vec::new(),
            ramps: Vec::new(),
            tunnels: Vec::new(),
            goals: Vec::new(),
            zones: Vec::new(),
            colliders: Vec::new(),
            pushed: Vec::new(),
            agent: Agent {
                pos: Vec2::ZERO,
                y: layout.agent.y,
                vel: Vec2::ZERO,
                vy: 0.0,
                heading: 0.0,
                grounded: false,
            },
        };
        let fixed_agent = matches!(layout.agent.position, [Some(_), Some(_)]);
        let mut agent_disc = None;
        if fixed_agent {
            let pos = Vec2::new(layout.agent.position[0].unwrap(), layout.agent.position[1].unwrap());
            agent_disc = Some((pos, layout.agent.y));
            w.agent.pos = pos;
        }
        let mut unplaced = Vec::new();
        for (k, spec) in layout.objects.iter().enumerate() {
            let mut placed = false;
            for _ in 0..SPAWN_TRIES {
                let random = spec.position.iter().any(Option::is_none) || spec.rotation.is_none();
                placed = w.try_place(spec, agent_disc, rng);
                if placed || !random {
                    break;
                }
            }
            if !placed {
                unplaced.push(k);
            }
        }
        w.settle();
        w.agent.heading = wrap_degrees(match layout.agent.rotation {
            Some(r) => r,
            None => rng.gen_range(0.0f32..360.0),
        });
        if !fixed_agent {
            w.agent.pos = w.random_agent_spot(&layout.agent, rng).0;
        }
        (w, unplaced)
    }

    /// Lets every wall the file places above the floor fall onto what is under it, lowest first,
    /// then every ramp onto the walls: v1's walls and ramps are rigid bodies (mass 100, not
    /// kinematic), so one left in the air falls at once. Here they land before the first frame,
    /// on a box whose footprint overlaps their own, however little (v1 would tip one resting on an
    /// edge).
    fn settle(&mut self) {
        let mut order: Vec<usize> = (0..self.walls.len()).filter(|&i| self.walls[i].base > 0.0).collect();
        order.sort_by(|&a, &b| self.walls[a].base.total_cmp(&self.walls[b].base));
        for i in order {
            let b = &self.walls[i];
            let rest = self
                .walls
                .iter()
                .enumerate()
                .filter(|&(j, o)| j != i && o.top() <= b.base + OVERLAP_EPS && o.foot.overlaps(&b.foot))
                .fold(0.0f32, |best, (_, o)| best.max(o.top()));
            self.walls[i].base = rest;
        }
        // Ramps (rigid bodies too) onto the settled walls.
        for r in self.ramps.iter_mut().filter(|r| r.base > 0.0) {
            r.base = self
                .walls
                .iter()
                .filter(|o| o.top() <= r.base + OVERLAP_EPS && o.foot.overlaps(&r.foot))
                .fold(0.0f32, |best, o| best.max(o.top()));
        }
        for c in &mut self.colliders {
            if let Some(i) = c.wall {
                (c.bottom, c.top) = (self.walls[i].base, self.walls[i].top());
            }
            if let Some(i) = c.ramp {
                (c.bottom, c.top) = (self.ramps[i].base, self.ramps[i].base + self.ramps[i].height);
            }
        }
    }

    /// Places one object if its spot is free; returns whether it was placed. `agent` is a placed
    /// agent's centre and the height of its bottom.
    fn try_place(&mut self, spec: &ObjectSpec, agent: Option<(Vec2, f32)>, rng: &mut ChaCha8Rng) -> bool {
        let (lo, hi) = spec.kind.size_range();
        let raw: [f32; 3] = std::array::from_fn(|i| {
            spec.size[i].unwrap_or_else(|| if lo[i] < hi[i] { rng.gen_range(lo[i]..hi[i]) } else { lo[i] })
        });
        let size = raw.map(|s| s * SIZE_ADJUST);
        let rotation = spec.rotation.unwrap_or_else(|| rng.gen_range(0.0f32..360.0));
        let mut coord = |c: Option<f32>, half: f32| {
            c.unwrap_or_else(|| rng.gen_range(half.min(20.0)..(ARENA_SIZE - half).max(20.0)))
        };
        let kind = spec.kind;
        let footprint_half = Vec2::new(size[0] / 2.0, size[2] / 2.0);
        let x = coord(spec.position[0], footprint_half.max_element());
        let z = coord(spec.position[2], footprint_half.max_element());
        let y = spec.position[1].unwrap_or(0.0);
        let centre = Vec2::new(x, z);
        let colour = spec.colour.unwrap_or_else(|| match kind {
            ObjectKind::Wall | ObjectKind::Ramp => {
                Rgb(rng.gen_range(0..=255u32) as u8, rng.gen_range(0..=255u32) as u8, rng.gen_range(0..=255u32) as u8)
            }
            _ => Rgb(255, 255, 255),
        });
        // v1's `IsSpotFree`: nothing solid in the object's box (a 3-D overlap at the place the
        // file gives, before anything falls), goals included (they are colliders too), so a random
        // goal drawn onto another is drawn again. `rise` is the heights the object spans.
        let free = |solid: &[Footprint], rise: (f32, f32)| {
            let agent_in = |s: &Footprint| {
                agent.is_some_and(|(a, ay)| {
                    ay < rise.1 - OVERLAP_EPS
                        && ay + 2.0 * AGENT_RADIUS > rise.0 + OVERLAP_EPS
                        && s.overlaps_disc(a, AGENT_RADIUS)
                })
            };
            // A ramp is a wedge (v1 checks its convex mesh): only its slope's height counts.
            let wedge_below =
                |c: &Collider, s: &Footprint| c.ramp.is_some_and(|i| self.ramps[i].top_over(s) <= rise.0 + OVERLAP_EPS);
            let colliders = || self.colliders.iter().copied().chain(self.pushed.iter().flat_map(Pushable::colliders));
            !solid.iter().any(|s| colliders().any(|c| c.spans(rise) && c.foot.overlaps(s) && !wedge_below(&c, s)))
                && !solid.iter().any(agent_in)
                && !solid.iter().any(|s| {
                    self.goals.iter().any(|g| {
                        g.centre.y - g.radius < rise.1
                            && g.centre.y + g.radius > rise.0
                            && s.overlaps_disc(Vec2::new(g.centre.x, g.centre.z), g.radius)
                    })
                })
        };
        match kind {
            ObjectKind::Wall | ObjectKind::WallTransparent => {
                let foot = Footprint::new(centre, footprint_half, rotation);
                if !free(&[foot], (y, y + size[1])) {
                    return false;
                }
                let transparent = kind == ObjectKind::WallTransparent;
                let colour = if transparent { Rgb(255, 255, 255) } else { colour };
                let wall = Some(self.walls.len());
                self.walls.push(BoxObj { foot, base: y, height: size[1], colour, transparent });
                self.colliders.push(Collider { foot, bottom: y, top: y + size[1], wall, ramp: None });
            }
            ObjectKind::Ramp => {
                let foot = Footprint::new(centre, footprint_half, rotation);
                if !free(&[foot], (y, y + size[1])) {
                    return false;
                }
                let ramp = Some(self.ramps.len());
                self.ramps.push(Ramp { foot, base: y, height: size[1], colour });
                self.colliders.push(Collider { foot, bottom: y, top: y + size[1], wall: None, ramp });
            }
            ObjectKind::CylinderTunnel | ObjectKind::CylinderTunnelTransparent => {
                let (outer_w, outer_h) = (size[0] / 2.0, size[1] / 2.0);
                let (inner_w, inner_h) = (TUNNEL_INNER * size[0], TUNNEL_INNER * size[1]);
                let t = Tunnel {
                    foot: Footprint::new(centre, footprint_half, rotation),
                    outer_w,
                    outer_h,
                    inner_w,
                    inner_h,
                    inv_sq: [outer_w, outer_h, inner_w, inner_h].map(|v| 1.0 / (v * v)),
                    half_len: size[2] / 2.0,
                    colour: if kind == ObjectKind::CylinderTunnel && spec.colour.is_none() {
                        Rgb(51, 51, 51)
                    } else {
                        colour
                    },
                    transparent: kind == ObjectKind::CylinderTunnelTransparent,
                };
                // Arches stand on the floor (no file of the Olympics corpus raises one).
                let legs = t.legs();
                if !free(&legs, (0.0, size[1] / 2.0)) {
                    return false;
                }
                self.colliders.extend(legs.map(|foot| Collider {
                    foot,
                    bottom: 0.0,
                    top: size[1] / 2.0,
                    wall: None,
                    ramp: None,
                }));
                self.tunnels.push(t);
            }
            k if k.mass().is_some() => {
                let (boxes, ratio, turn) = k.prefab_boxes();
                let scale = Vec2::new(size[0] * ratio[0], size[2] * ratio[1]);
                let offsets: Vec<Vec2> = boxes.iter().map(|b| Vec2::new(b[0], b[1]) * scale).collect();
                let halves: Vec<Vec2> = boxes.iter().map(|b| Vec2::new(b[2], b[3]) * scale / 2.0).collect();
                // v1 tests a box of the object's bounds centred on its pivot (`GetBoundsWithChildren`,
                // then `OverlapBox` at the pivot), not the boxes themselves.
                let (lo, hi) = offsets
                    .iter()
                    .zip(&halves)
                    .fold((Vec2::MAX, Vec2::MIN), |(lo, hi), (&o, &h)| (lo.min(o - h), hi.max(o + h)));
                let pose = Footprint::new(centre, (hi - lo) / 2.0, rotation + turn);
                if !free(&[pose], (y, y + size[1])) {
                    return false;
                }
                let colour = if k == ObjectKind::Cardbox1 || k == ObjectKind::Cardbox2 { CARDBOARD } else { WOOD };
                let parts = halves
                    .iter()
                    .map(|&half| {
                        let foot = Footprint { half, ..pose };
                        BoxObj { foot, base: y, height: size[1], colour, transparent: false }
                    })
                    .collect();
                let mut p = Pushable { parts, offsets, pose, mass: k.mass().unwrap_or(1.0), friction: k.friction() };
                p.move_to(pose, y);
                self.pushed.push(p);
            }
            k if k.is_goal() => {
                // A sphere's diameter is size.x; y and z are ignored (docs/ARENAS.md section 5).
                let radius = size[0] / 2.0;
                let foot = Footprint::new(centre, Vec2::splat(radius), 0.0);
                let cy = y + radius + 0.01;
                if !free(&[foot], (cy - radius, cy + radius)) {
                    return false;
                }
                let sign = if kind.unbounced() == ObjectKind::BadGoal { -1.0 } else { 1.0 };
                // v1 launches a bouncing goal along its rotation as it starts (`BallGoalBounce`).
                let r = rotation.to_radians();
                let forward = Vec2::new(libm::sinf(r), libm::cosf(r));
                // In f64, so that a size-3 goal pays 2.997 to the last digit.
                self.goals.push(Goal {
                    kind: kind.unbounced(),
                    centre: Vec3::new(x, cy, z),
                    radius,
                    vy: 0.0,
                    vel: Vec2::ZERO,
                    spin: Vec2::ZERO,
                    bouncing: kind.bounces(),
                    launch: kind.bounces().then_some(forward),
                    resting: false,
                    reward: sign * raw[0] as f64 * 0.999,
                    collected: false,
                });
            }
            _ => {
                // Zones are triggers: they never block spawning.
                self.zones.push(Zone { kind, foot: Footprint::new(centre, footprint_half, rotation) });
            }
        }
        true
    }

    /// A free spot for the agent, drawn up to 1000 times; the last drawn spot and `false` if none
    /// was free (the env refuses such a layout at construction, see `agent_has_room`).
    fn random_agent_spot(&self, spec: &AgentSpec, rng: &mut ChaCha8Rng) -> (Vec2, bool) {
        let lo = AGENT_RADIUS;
        let hi = ARENA_SIZE - AGENT_RADIUS;
        let mut p = Vec2::splat(ARENA_SIZE / 2.0);
        for _ in 0..10 * SPAWN_TRIES {
            p = Vec2::new(
                spec.position[0].unwrap_or_else(|| rng.gen_range(lo..hi)),
                spec.position[1].unwrap_or_else(|| rng.gen_range(lo..hi)),
            );
            let (lo, hi) = (spec.y, spec.y + 2.0 * AGENT_RADIUS);
            let pushed = self.pushed.iter().flat_map(Pushable::colliders);
            let blocked = self
                .colliders
                .iter()
                .copied()
                .chain(pushed)
                .any(|c| c.spans((lo, hi)) && c.foot.overlaps_disc(p, AGENT_RADIUS))
                || self.goals.iter().any(|g| {
                    g.centre.y - g.radius < hi
                        && g.centre.y + g.radius > lo
                        && (Vec2::new(g.centre.x, g.centre.z) - p).length() < g.radius + AGENT_RADIUS + 0.5
                })
                || self.zones.iter().any(|z| z.foot.contains(p, AGENT_RADIUS));
            if !blocked {
                return (p, true);
            }
        }
        (p, false)
    }

    /// The objects of `layout` (indices in `layout.objects`) that no spawn places: each of the four
    /// fixed draws of `check_room` finds their spot taken. v1 leaves such an object out, and so
    /// does the YAML loader, saying so (a layout built in code is refused instead).
    pub fn always_left_out(layout: &Layout) -> Vec<usize> {
        let mut out: Option<Vec<usize>> = None;
        for k in 0..4u64 {
            let mut rng = crate::seed::rng(k, crate::seed::Stream::Env);
            let (_, unplaced) = World::spawn_counting(layout, &mut rng);
            out = Some(match out {
                None => unplaced,
                Some(before) => before.into_iter().filter(|i| unplaced.contains(i)).collect(),
            });
        }
        out.unwrap_or_default()
    }

    /// Why `layout` cannot be spawned as written, if it cannot: an object left out (its index in
    /// `layout.objects` and kind), or a randomly placed agent with no free spot. Checked with four
    /// fixed draws, so a layout that fits is never refused for its randomness alone.
    pub fn check_room(layout: &Layout) -> Result<(), String> {
        if let Some((i, o)) = layout.objects.iter().enumerate().find(|(_, o)| !o.kind.simulated()) {
            let kind = o.kind.name();
            return Err(format!(
                "object {i} (a {kind}) is pushable, which needs the `pushables` feature (the arena build)"
            ));
        }
        for k in 0..4u64 {
            let mut rng = crate::seed::rng(k, crate::seed::Stream::Env);
            let (w, unplaced) = World::spawn_counting(layout, &mut rng);
            if let Some(&i) = unplaced.first() {
                let kind = layout.objects[i].kind.name();
                return Err(format!("object {i} (a {kind}) finds no free spot ({SPAWN_TRIES} tries when random)"));
            }
            if !matches!(layout.agent.position, [Some(_), Some(_)]) && !w.random_agent_spot(&layout.agent, &mut rng).1 {
                return Err(format!("the agent finds no free spot ({} draws)", 10 * SPAWN_TRIES));
            }
        }
        Ok(())
    }
}

/// Maps any angle in degrees into [0, 360).
pub fn wrap_degrees(d: f32) -> f32 {
    let w = d % 360.0;
    if w < 0.0 {
        w + 360.0
    } else {
        w
    }
}
