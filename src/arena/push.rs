//! Pushable objects as rigid bodies (docs/ARENAS.md section 5): rapier3d, built with its
//! cross-platform determinism (`enhanced-determinism`), so that a run gives the same bits on every
//! target. Only an arena with a pushable object builds these bodies; no other arena, the paper's
//! tasks among them, ever calls rapier.
//!
//! What rapier simulates: the pushable objects (dynamic bodies of one box, or of the two or three
//! boxes of an L or a U, with the prefabs' masses and Unity's default friction, turning only
//! about the vertical, since the renderer draws upright boxes), on the floor and on
//! the arena's colliders (walls, arch legs and ramps, all fixed), and the agent's sphere, of mass
//! 1, which meets only the boxes. The agent's own dynamics stay `physics`'s: each frame its
//! velocity after the motor, friction and drag goes in, rapier moves it, meeting the boxes (which
//! it pushes, and which push back by their mass and friction), and its position and velocity come
//! back for `physics` to meet the walls as in any arena.

use super::physics::{
    RigidBodies, BOUNCE_FRICTION, BOUNCE_LAUNCH, BOUNCE_RESTITUTION, FRAME_DT, GOAL_ANGULAR_DRAG, GOAL_BOUNCINESS,
    GOAL_FRICTION, GRAVITY,
};
use super::world::{Agent, BoxObj, Footprint, Goal, Pushable, World, AGENT_RADIUS};
use super::ARENA_SIZE;
use rapier3d::prelude::*;

/// Unity's default physics material's friction, the floor's, the fixed bodies' and the agent's
/// (combined by average with a pushable object's own).
const FRICTION: f32 = 0.6;
/// Unity's default angular drag, per second (a box has no linear drag).
const ANGULAR_DRAG: f32 = 0.05;
/// The agent's mass, kg (v1's agent prefab).
const AGENT_MASS: f32 = 1.0;
/// A goal's mass, kg (the goal prefabs' rigid bodies).
const GOAL_MASS: f32 = 1.0;
/// Thickness of the floor's and the fences' fixed boxes, metres.
const SLAB: f32 = 1.0;
/// The fences' height: no box is taller than 10.
const FENCE_HEIGHT: f32 = 20.0;

/// Who meets whom: the agent only the pushable objects (it touches goals by `physics`'s rules);
/// the objects and the goals everything else, and each other.
const AGENT: InteractionGroups = InteractionGroups::new(Group::GROUP_1, Group::GROUP_2, InteractionTestMode::And);
const BOXES: InteractionGroups = InteractionGroups::new(Group::GROUP_2, Group::ALL, InteractionTestMode::And);
const FIXED: InteractionGroups =
    InteractionGroups::new(Group::GROUP_3, Group::GROUP_2.union(Group::GROUP_4), InteractionTestMode::And);
const GOALS: InteractionGroups = InteractionGroups::new(
    Group::GROUP_4,
    Group::GROUP_2.union(Group::GROUP_3).union(Group::GROUP_4),
    InteractionTestMode::And,
);

/// The rigid bodies of one episode's world: the agent's sphere, one per pushable object (in the
/// order of `World::pushed`) and one per goal (in the order of `World::goals`).
pub struct Bodies {
    world: PhysicsWorld,
    agent: RigidBodyHandle,
    boxes: Vec<RigidBodyHandle>,
    goals: Vec<RigidBodyHandle>,
}

impl Bodies {
    /// The bodies of a spawned world: its colliders fixed, its pushable boxes where they spawned.
    pub fn new(w: &World) -> Bodies {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, -GRAVITY, 0.0);
        world.integration_parameters.dt = FRAME_DT;
        // Colliders with no body are fixed.
        let fixed = |world: &mut PhysicsWorld, pose: Pose, collider: ColliderBuilder| {
            world.insert_collider(collider.position(pose).friction(FRICTION).collision_groups(FIXED), None);
        };
        let mid = ARENA_SIZE / 2.0;
        let half = mid + SLAB;
        fixed(&mut world, Pose::translation(mid, -SLAB / 2.0, mid), ColliderBuilder::cuboid(half, SLAB / 2.0, half));
        for (x, z, hx, hz) in [
            (-SLAB / 2.0, mid, SLAB / 2.0, half),
            (ARENA_SIZE + SLAB / 2.0, mid, SLAB / 2.0, half),
            (mid, -SLAB / 2.0, half, SLAB / 2.0),
            (mid, ARENA_SIZE + SLAB / 2.0, half, SLAB / 2.0),
        ] {
            let pose = Pose::translation(x, FENCE_HEIGHT / 2.0, z);
            fixed(&mut world, pose, ColliderBuilder::cuboid(hx, FENCE_HEIGHT / 2.0, hz));
        }
        for c in &w.colliders {
            let f = &c.foot;
            match c.ramp {
                // A ramp's wedge: its floor rectangle and its high edge (it rises towards local -z).
                Some(i) => {
                    let r = &w.ramps[i];
                    let (hx, hz) = (f.half.x, f.half.y);
                    let (lo, hi) = (r.base, r.base + r.height);
                    let mut corners = vec![];
                    for (lx, lz, y) in
                        [(-hx, -hz, lo), (hx, -hz, lo), (hx, hz, lo), (-hx, hz, lo), (-hx, -hz, hi), (hx, -hz, hi)]
                    {
                        let p = f.centre + f.to_world_dir(glam::Vec2::new(lx, lz));
                        corners.push(Vector::new(p.x, y, p.y));
                    }
                    if let Some(hull) = ColliderBuilder::convex_hull(&corners) {
                        fixed(&mut world, Pose::identity(), hull);
                    }
                }
                None => {
                    let pose = upright(f, (c.bottom + c.top) / 2.0);
                    fixed(&mut world, pose, ColliderBuilder::cuboid(f.half.x, (c.top - c.bottom) / 2.0, f.half.y));
                }
            }
        }
        let boxes = w
            .pushed
            .iter()
            .map(|p| {
                let body = RigidBodyBuilder::dynamic()
                    .pose(upright(&p.pose, p.base() + p.height() / 2.0))
                    .enabled_rotations(false, true, false)
                    .angular_damping(ANGULAR_DRAG)
                    // Continuous collision: a box pushed fast or dropped from high up does not
                    // pass through a thin wall (0.1 m) in one frame.
                    .ccd_enabled(true);
                let body = world.insert_body(body);
                // The mass shared by the boxes' volumes, so that rapier finds the centre of mass
                // as Unity does from the colliders (all boxes have the object's height).
                let area = |b: &BoxObj| b.foot.half.x * b.foot.half.y;
                let total: f32 = p.parts.iter().map(area).sum();
                for (b, o) in p.parts.iter().zip(&p.offsets) {
                    let shape = ColliderBuilder::cuboid(b.foot.half.x, b.height / 2.0, b.foot.half.y)
                        .translation(Vector::new(o.x, 0.0, o.y))
                        .mass(p.mass * (area(b) / total))
                        .friction(p.friction)
                        .collision_groups(BOXES);
                    world.insert_collider(shape, Some(body));
                }
                body
            })
            .collect();
        let sphere = RigidBodyBuilder::dynamic()
            .translation(Vector::new(w.agent.pos.x, w.agent.y + AGENT_RADIUS, w.agent.pos.y))
            .enabled_translations(true, false, true)
            .lock_rotations()
            .gravity_scale(0.0)
            .can_sleep(false);
        let agent = world.insert_body(sphere);
        let ball = ColliderBuilder::ball(AGENT_RADIUS).mass(AGENT_MASS).friction(FRICTION).collision_groups(AGENT);
        world.insert_collider(ball, Some(agent));
        // Goals as the goal prefabs' bodies: spheres with their materials (docs/ARENAS.md
        // section 5), launched in their first frame if they bounce (`step`).
        let goals = w
            .goals
            .iter()
            .map(|g| {
                let c = g.centre;
                let body = RigidBodyBuilder::dynamic()
                    .translation(Vector::new(c.x, c.y, c.z))
                    .angular_damping(GOAL_ANGULAR_DRAG)
                    .ccd_enabled(true);
                let body = world.insert_body(body);
                let (restitution, rule, friction, friction_rule) = if g.bouncing {
                    (BOUNCE_RESTITUTION, CoefficientCombineRule::Max, BOUNCE_FRICTION, CoefficientCombineRule::Min)
                } else {
                    (GOAL_BOUNCINESS, CoefficientCombineRule::Average, GOAL_FRICTION, CoefficientCombineRule::Average)
                };
                let ball = ColliderBuilder::ball(g.radius)
                    .mass(GOAL_MASS)
                    .restitution(restitution)
                    .restitution_combine_rule(rule)
                    .friction(friction)
                    .friction_combine_rule(friction_rule)
                    .collision_groups(GOALS);
                world.insert_collider(ball, Some(body));
                body
            })
            .collect();
        Bodies { world, agent, boxes, goals }
    }

    /// Every body's pose and velocity, as bits (what makes two worlds the same).
    fn state(&self) -> Vec<u32> {
        let mut bits = Vec::new();
        for &h in self.boxes.iter().chain(&self.goals).chain([&self.agent]) {
            let b = &self.world.bodies[h];
            let (t, q, v, w) = (b.translation(), b.rotation(), b.linvel(), b.angvel());
            bits.extend([t.x, t.y, t.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z].map(f32::to_bits));
        }
        bits
    }
}

impl RigidBodies for Bodies {
    /// The agent, at its position with its velocity, moves with the pushable objects and the
    /// goals; it, `pushed` and `goals` take their new poses. A collected goal leaves the world.
    fn step(&mut self, agent: &mut Agent, pushed: &mut [Pushable], goals: &mut [Goal]) {
        let sphere = &mut self.world.bodies[self.agent];
        sphere.set_translation(Vector::new(agent.pos.x, agent.y + AGENT_RADIUS, agent.pos.y), true);
        sphere.set_linvel(Vector::new(agent.vel.x, 0.0, agent.vel.y), true);
        for (g, &h) in goals.iter_mut().zip(&self.goals) {
            let body = &mut self.world.bodies[h];
            if g.collected {
                if body.is_enabled() {
                    body.set_enabled(false);
                }
            } else if let Some(forward) = g.launch.take() {
                let v = forward * BOUNCE_LAUNCH;
                body.set_linvel(body.linvel() + Vector::new(v.x, 0.0, v.y), true);
            }
        }
        self.world.step();
        let sphere = &self.world.bodies[self.agent];
        let (t, v) = (sphere.translation(), sphere.linvel());
        agent.pos = glam::Vec2::new(t.x, t.z);
        agent.vel = glam::Vec2::new(v.x, v.z);
        for (p, &h) in pushed.iter_mut().zip(&self.boxes) {
            let body = &self.world.bodies[h];
            let (t, q) = (body.translation(), body.rotation());
            // Upright, a turn by a about +y: q = (0, sin(a/2), 0, cos(a/2)), so that cos a and
            // sin a are these (`Footprint`'s local +x is (cos, -sin)).
            let pose = Footprint {
                centre: glam::Vec2::new(t.x, t.z),
                cos: 1.0 - 2.0 * q.y * q.y,
                sin: 2.0 * q.y * q.w,
                ..p.pose
            };
            p.move_to(pose, t.y - p.height() / 2.0);
        }
        for (g, &h) in goals.iter_mut().zip(&self.goals).filter(|(g, _)| !g.collected) {
            let body = &self.world.bodies[h];
            let (t, v) = (body.translation(), body.linvel());
            g.centre = glam::Vec3::new(t.x, t.y, t.z);
            (g.vel, g.vy) = (glam::Vec2::new(v.x, v.z), v.y);
        }
    }
}

/// A body's pose: upright over `foot`, its centre at height `y`. The rotation is built from the
/// footprint's cosine and sine by square roots (the half angle), exact on every target.
fn upright(foot: &Footprint, y: f32) -> Pose {
    let half_cos = ((1.0 + foot.cos) / 2.0).max(0.0).sqrt();
    let half_sin = ((1.0 - foot.cos) / 2.0).max(0.0).sqrt().copysign(foot.sin);
    let rotation = Rotation::from_xyzw(0.0, half_sin, 0.0, half_cos);
    Pose::from_parts(Vector::new(foot.centre.x, y, foot.centre.y), rotation)
}

impl Clone for Bodies {
    /// The same bodies; the pipelines are workspace only and start empty.
    fn clone(&self) -> Self {
        let w = &self.world;
        let world = PhysicsWorld {
            gravity: w.gravity,
            integration_parameters: w.integration_parameters,
            physics_pipeline: PhysicsPipeline::new(),
            collision_pipeline: CollisionPipeline::new(),
            islands: w.islands.clone(),
            broad_phase: w.broad_phase.clone(),
            narrow_phase: w.narrow_phase.clone(),
            bodies: w.bodies.clone(),
            colliders: w.colliders.clone(),
            impulse_joints: w.impulse_joints.clone(),
            multibody_joints: w.multibody_joints.clone(),
            soft_bodies: w.soft_bodies.clone(),
            ccd_solver: w.ccd_solver.clone(),
        };
        Bodies { world, agent: self.agent, boxes: self.boxes.clone(), goals: self.goals.clone() }
    }
}

impl std::fmt::Debug for Bodies {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Bodies")
            .field("boxes", &self.boxes.len())
            .field("goals", &self.goals.len())
            .finish_non_exhaustive()
    }
}

impl PartialEq for Bodies {
    fn eq(&self, other: &Self) -> bool {
        self.state() == other.state()
    }
}
