//! Animal-AI v1 dynamics, one 0.02 s physics frame at a time (docs/ARENAS.md section 3).

use super::world::{support, wrap_degrees, Agent, Collider, Goal, Pushable, Ramp, Support, World, AGENT_RADIUS};
use super::{ObjectKind, ARENA_SIZE};
use glam::Vec2;

/// Physics timestep, seconds.
pub const FRAME_DT: f32 = 0.02;
/// Physics frames per env step (`numberOfActionsBetweenDecisions: 3`).
pub const FRAMES_PER_STEP: u32 = 3;
/// Rotation per frame, degrees (rotationSpeed 100 x dt).
pub const TURN_DEGREES: f32 = 2.0;
/// Velocity change per grounded frame along the heading (speed 50 x dt, VelocityChange).
pub const IMPULSE_DV: f32 = 1.0;
/// PhysX sliding friction per frame: mu g dt = 0.6 x 9.81 x 0.02.
pub const FRICTION_DV: f32 = 0.6 * 9.81 * FRAME_DT;
/// Rigid-body drag per frame: 1 - drag x dt = 1 - 2 x 0.02.
pub const DRAG_FACTOR: f32 = 0.96;
/// Gravity, m/s^2 (goals fall until they rest).
pub const GRAVITY: f32 = 9.81;
/// Goals' `MediumBounce` material: bounciness 0.4, averaged with the floor's 0.
pub(super) const GOAL_BOUNCINESS: f32 = 0.4;
/// What a goal's bounce keeps of its speed.
const GOAL_RESTITUTION: f32 = GOAL_BOUNCINESS / 2.0;
/// A bouncing goal's launch speed, m/s: `forceToApply` 500 x the physics step as a velocity
/// change, in its first frame (`BallGoalBounce.Start`).
pub const BOUNCE_LAUNCH: f32 = 500.0 * FRAME_DT;
/// Its `BounceBall` material's bounciness 0.8, combined by maximum: 0.8 against every surface.
pub(super) const BOUNCE_RESTITUTION: f32 = 0.8;
/// Its dynamic friction, combined by minimum (the floor's is higher).
pub(super) const BOUNCE_FRICTION: f32 = 0.3;
/// The sliding deceleration while its spin catches up with its speed.
const BOUNCE_FRICTION_DV: f32 = BOUNCE_FRICTION * GRAVITY * FRAME_DT;
/// Other goals' `MediumBounce` material: friction 0.6 (averaged with the floor's, taken as the
/// same), which acts once a ramp sets them rolling.
pub(super) const GOAL_FRICTION: f32 = 0.6;
/// Its sliding deceleration.
const GOAL_FRICTION_DV: f32 = GOAL_FRICTION * GRAVITY * FRAME_DT;
/// Every goal's rigid body's angular drag, per second.
pub(super) const GOAL_ANGULAR_DRAG: f32 = 0.05;
/// The same, per frame.
const SPIN_FACTOR: f32 = 1.0 - GOAL_ANGULAR_DRAG * FRAME_DT;
/// Unity puts a body to sleep below 0.005 of kinetic energy per unit mass: v^2 / 2 < 0.005.
const SLEEP_SPEED: f32 = 0.1;
/// Unity's bounce threshold: a rebound slower than this is dropped, which gives the single
/// bounce of docs/ARENAS.md section 7.2 (14 m/s -> 2.8 m/s, then 0.56 m/s is dropped).
const BOUNCE_THRESHOLD: f32 = 2.0;
/// The agent is "in" a zone when its centre is within this of the rectangle.
const ZONE_MARGIN: f32 = 0.1;
/// How far a ramp's slope can lift a sphere in one frame: it meets the slope below its centre, so
/// one radius (the agent's 0.5; a goal's own).
const CLIMB: f32 = AGENT_RADIUS;
/// Collision passes per frame; several resolve corners where two walls push at once.
const COLLISION_PASSES: usize = 4;

/// What happened in one physics frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameEvents {
    /// Goal, death-zone and hot-zone rewards this frame (not the time penalty).
    pub reward: f64,
    /// A GoodGoal, BadGoal or DeathZone ended the episode, or the GoodGoalMulti that brought the
    /// multi-goals collected to the number of good goals spawned.
    pub terminal: bool,
    /// A good goal (GoodGoal or GoodGoalMulti) was touched this frame.
    pub good_goal: bool,
}

/// Rigid bodies that move the agent with the world's pushable objects and goals, one physics
/// frame at a time: the agent's position and velocity go in and come back, the objects and the
/// goals take their new poses (`push::Bodies`, in an arena with pushable objects, where the goals
/// are rigid bodies too, so that a pushed object pushes them).
pub trait RigidBodies {
    /// One physics frame of the agent, `pushed` and `goals`.
    fn step(&mut self, agent: &mut Agent, pushed: &mut [Pushable], goals: &mut [Goal]);
}

/// Advances the world by one physics frame with the action's two branches:
/// `movement` 0 none, 1 forward, 2 backward; `turn` 0 none, 1 right (clockwise), 2 left.
/// `hot_penalty` is the HotZone reward per frame (negative). `bodies`: the rigid bodies of the
/// pushable objects and the goals, in an arena that has pushable objects.
pub fn physics_frame(
    w: &mut World,
    bodies: Option<&mut dyn RigidBodies>,
    movement: u8,
    turn: u8,
    hot_penalty: f64,
) -> FrameEvents {
    let under = under_agent(w);
    let a = &mut w.agent;
    match turn {
        1 => a.heading = wrap_degrees(a.heading + TURN_DEGREES),
        2 => a.heading = wrap_degrees(a.heading - TURN_DEGREES),
        _ => {}
    }
    if a.grounded {
        // On a slope, gravity first (as Unity integrates it, before the contacts and the drag).
        if let Some(i) = under.ramp.filter(|_| under.height == a.y) {
            let (downhill, rise) = w.ramps[i].downhill();
            a.vel += downhill * (slope_gravity(rise) * FRAME_DT);
        }
        let push = match movement {
            1 => IMPULSE_DV,
            2 => -IMPULSE_DV,
            _ => 0.0,
        };
        if push != 0.0 {
            a.vel += a.forward() * push;
        }
        let s = a.vel.length();
        if s > 0.0 {
            a.vel *= (s - FRICTION_DV).max(0.0) / s;
        }
    }
    a.vel *= DRAG_FACTOR;
    let before = a.pos;
    // The agent moves by its velocity; in an arena with pushable objects, the rigid bodies move
    // it with them (it pushes them and they push back), and the goals with them.
    match bodies {
        Some(b) => b.step(&mut w.agent, &mut w.pushed, &mut w.goals),
        None => w.agent.pos += w.agent.vel * FRAME_DT,
    }
    if !collide(w) {
        // Squeezed between colliders (a gap narrower than the agent): stay where it was.
        w.agent.pos = before;
        w.agent.vel = Vec2::ZERO;
    }
    fall_agent(w);
    if w.pushed.is_empty() {
        fall_goals(w);
    }
    touches(w, hot_penalty)
}

/// The agent above what is under it falls under gravity, with the drag it has in every
/// direction, and lands without a bounce; it is grounded when it stands on something. Standing on
/// a ramp it follows the slope, up or down (gravity pulls it downhill in `physics_frame`).
fn fall_agent(w: &mut World) {
    let under = under_agent(w);
    let a = &mut w.agent;
    let floor = under.height;
    if floor > a.y || (under.ramp.is_some() && a.grounded && floor >= a.y - CLIMB) {
        a.y = floor;
        a.vy = 0.0;
    } else if a.y > floor || a.vy != 0.0 {
        a.vy = (a.vy - GRAVITY * FRAME_DT) * DRAG_FACTOR;
        a.y += a.vy * FRAME_DT;
        if a.y <= floor {
            a.y = floor;
            a.vy = 0.0;
        }
    }
    a.grounded = a.y == floor;
}

/// What the agent stands on. On the floor of an arena without ramps nothing else can be under
/// it (a box would have stopped it first), which is most frames of most arenas: no search.
fn under_agent(w: &World) -> Support {
    if w.ramps.is_empty() && w.agent.y == 0.0 {
        return Support { height: 0.0, ramp: None };
    }
    support(w.boxes(), &w.ramps, w.agent.pos, w.agent.y, CLIMB)
}

/// The horizontal pull of gravity on a slope rising `rise` per metre: g sin(a) cos(a).
fn slope_gravity(rise: f32) -> f32 {
    GRAVITY * rise / (1.0 + rise * rise)
}

/// Pushes the agent's disc out of every collider in its way (one spanning some of its heights;
/// a ramp only where its slope at the contact is too high to climb onto) and the fences,
/// dropping the velocity component into the surface (no bounce, no wall friction). Returns false
/// when the pushes could not resolve every overlap.
fn collide(w: &mut World) -> bool {
    // Its bottom is where it now stands (a slope's or a box's height, which the fall below sets
    // for the frame): on a ramp the sphere rides over the edge of a box the ramp leads onto, which
    // it touches at most the slope's rise over one radius below the box's top.
    let under = under_agent(w);
    let a = &mut w.agent;
    let step = under.ramp.map_or(0.0, |i| w.ramps[i].downhill().1 * AGENT_RADIUS + 1e-3);
    let span = (under.height.max(a.y) + step, a.y + 2.0 * AGENT_RADIUS);
    for _ in 0..COLLISION_PASSES {
        let mut moved = false;
        for c in w.colliders.iter().filter(|c| c.spans(span)) {
            if let Some(i) = c.ramp {
                let l = c.foot.to_local(a.pos);
                if w.ramps[i].surface_local(l.clamp(-c.foot.half, c.foot.half)) <= a.y + CLIMB {
                    continue;
                }
            }
            let c = &c.foot;
            let l = c.to_local(a.pos);
            if l.x.abs() >= c.half.x + AGENT_RADIUS || l.y.abs() >= c.half.y + AGENT_RADIUS {
                continue;
            }
            let q = l.clamp(-c.half, c.half);
            let d = l - q;
            let dist2 = d.length_squared();
            let (normal_local, depth) = if dist2 > 0.0 {
                let dist = dist2.sqrt();
                if dist >= AGENT_RADIUS {
                    continue;
                }
                (d / dist, AGENT_RADIUS - dist)
            } else {
                // Centre inside the box (cannot happen at these speeds): leave by the nearest side.
                let ex = c.half.x - l.x.abs();
                let ez = c.half.y - l.y.abs();
                if ex < ez {
                    (Vec2::new(l.x.signum(), 0.0), ex + AGENT_RADIUS)
                } else {
                    (Vec2::new(0.0, l.y.signum()), ez + AGENT_RADIUS)
                }
            };
            let n = c.to_world_dir(normal_local);
            a.pos += n * depth;
            let vn = a.vel.dot(n);
            if vn < 0.0 {
                a.vel -= n * vn;
            }
            moved = true;
        }
        // Fences: invisible infinitely tall walls at 0 and 40.
        let lo = AGENT_RADIUS;
        let hi = ARENA_SIZE - AGENT_RADIUS;
        if a.pos.x < lo || a.pos.x > hi {
            a.pos.x = a.pos.x.clamp(lo, hi);
            a.vel.x = 0.0;
        }
        if a.pos.y < lo || a.pos.y > hi {
            a.pos.y = a.pos.y.clamp(lo, hi);
            a.vel.y = 0.0;
        }
        if !moved {
            return true;
        }
    }
    !w.colliders.iter().filter(|c| c.spans(span)).any(|c| {
        let l = c.foot.to_local(a.pos);
        (l - l.clamp(-c.foot.half, c.foot.half)).length() < AGENT_RADIUS - 1e-3
    })
}

/// Goals fall under gravity (no drag) and bounce once on the floor or the box under them; a
/// bouncing goal, and any goal a ramp sets rolling, also rolls (`roll`) until it sleeps. (In an
/// arena with pushable objects the goals are rigid bodies of `push` instead.)
fn fall_goals(w: &mut World) {
    for g in w.goals.iter_mut().filter(|g| !g.resting && !g.collected) {
        let under =
            support(w.walls.iter(), &w.ramps, Vec2::new(g.centre.x, g.centre.z), g.centre.y - g.radius, g.radius);
        let floor = under.height;
        g.vy -= GRAVITY * FRAME_DT;
        g.centre.y += g.vy * FRAME_DT;
        let mut grounded = false;
        if g.centre.y <= floor + g.radius {
            g.centre.y = floor + g.radius;
            let e = if g.bouncing { BOUNCE_RESTITUTION } else { GOAL_RESTITUTION };
            let rebound = -g.vy * e;
            if rebound >= BOUNCE_THRESHOLD {
                g.vy = rebound;
            } else {
                g.vy = 0.0;
                grounded = true;
                g.resting = !g.bouncing && under.ramp.is_none() && g.vel == Vec2::ZERO;
            }
        }
        if g.bouncing || under.ramp.is_some() || g.vel != Vec2::ZERO {
            let slope = under.ramp.filter(|_| grounded).map(|i| w.ramps[i].downhill());
            roll(g, grounded, slope, &w.colliders, &w.ramps);
        }
    }
}

/// One frame of a goal's horizontal motion (a bouncing goal's always, another's once a ramp sets
/// it rolling): its launch; its spin's drag; downhill on a slope (`slope`: downhill and rise);
/// on the ground, sliding friction between its speed and its spin until it rolls (a solid
/// sphere: the spin gains 5/2 of what the speed loses); the move; bounces off the colliders in
/// its way and the fences; sleep.
fn roll(g: &mut Goal, grounded: bool, slope: Option<(Vec2, f32)>, colliders: &[Collider], ramps: &[Ramp]) {
    if let Some(forward) = g.launch.take() {
        g.vel += forward * BOUNCE_LAUNCH;
    }
    let (restitution, friction) =
        if g.bouncing { (BOUNCE_RESTITUTION, BOUNCE_FRICTION_DV) } else { (GOAL_RESTITUTION, GOAL_FRICTION_DV) };
    g.spin *= SPIN_FACTOR;
    if let Some((downhill, rise)) = slope {
        g.vel += downhill * (slope_gravity(rise) * FRAME_DT);
    }
    if grounded {
        let slip = g.vel - g.spin;
        let s = slip.length();
        if s <= 3.5 * friction {
            let rolling = (g.vel * 2.5 + g.spin) / 3.5;
            (g.vel, g.spin) = (rolling, rolling);
        } else {
            let d = slip / s * friction;
            g.vel -= d;
            g.spin += d * 2.5;
        }
    }
    let mut p = Vec2::new(g.centre.x, g.centre.z) + g.vel * FRAME_DT;
    let r = g.radius;
    let bounce = |vel: &mut Vec2, n: Vec2| {
        let vn = vel.dot(n);
        if vn < 0.0 {
            let rebound = if -vn * restitution >= BOUNCE_THRESHOLD { restitution } else { 0.0 };
            *vel -= n * vn * (1.0 + rebound);
        }
    };
    for c in colliders.iter().filter(|c| c.spans((g.centre.y - r, g.centre.y + r))) {
        let l = c.foot.to_local(p);
        let q = l.clamp(-c.foot.half, c.foot.half);
        if c.ramp.is_some_and(|i| ramps[i].surface_local(q) <= g.centre.y) {
            // Onto the slope, not off its side.
            continue;
        }
        let d = l - q;
        let dist = d.length();
        if dist >= r || dist == 0.0 {
            continue;
        }
        let n = c.foot.to_world_dir(d / dist);
        p += n * (r - dist);
        bounce(&mut g.vel, n);
    }
    for (axis, n) in [(0, Vec2::X), (1, Vec2::Y)] {
        if p[axis] < r {
            p[axis] = r;
            bounce(&mut g.vel, n);
        } else if p[axis] > ARENA_SIZE - r {
            p[axis] = ARENA_SIZE - r;
            bounce(&mut g.vel, -n);
        }
    }
    (g.centre.x, g.centre.z) = (p.x, p.y);
    // A goal on a slope never sleeps: gravity keeps pulling it.
    if grounded && slope.is_none() && g.vel.length() < SLEEP_SPEED && g.spin.length() < SLEEP_SPEED {
        (g.vel, g.spin) = (Vec2::ZERO, Vec2::ZERO);
        g.resting = true;
    }
}

/// Goal touches (3-D centre distance <= 0.5 + r) and zones.
fn touches(w: &mut World, hot_penalty: f64) -> FrameEvents {
    let mut ev = FrameEvents::default();
    let agent3 = glam::Vec3::new(w.agent.pos.x, w.agent.y + AGENT_RADIUS, w.agent.pos.y);
    for g in w.goals.iter_mut().filter(|g| !g.collected) {
        if (g.centre - agent3).length() > AGENT_RADIUS + g.radius {
            continue;
        }
        ev.reward += g.reward;
        match g.kind {
            ObjectKind::GoodGoalMulti => {
                g.collected = true;
                ev.good_goal = true;
            }
            ObjectKind::GoodGoal => {
                ev.good_goal = true;
                ev.terminal = true;
            }
            _ => ev.terminal = true,
        }
    }
    // v1 counts every good goal spawned, GoodGoals too (`ArenaBuilders.updateGoodGoalsMulti`), and
    // ends when the multi-goals collected reach that count (`Goal.OnCollisionEnter`): beside a
    // GoodGoal, the last multi-goal does not end the episode.
    let good = w.goals.iter().filter(|g| matches!(g.kind, ObjectKind::GoodGoal | ObjectKind::GoodGoalMulti)).count();
    let collected = w.goals.iter().filter(|g| g.kind == ObjectKind::GoodGoalMulti && g.collected).count();
    if ev.good_goal && collected == good {
        ev.terminal = true;
    }
    // Zones lie on the floor: the agent on a box above one is not in it.
    for z in w.zones.iter().filter(|_| w.agent.y < ZONE_MARGIN) {
        if !z.foot.contains(w.agent.pos, ZONE_MARGIN) {
            continue;
        }
        match z.kind {
            ObjectKind::DeathZone => {
                ev.reward += -1.0;
                ev.terminal = true;
            }
            _ => ev.reward += hot_penalty,
        }
    }
    ev
}
