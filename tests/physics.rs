//! The v1 dynamics against the published numbers (docs/ARENAS.md section 3), collisions and rewards.
#![cfg(not(target_arch = "wasm32"))]

use glam::Vec2;
use sec_playground::arena::{Action, AgentSpec, Layout, ObjectKind, ObjectSpec, Task, AGENT_RADIUS};
use sec_playground::env::{Env, EnvConfig};

/// An arena with only the given objects and the agent at (x, z) facing `heading`.
fn open_env(objects: Vec<ObjectSpec>, x: f32, z: f32, heading: f32) -> Env {
    raised_env(objects, x, 0.0, z, heading)
}

/// The same with the agent placed `y` high.
fn raised_env(objects: Vec<ObjectSpec>, x: f32, y: f32, z: f32, heading: f32) -> Env {
    let layout = Layout {
        name: "test".into(),
        t: 1000,
        objects,
        agent: AgentSpec { position: [Some(x), Some(z)], y, rotation: Some(heading) },
        blackouts: Default::default(),
    };
    let task = Task { name: "test".into(), description: String::new(), layouts: vec![layout], warnings: Vec::new() };
    Env::new(EnvConfig::new(task), 1).unwrap()
}

fn speed(env: &Env) -> f32 {
    env.world().agent.vel.length()
}

#[test]
fn velocity_trace_matches_the_published_v1_log() {
    // OLY issue #77, forward held; started from the published second step (3.00 m/s, grounded).
    let published = [0.847, 3.00, 5.10, 6.95, 8.59, 10.04, 11.32, 12.46, 13.46, 14.35, 15.14];
    let mut env = open_env(vec![], 5.0, 2.0, 0.0);
    env.step(Action::NOOP).unwrap(); // settle: grounded from now on
    {
        let a = &mut env.world_mut().agent;
        a.vel = Vec2::new(0.0, published[1]);
    }
    for (k, &want) in published.iter().enumerate().skip(2) {
        env.step(Action::FORWARD).unwrap();
        let got = speed(&env);
        assert!((got - want).abs() / want < 0.005, "env step {}: speed {got}, published {want}", k + 1);
    }
}

#[test]
fn speeds_from_rest_and_top_speed() {
    for (steps, want) in [(4, 8.20), (8, 13.2), (16, 18.2)] {
        let mut env = open_env(vec![], 5.0, 2.0, 0.0);
        env.step(Action::NOOP).unwrap();
        assert_eq!(speed(&env), 0.0, "at rest before pushing");
        for _ in 0..steps {
            env.step(Action::FORWARD).unwrap();
        }
        let got = speed(&env);
        assert!((got - want).abs() / want < 0.005, "{steps} steps from rest: {got}, expected {want}");
    }
    // Top speed: hold forward long enough, teleporting back before the far fence.
    let mut env = open_env(vec![], 20.0, 2.0, 0.0);
    for _ in 0..300 {
        env.step(Action::FORWARD).unwrap();
        let a = &mut env.world_mut().agent;
        if a.pos.y > 30.0 {
            a.pos.y = 2.0;
        }
    }
    let top = speed(&env);
    assert!((top - 21.17).abs() < 0.01, "top speed {top}");
}

#[test]
fn turning_is_six_degrees_per_env_step_and_momentum_stays_in_the_world_frame() {
    let mut env = open_env(vec![], 20.0, 5.0, 0.0);
    env.step(Action::RIGHT).unwrap();
    assert_eq!(env.world().agent.heading, 6.0);
    env.step(Action::LEFT).unwrap();
    env.step(Action::LEFT).unwrap();
    assert_eq!(env.world().agent.heading, 354.0);
    // Build speed along +z, then turn 90 degrees without pushing: the velocity keeps its direction.
    let mut env = open_env(vec![], 20.0, 2.0, 0.0);
    for _ in 0..4 {
        env.step(Action::FORWARD).unwrap();
    }
    for _ in 0..5 {
        env.step(Action::RIGHT).unwrap();
    }
    let v = env.world().agent.vel;
    assert_eq!(env.world().agent.heading, 30.0);
    assert!(v.x.abs() < 1e-6 && v.y > 0.5, "drift keeps the world-frame direction: {v}");
}

/// Drives at `heading` for `steps` env steps and returns the largest penetration into any
/// collider seen after any physics step, plus the final position.
fn drive(env: &mut Env, action: Action, steps: u32) -> (f32, Vec2) {
    let mut worst = 0.0f32;
    for _ in 0..steps {
        if env.is_over() {
            break;
        }
        env.step(action).unwrap();
        let w = env.world();
        for c in &w.colliders {
            let l = c.foot.to_local(w.agent.pos);
            let q = l.clamp(-c.foot.half, c.foot.half);
            worst = worst.max(AGENT_RADIUS - (l - q).length());
        }
    }
    (worst, env.world().agent.pos)
}

#[test]
fn no_wall_of_the_double_t_maze_can_be_crossed() {
    let task = Task::preset("double-t-maze").unwrap();
    let walls: Vec<ObjectSpec> =
        task.layouts[0].objects.iter().filter(|o| o.kind == ObjectKind::Wall).cloned().collect();
    let mut runs = 0;
    // Run at the middle of every wall from all four sides at full speed, head-on and skewed.
    for w in &walls {
        let centre = Vec2::new(w.position[0].unwrap(), w.position[2].unwrap());
        let half = Vec2::new(w.size[0].unwrap(), w.size[2].unwrap()) / 2.0;
        for heading in [0.0f32, 90.0, 180.0, 270.0] {
            for skew in [0.0f32, 25.0, -25.0] {
                let h = (heading + skew).to_radians();
                let dir = Vec2::new(h.sin(), h.cos());
                let reach = (dir.x.abs() * half.x).max(dir.y.abs() * half.y).min(half.length());
                let start = centre - dir * (reach + 6.0);
                if !(1.0..=39.0).contains(&start.x) || !(1.0..=39.0).contains(&start.y) {
                    continue;
                }
                runs += 1;
                let mut env = open_env(vec![w.clone()], start.x, start.y, heading + skew);
                let foot = env.world().colliders[0].foot;
                let mut prev = start;
                for _ in 0..60 {
                    let (pen, p) = drive(&mut env, Action::FORWARD, 1);
                    assert!(pen < 0.02, "wall at {centre} heading {heading}+{skew}: penetration {pen}");
                    // The centre's path never passes through the wall (it may go round it).
                    for k in 0..=20 {
                        let q = prev + (p - prev) * (k as f32 / 20.0);
                        assert!(
                            !foot.contains(q, 0.0),
                            "went through the wall at {centre} heading {heading}+{skew}: {prev} -> {p}"
                        );
                    }
                    prev = p;
                }
            }
        }
    }
    assert!(runs >= 100, "only {runs} runs");
}

#[test]
fn the_transparent_wall_and_the_tunnel_legs_block() {
    // detour-transparent: straight at the glass from the start.
    let mut env = Env::new(EnvConfig::new(Task::preset("detour-transparent").unwrap()), 3).unwrap();
    let (pen, end) = drive(&mut env, Action::FORWARD, 120);
    assert!(pen < 0.02 && end.y <= 36.5 - AGENT_RADIUS + 0.02, "went through the glass to {end}");
    // cylinder: from the start (1,1) facing 45 degrees the arch is side-on; run into the near leg.
    let mut env = Env::new(EnvConfig::new(Task::preset("cylinder").unwrap()), 3).unwrap();
    let (pen, end) = drive(&mut env, Action::FORWARD, 120);
    let axis_dist = ((end.x - 20.0) + (end.y - 20.0)) / std::f32::consts::SQRT_2;
    assert!(pen < 0.02, "penetrated the leg by {pen}");
    assert!(axis_dist < -5.0 + 0.02, "got through the leg: {end}, {axis_dist} from the axis");
}

#[test]
fn a_gap_of_1_1_is_passable() {
    // Two walls along x leave x in [19.45, 20.55] open at z = 20.
    let left = ObjectSpec::new(ObjectKind::Wall, 9.725, 0.0, 20.0).size(19.45, 2.0, 1.0);
    let right = ObjectSpec::new(ObjectKind::Wall, 30.275, 0.0, 20.0).size(19.45, 2.0, 1.0);
    // The 0.999 size adjustment widens the gap slightly; the config gap is 1.1.
    let mut env = open_env(vec![left, right], 20.0, 10.0, 0.0);
    let (pen, end) = drive(&mut env, Action::FORWARD, 30);
    assert!(pen < 0.02);
    assert!(end.y > 22.0, "stuck at {end}");
    // And a 0.9 gap is not.
    let left = ObjectSpec::new(ObjectKind::Wall, 9.775, 0.0, 20.0).size(19.55, 2.0, 1.0);
    let right = ObjectSpec::new(ObjectKind::Wall, 30.225, 0.0, 20.0).size(19.55, 2.0, 1.0);
    let mut env = open_env(vec![left, right], 20.0, 10.0, 0.0);
    let (pen, end) = drive(&mut env, Action::FORWARD, 30);
    assert!(pen < 0.02, "penetration {pen}");
    assert!(end.y < 20.0, "squeezed through a 0.9 gap to {end}");
}

#[test]
fn a_timed_out_t_maze_episode_sums_to_minus_one() {
    let mut env = Env::new(EnvConfig::new(Task::preset("double-t-maze").unwrap()), 5).unwrap();
    let mut total = 0.0;
    let mut n = 0;
    loop {
        // Turning on the spot never reaches the goal.
        let s = env.step(Action::RIGHT).unwrap();
        total += s.reward;
        n += 1;
        assert!(!s.terminated);
        if s.truncated {
            break;
        }
    }
    assert_eq!(n, 1000);
    assert!((total + 1.0).abs() < 1e-9, "total {total}");
    assert!(env.step(Action::NOOP).is_err(), "stepping a finished episode is an error");
}

#[test]
fn touching_the_t_maze_goal_pays_2_997_and_ends_the_episode() {
    let mut env = Env::new(EnvConfig::new(Task::preset("double-t-maze").unwrap()), 5).unwrap();
    {
        let a = &mut env.world_mut().agent;
        a.pos = Vec2::new(20.0, 16.5);
        a.heading = 0.0;
    }
    let mut last = None;
    for _ in 0..20 {
        let s = env.step(Action::FORWARD).unwrap();
        if s.terminated {
            last = Some((s.reward, s.info.good_goal));
            break;
        }
        assert!((s.reward + 0.001).abs() < 1e-12);
    }
    let (reward, good) = last.expect("the goal was not reached");
    assert!(good);
    assert!((reward - (2.997 - 0.001)).abs() < 1e-12, "goal step reward {reward}");
    assert!(env.is_over());
}

#[test]
fn the_dropped_goal_falls_bounces_once_and_rests() {
    let mut env = Env::new(EnvConfig::new(Task::preset("object-permanence").unwrap()), 1).unwrap();
    let big = |env: &Env| env.world().goals[0].clone();
    assert!((big(&env).centre.y - 11.5085).abs() < 1e-3);
    let mut first_bounce = None;
    let mut bounces = 0;
    let mut falling = true;
    for _ in 0..60 {
        env.step(Action::NOOP).unwrap();
        let g = big(&env);
        if falling && g.vy > 0.0 {
            bounces += 1;
            first_bounce.get_or_insert(env.steps());
        }
        falling = g.vy <= 0.0;
    }
    let g = big(&env);
    assert!(g.resting && (g.centre.y - g.radius).abs() < 1e-6);
    assert_eq!(bounces, 1, "bounces once");
    let landed = first_bounce.unwrap();
    assert!((23..=25).contains(&landed), "landed after {landed} env steps (docs/ARENAS.md: about 24)");
}

/// v1's `IsSpotFree` counts goals as colliders (`ArenaBuilders.SamplePositionRotation`): a random
/// goal drawn onto another is drawn again, and a wall is not spawned onto a goal.
#[test]
fn a_random_goal_is_drawn_again_where_it_would_overlap_another() {
    let fixed = ObjectSpec::new(ObjectKind::GoodGoal, 20.0, 0.0, 20.0).size(5.0, 5.0, 5.0);
    let random =
        ObjectSpec { position: [None, Some(0.0), Some(20.0)], ..ObjectSpec::new(ObjectKind::BadGoal, 0.0, 0.0, 0.0) };
    let mut env = open_env(vec![fixed, random], 5.0, 5.0, 0.0);
    let mut near = 0;
    for seed in 0..200 {
        env.reset(Some(seed));
        let g = &env.world().goals;
        assert_eq!(g.len(), 2);
        let gap = (g[0].centre - g[1].centre).length() - g[0].radius - g[1].radius;
        assert!(gap > -1e-4, "seed {seed}: goals overlap by {}", -gap);
        near += (gap < 2.0) as u32;
    }
    assert!(near > 0, "some draws land next to the fixed goal (the test reaches the case)");
    // A wall written onto a goal is not spawned: the layout is refused, naming it.
    let wall = ObjectSpec::new(ObjectKind::Wall, 20.0, 0.0, 20.0).size(4.0, 2.0, 1.0);
    let layout = Layout {
        name: "onto".into(),
        t: 100,
        objects: vec![ObjectSpec::new(ObjectKind::GoodGoal, 20.0, 0.0, 20.0), wall],
        agent: AgentSpec { position: [Some(5.0), Some(5.0)], y: 0.0, rotation: Some(0.0) },
        blackouts: Default::default(),
    };
    let task = Task { name: "onto".into(), description: String::new(), layouts: vec![layout], warnings: Vec::new() };
    let err = Env::new(EnvConfig::new(task), 1).unwrap_err().to_string();
    assert!(err.contains("object 1 (a Wall) finds no free spot"), "{err}");
}

/// v1 counts every good goal spawned, the GoodGoal too, and ends when the multi-goals collected
/// reach that count (beyretb/AnimalAI-Environment, `TrainEnv/Scripts/ArenaBuilders.cs`
/// `updateGoodGoalsMulti`, `TrainEnv/Prefab/Rewards/Scripts/Goal.cs` `OnCollisionEnter`): beside
/// a GoodGoal the last multi-goal pays and the episode goes on, until the GoodGoal ends it.
#[test]
fn beside_a_good_goal_the_last_multi_goal_does_not_end_the_episode() {
    let multi = |z| ObjectSpec::new(ObjectKind::GoodGoalMulti, 20.0, 0.0, z);
    let mut env =
        open_env(vec![multi(8.0), multi(11.0), ObjectSpec::new(ObjectKind::GoodGoal, 20.0, 0.0, 14.0)], 20.0, 5.0, 0.0);
    let mut rewards = Vec::new();
    for _ in 0..200 {
        let s = env.step(Action::FORWARD).unwrap().info;
        if s.good_goal {
            rewards.push((s.reward, s.terminated));
        }
        if s.terminated {
            break;
        }
    }
    let paid: Vec<(bool, bool)> = rewards.iter().map(|(r, t)| (*r > 0.9, *t)).collect();
    assert_eq!(paid, [(true, false), (true, false), (true, true)], "{rewards:?}");
    assert!(env.world().goals.iter().filter(|g| g.kind == ObjectKind::GoodGoalMulti).all(|g| g.collected));
}

#[test]
fn good_goal_multi_ends_after_the_last_and_death_zones_cost_one() {
    let multi = |x| ObjectSpec::new(ObjectKind::GoodGoalMulti, x, 0.0, 10.0);
    let mut env = open_env(
        vec![multi(20.0), ObjectSpec::new(ObjectKind::DeathZone, 20.0, 0.0, 30.0).size(10.0, 0.0, 4.0)],
        20.0,
        5.0,
        0.0,
    );
    let mut total = 0.0;
    let mut goal_steps = 0;
    for _ in 0..100 {
        let s = env.step(Action::FORWARD).unwrap().info;
        total += s.reward;
        if s.good_goal {
            goal_steps += 1;
            assert!(!s.terminated || env.world().goals.iter().all(|g| g.collected));
        }
        if s.terminated {
            break;
        }
    }
    assert_eq!(goal_steps, 1);
    assert!(env.is_over(), "the last GoodGoalMulti ends the episode");
    assert!(total > 0.9);
    // Death zone straight ahead: -1 and the end.
    let mut env =
        open_env(vec![ObjectSpec::new(ObjectKind::DeathZone, 20.0, 0.0, 12.0).size(10.0, 0.0, 4.0)], 20.0, 5.0, 0.0);
    let mut last = 0.0;
    for _ in 0..100 {
        let s = env.step(Action::FORWARD).unwrap();
        last = s.reward;
        if s.terminated {
            break;
        }
    }
    assert!(env.is_over());
    assert!((last - (-1.0 - 0.001)).abs() < 1e-12, "{last}");
}

#[test]
fn layouts_cycle_in_an_order_shuffled_once_per_seed() {
    let mut env = Env::new(EnvConfig::new(Task::preset("double-t-maze").unwrap()), 11).unwrap();
    let mut names = vec![env.layout_name().to_string()];
    for _ in 0..7 {
        env.reset(None);
        names.push(env.layout_name().to_string());
    }
    let mut first4 = names[..4].to_vec();
    first4.sort();
    assert_eq!(first4, ["corner-1", "corner-2", "corner-3", "corner-4"]);
    assert_eq!(names[..4], names[4..], "the order repeats");
    let starts: Vec<Vec2> = (0..4)
        .map(|_| {
            env.reset(None);
            env.world().agent.pos
        })
        .collect();
    assert!(starts.iter().all(|p| [3.0, 37.0].contains(&p.x) && [3.0, 37.0].contains(&p.y)));
    // Same seed, same everything.
    let a = Env::new(EnvConfig::new(Task::preset("double-t-maze").unwrap()), 11).unwrap();
    assert_eq!(a.layout_name(), names[0]);
    assert_eq!(
        a.world(),
        &Env::new(EnvConfig::new(Task::preset("double-t-maze").unwrap()), 11).unwrap().world().clone()
    );
}

#[test]
fn actions_and_limits_are_validated() {
    assert!(Action::new(9).unwrap_err().to_string().contains("action"));
    assert_eq!(Action::from_branches(1, 2).unwrap().index(), 5);
    assert!(Action::from_branches(3, 0).is_err());
    let mut cfg = EnvConfig::new(Task::preset("detour").unwrap());
    cfg.t = Some(10_000_000);
    let e = Env::new(cfg, 1).unwrap_err();
    assert_eq!(e.field, "t");
    assert!(e.message.contains("0..=100000"));
    assert!(Task::preset("nope").unwrap_err().message.contains("double-t-maze"));
    let mut env = open_env(vec![], 5.0, 5.0, 0.0);
    assert_eq!(env.step_held(Action::FORWARD, 0).unwrap_err().field, "k");
    let s = env.step_held(Action::FORWARD, 4).unwrap();
    assert_eq!(s.info.env_steps, 4);
    assert!((s.reward + 0.004).abs() < 1e-12);
    assert_eq!(env.steps(), 4);
}

#[test]
fn a_hot_zone_costs_ten_times_the_time_penalty_and_does_not_end_the_episode() {
    let zone = ObjectSpec::new(ObjectKind::HotZone, 20.0, 0.0, 20.0).size(6.0, 0.0, 6.0);
    let mut env = open_env(vec![zone], 20.0, 20.0, 0.0);
    let s = env.step(Action::NOOP).unwrap();
    // -1/t for the step plus min(10 * -1/(3t), -1e-5) in each of its 3 frames.
    let want = -0.001 + 3.0 * (-10.0 / 3000.0);
    assert!((s.reward - want).abs() < 1e-12, "{} vs {want}", s.reward);
    assert!(!s.terminated && !s.truncated);
}

/// v1's lights (beyretb/AnimalAI-Environment, `TrainEnv/Scripts/Lights.cs` `LightsSwitch`, read by
/// `Scripts/Agent.cs` `SendInfoToBrain` at each decision, every 3 frames: one env step): the list's
/// entries are env steps where the light switches, off first; a lone negative -n switches every n
/// steps; only the list's strictly increasing head switches (the enumerator waits for equality).
#[test]
fn blackouts_switch_the_light_at_v1s_steps() {
    use sec_playground::arena::Blackouts;
    let dark = |b: &[i32], upto: u32| -> Vec<u32> { (0..upto).filter(|&s| !Blackouts(b.to_vec()).lit(s)).collect() };
    assert_eq!(dark(&[5, 10], 20), (5..10).collect::<Vec<_>>());
    assert_eq!(dark(&[5, 10, 15, 20, 25], 30), [5, 6, 7, 8, 9, 15, 16, 17, 18, 19, 25, 26, 27, 28, 29]);
    assert_eq!(dark(&[-20], 90), (20..40).chain(60..80).collect::<Vec<_>>());
    assert_eq!(dark(&[0, 50], 60), (0..50).collect::<Vec<_>>());
    assert_eq!(dark(&[15, 10, 60], 80), (15..80).collect::<Vec<_>>(), "10 is never reached after 15");
    assert!(dark(&[], 100).is_empty());
}

#[test]
fn the_camera_is_black_while_the_light_is_off() {
    let src = "!ArenaConfig\narenas:\n  0: !Arena\n    t: 100\n    blackouts: [3, 6]\n    items:\n\
        \x20   - !Item\n      name: GoodGoal\n      positions:\n      - !Vector3 {x: 20, y: 0, z: 35}\n\
        \x20   - !Item\n      name: Agent\n      positions:\n      - !Vector3 {x: 20, y: 0, z: 5}\n      rotations: [0]\n";
    let task = sec_playground::arena::yaml::load_task("lights", src).unwrap();
    let mut env = Env::new(EnvConfig::new(task), 1).unwrap();
    let black = |env: &mut Env| env.observation().rgba.chunks_exact(4).all(|p| p == [0, 0, 0, 255]);
    let mut seen = vec![black(&mut env)];
    let mut serials = vec![env.view_serial()];
    for _ in 0..8 {
        env.step(Action::new(0).unwrap()).unwrap();
        seen.push(black(&mut env));
        serials.push(env.view_serial());
    }
    assert_eq!(seen, [false, false, false, true, true, true, false, false, false], "black at env steps 3, 4, 5");
    // Standing still, the view changes only where the light switches.
    assert!(serials[3] != serials[2] && serials[6] != serials[5] && serials[2] == serials[1], "{serials:?}");
}

/// The agent's bottom height after each physics frame of a fall from rest at `from` to `to`, as
/// Unity integrates a rigid body (docs/ARENAS.md section 3): gravity 9.81 m/s^2 first, then the
/// drag of 2 (a factor 1 - 2 x 0.02 per 0.02 s frame), then the move; it lands without a bounce.
fn unity_fall(from: f32, to: f32) -> Vec<f32> {
    let (mut y, mut v, mut out) = (from, 0.0f32, Vec::new());
    while y > to {
        v = (v - 9.81 * 0.02) * (1.0 - 2.0 * 0.02);
        y = (y + v * 0.02).max(to);
        out.push(y);
    }
    out
}

#[test]
fn an_agent_placed_on_a_platform_stands_on_it_and_falls_when_it_walks_off() {
    // A 1-high platform 2 wide along z; the agent placed 1 high on it (v1's files write y = 1
    // for an agent on a platform the config makes 1 high, which SIZE_ADJUST makes 0.999).
    let platform = ObjectSpec::new(ObjectKind::Wall, 20.0, 0.0, 20.0).size(2.0, 1.0, 30.0);
    let mut env = raised_env(vec![platform], 20.0, 1.0, 10.0, 90.0);
    env.step(Action::NOOP).unwrap();
    let top = env.world().walls[0].top();
    assert_eq!(env.world().agent.y, top, "it lands on the top, {top} high");
    assert!(env.world().agent.grounded);
    // Forward (east, +x) off the 1 m half-width: it falls as a Unity body does, frame by frame.
    let mut heights = Vec::new();
    let mut left = None;
    for step in 0..40 {
        env.step(Action::FORWARD).unwrap();
        let a = &env.world().agent;
        if left.is_none() && a.y < top {
            left = Some(step);
        }
        if left.is_some() {
            heights.push(a.y);
        }
        if a.y == 0.0 {
            break;
        }
    }
    assert!(left.is_some(), "it walked off the platform");
    let a = &env.world().agent;
    assert!(a.y == 0.0 && a.grounded && a.vy == 0.0, "it lands on the floor: {a:?}");
    assert!(a.pos.x >= 21.0 + AGENT_RADIUS - 1e-3, "clear of the platform's side: {}", a.pos.x);
    // 3 frames a step: the fall's last frame is Unity's, and it takes as many frames to within a step.
    let unity = unity_fall(top, 0.0);
    let frames = heights.len() * 3;
    assert!(unity.len().abs_diff(frames) <= 3, "fell in {frames} frames; Unity's body in {}", unity.len());
}

#[test]
fn a_raised_wall_is_placed_where_another_box_spans_other_heights_and_falls_onto_it() {
    // v1's spawn check is a 3-D box overlap: a box above another (a gap between them) is free;
    // the walls are rigid bodies, so it then falls onto the one under it.
    let low = ObjectSpec::new(ObjectKind::Wall, 10.0, 0.0, 10.0).size(4.0, 1.0, 4.0);
    let high = ObjectSpec::new(ObjectKind::Wall, 10.0, 3.0, 10.0).size(2.0, 1.0, 2.0);
    let env = open_env(vec![low.clone(), high], 30.0, 30.0, 0.0);
    let w = env.world();
    assert_eq!(w.walls.len(), 2);
    assert_eq!(w.walls[1].base, w.walls[0].top(), "it rests on the low box");
    assert_eq!((w.colliders[1].bottom, w.colliders[1].top), (w.walls[1].base, w.walls[1].top()));
    // The same box at a height the low one spans overlaps it: refused as v1 leaves it out.
    let clash = ObjectSpec::new(ObjectKind::Wall, 10.0, 0.5, 10.0).size(2.0, 1.0, 2.0);
    let layout = Layout {
        name: "clash".into(),
        t: 1000,
        objects: vec![low, clash],
        agent: AgentSpec { position: [Some(30.0), Some(30.0)], y: 0.0, rotation: Some(0.0) },
        blackouts: Default::default(),
    };
    assert!(sec_playground::arena::World::check_room(&layout).is_err());
}

#[test]
fn a_goal_over_a_box_rests_on_its_top_and_the_agent_walks_under_a_raised_box() {
    // A goal dropped over a 2-high box comes to rest on its top.
    let box_ = ObjectSpec::new(ObjectKind::Wall, 10.0, 0.0, 10.0).size(3.0, 2.0, 3.0);
    let goal = ObjectSpec::new(ObjectKind::GoodGoal, 10.0, 5.0, 10.0).size(1.0, 1.0, 1.0);
    // A bridge deck resting on two pillars 2 high: the agent (1 high) passes under it.
    let pillars = [6.0f32, 14.0].map(|x| ObjectSpec::new(ObjectKind::Wall, x, 0.0, 30.0).size(1.0, 2.0, 1.0));
    let deck = ObjectSpec::new(ObjectKind::Wall, 10.0, 2.0, 30.0).size(9.0, 0.5, 1.0);
    let mut objects = vec![box_, goal];
    objects.extend(pillars);
    objects.push(deck);
    let mut env = open_env(objects, 10.0, 26.0, 0.0);
    for _ in 0..60 {
        env.step(Action::NOOP).unwrap();
    }
    let w = env.world();
    let g = &w.goals[0];
    assert!(g.resting, "the goal came to rest");
    assert!((g.centre.y - (w.walls[0].top() + g.radius)).abs() < 1e-6, "on the box: {}", g.centre.y);
    assert!(w.walls[3].base > 1.0, "the deck stays on its pillars: {}", w.walls[3].base);
    // Forward (+z) under the deck at z = 30: nothing stops it.
    for _ in 0..12 {
        env.step(Action::FORWARD).unwrap();
    }
    assert!(env.world().agent.pos.y > 31.0, "it passed under the deck: {}", env.world().agent.pos.y);
}

#[test]
fn a_zone_under_a_platform_does_not_touch_the_agent_on_it() {
    let platform = ObjectSpec::new(ObjectKind::Wall, 20.0, 0.0, 20.0).size(4.0, 1.0, 4.0);
    let zone = ObjectSpec::new(ObjectKind::DeathZone, 30.0, 0.0, 30.0).size(4.0, 0.0, 4.0);
    let mut env = raised_env(vec![platform, zone], 20.0, 1.0, 20.0, 0.0);
    env.step(Action::NOOP).unwrap();
    // Moved over the zone while standing 0.999 high (as on an invisible shelf), no death.
    let a = &mut env.world_mut().agent;
    a.pos = Vec2::new(30.0, 30.0);
    let out = env.step(Action::NOOP).unwrap();
    assert!(!out.terminated, "not in the zone while above it");
}

#[test]
fn a_bouncing_goal_is_launched_at_v1s_speed_rolls_and_bounces_off_the_fence() {
    // `BallGoalBounce.Start`: AddForce(forceToApply 500 x forward x fixedDeltaTime 0.02,
    // VelocityChange) = 10 m/s along its rotation (90: +x).
    let ball = ObjectSpec::new(ObjectKind::GoodGoalBounce, 10.0, 0.0, 30.0).size(1.0, 1.0, 1.0).rotation(90.0);
    let mut env = open_env(vec![ball], 20.0, 5.0, 0.0);
    let g = env.world().goals[0].clone();
    assert_eq!(g.kind, ObjectKind::GoodGoal, "it pays and looks as a GoodGoal");
    assert_eq!((g.vel, g.launch.map(|d| d.round())), (Vec2::ZERO, Some(Vec2::X)), "launched as it starts");
    // One env step: launched in the first frame (in the air: it spawns 0.01 up), then at most two
    // frames of the floor's friction, 0.3 x 9.81 x 0.02 = 0.0589 m/s each.
    env.step(Action::NOOP).unwrap();
    let v = env.world().goals[0].vel;
    assert!(v.x <= 10.0 && v.x >= 10.0 - 2.0 * 0.0589 - 1e-4 && v.y.abs() < 1e-5, "launched at 10 m/s: {v:?}");
    // Sliding on the floor (friction 0.3) until its spin catches up: a solid sphere then rolls
    // at 5/7 of its speed.
    let mut rolled = None;
    for _ in 0..30 {
        env.step(Action::NOOP).unwrap();
        let g = &env.world().goals[0];
        if g.vel == g.spin && g.vel.x > 0.0 {
            rolled.get_or_insert(g.vel.x);
        }
    }
    let rolling = rolled.expect("it rolls");
    assert!((rolling - 10.0 * 5.0 / 7.0).abs() < 0.15, "rolls at {rolling}, 5/7 of 10 is 7.14");
    // At the fence (x = 40) its speed reverses at bounciness 0.8 (combined by maximum).
    let (mut before, mut after) = (0.0, 0.0);
    for _ in 0..200 {
        let v = env.world().goals[0].vel.x;
        env.step(Action::NOOP).unwrap();
        after = env.world().goals[0].vel.x;
        if v > 0.0 && after < 0.0 {
            before = v;
            break;
        }
    }
    assert!(before > 6.0, "it reached the fence rolling");
    // Within the step, friction against its spin (still forward) takes at most 0.06 m/s a frame.
    assert!((after + 0.8 * before).abs() < 0.2, "{before} came back at {after}, not -0.8 x");
    let g = &env.world().goals[0];
    assert!(g.centre.x <= 40.0 - g.radius && !g.resting);
}

#[test]
fn a_bouncing_goal_bounces_off_a_wall_and_pays_when_touched() {
    // Launched at a wall 5 m away (rotation 0: +z); the agent waits where it comes back.
    let ball = ObjectSpec::new(ObjectKind::BadGoalBounce, 20.0, 0.0, 20.0).size(2.0, 2.0, 2.0).rotation(0.0);
    let wall = ObjectSpec::new(ObjectKind::Wall, 20.0, 0.0, 26.0).size(10.0, 3.0, 1.0);
    let mut env = open_env(vec![ball, wall], 20.0, 10.0, 0.0);
    let mut turned = false;
    let mut paid = None;
    for _ in 0..200 {
        let (terminated, reward) = {
            let o = env.step(Action::NOOP).unwrap();
            (o.terminated, o.reward)
        };
        let g = &env.world().goals[0];
        turned |= g.vel.y < 0.0;
        assert!(g.centre.z + g.radius <= 25.5 + 1e-3, "never inside the wall: {}", g.centre.z);
        if terminated {
            paid = Some(reward);
            break;
        }
    }
    assert!(turned, "it came back off the wall");
    let reward = paid.expect("it reached the agent");
    assert!((reward - (-2.0 * 0.999 - 1.0 / 1000.0)).abs() < 1e-9, "a bad goal of size 2: {reward}");
}

#[test]
fn the_agent_climbs_a_ramp_onto_the_platform_it_leads_to_and_not_its_high_face() {
    // v1's Ramp rises towards its local -z (its mesh; docs/ARENAS.md section 5): turned 180, a
    // 2 m ramp over z 15-25 rises northwards onto a 2 m platform over z 25-35.
    let platform = ObjectSpec::new(ObjectKind::Wall, 20.0, 0.0, 30.0).size(6.0, 2.0, 10.0).rotation(0.0);
    let ramp = ObjectSpec::new(ObjectKind::Ramp, 20.0, 0.0, 20.0).size(6.0, 2.0, 10.0).rotation(180.0);
    let mut env = open_env(vec![platform.clone(), ramp], 20.0, 8.0, 0.0);
    let mut on_slope = Vec::new();
    for _ in 0..40 {
        env.step(Action::FORWARD).unwrap();
        let a = &env.world().agent;
        if a.pos.y > 16.0 && a.pos.y < 24.0 {
            on_slope.push((a.pos.y, a.y));
        }
        if a.pos.y > 27.0 {
            break;
        }
    }
    let a = &env.world().agent;
    let top = env.world().walls[0].top();
    assert!(a.pos.y > 27.0 && a.y == top && a.grounded, "onto the platform: {a:?}");
    // On the slope it stands on the surface: 0.2 m up per metre from z 15.005.
    for (z, y) in on_slope {
        assert!((y - (z - 15.005) * 0.2).abs() < 0.1, "at z {z} the slope is {}, the agent {y}", (z - 15.005) * 0.2);
    }
    // From the other side its 2 m high face is a wall: facing south from z 12, held back.
    let back = ObjectSpec::new(ObjectKind::Ramp, 20.0, 0.0, 20.0).size(6.0, 2.0, 10.0).rotation(0.0);
    let mut env = open_env(vec![back], 20.0, 8.0, 0.0);
    for _ in 0..30 {
        env.step(Action::FORWARD).unwrap();
    }
    let a = &env.world().agent;
    assert!(a.y == 0.0 && a.pos.y <= 15.005 - AGENT_RADIUS + 1e-3, "stopped by the high face: {a:?}");
}

#[test]
fn a_goal_on_an_olympics_ramp_rolls_down_towards_the_agent() {
    // 02-21-01 (preferences): a 3 m goal dropped on the low end of a ramp turned 180 over a
    // platform; its high end is north, so the goal rolls south, off the platform, to the agent's
    // side: how the arena is meant to be solved.
    let src = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/arenas/competition/02-21-01.yaml"))
        .unwrap();
    let task = sec_playground::arena::yaml::load_task("02-21-01.yaml", &src).unwrap();
    let mut env = Env::new(EnvConfig::new(task), 1).unwrap();
    let z0 = env.world().goals[0].centre.z;
    let mut fastest = 0.0f32;
    for _ in 0..100 {
        env.step(Action::NOOP).unwrap();
        fastest = fastest.max(-env.world().goals[0].vel.y);
    }
    let g = &env.world().goals[0];
    assert!(g.centre.z < 5.0 && z0 > 8.0, "rolled south off the ramp: z {z0} -> {}", g.centre.z);
    assert!((g.centre.y - g.radius).abs() < 1e-4, "down on the floor: {}", g.centre.y);
    // A solid sphere rolling down a slope of 2 m in 35 accelerates at 5/7 g sin(a) cos(a)
    // horizontally: over the 4 m it rolls on the ramp, about 1.2 m/s.
    assert!(fastest > 0.8, "{fastest}");
}

#[test]
fn up_a_slope_the_speed_follows_v1s_push_friction_and_drag_less_gravity_along_it() {
    // Straight up a 3 m ramp 30 m long (rise 0.1): per frame, gravity along the slope first
    // (g sin a cos a = 9.81 x 0.1 / 1.01 m/s^2 horizontally), then v1's push (+1.0 m/s), its
    // friction (-0.6 x 9.81 x 0.02) and its drag (x 0.96), as on the flat (docs/ARENAS.md section 3).
    let ramp = ObjectSpec::new(ObjectKind::Ramp, 20.0, 0.0, 20.0).size(6.0, 3.0, 30.0).rotation(180.0);
    let mut env = open_env(vec![ramp], 20.0, 2.0, 0.0);
    let slope = 9.81 * 0.1 / (1.0 + 0.01) * 0.02;
    let mut checked = 0;
    let mut before: Option<f32> = None;
    for _ in 0..30 {
        env.step(Action::FORWARD).unwrap();
        let a = &env.world().agent;
        let on = a.y > 0.3 && a.pos.y < 33.0;
        if let (Some(v), true) = (before, on) {
            let want = (0..3).fold(v, |v, _| 0.96 * (v - slope + 1.0 - 0.6 * 9.81 * 0.02));
            assert!((a.vel.y - want).abs() / want < 0.005, "{v} -> {}, expected {want}", a.vel.y);
            checked += 1;
        }
        before = on.then_some(a.vel.y);
    }
    assert!(checked >= 2, "{checked} steps checked on the slope");
}

/// A pushable box of `kind`, `size` on a side, at (x, z), unrotated.
fn cardbox(kind: ObjectKind, x: f32, z: f32, size: f32) -> ObjectSpec {
    ObjectSpec::new(kind, x, 0.0, z).size(size, size, size).rotation(0.0)
}

/// Holds forward for `steps` env steps; the first pushable box's centre after.
fn push_for(env: &mut Env, steps: usize) -> Vec2 {
    for _ in 0..steps {
        env.step(Action::FORWARD).unwrap();
    }
    env.world().pushed[0].pose.centre
}

#[test]
fn the_agent_pushes_a_box_and_never_passes_through_it() {
    // A 1 m Cardbox1 2.5 m ahead; held forward, the agent pushes it along +z.
    let mut env = open_env(vec![cardbox(ObjectKind::Cardbox1, 20.0, 12.5, 1.0)], 20.0, 10.0, 0.0);
    let start = env.world().pushed[0].pose.centre;
    for _ in 0..30 {
        env.step(Action::FORWARD).unwrap();
        let w = env.world();
        let b = &w.pushed[0].parts[0];
        let l = b.foot.to_local(w.agent.pos);
        let gap = (l - l.clamp(-b.foot.half, b.foot.half)).length();
        assert!(gap > AGENT_RADIUS - 0.02, "the agent is {gap} m from the box's side: inside it");
    }
    let end = env.world().pushed[0].pose.centre;
    assert!(end.y - start.y > 5.0, "pushed {} m", end.y - start.y);
    assert!((end.x - start.x).abs() < 0.5, "pushed straight: x moved {} m", end.x - start.x);
    // It rests on the floor, and stays where the push left it.
    assert!(env.world().pushed[0].base().abs() < 1e-3);
}

#[test]
fn a_heavier_box_is_pushed_less_far() {
    // v1's prefabs: Cardbox1 has mass 1, Cardbox2 mass 2 (docs/ARENAS.md section 5).
    assert_eq!((ObjectKind::Cardbox1.mass(), ObjectKind::Cardbox2.mass()), (Some(1.0), Some(2.0)));
    let moved = |kind| {
        let mut env = open_env(vec![cardbox(kind, 20.0, 12.5, 2.0)], 20.0, 10.0, 0.0);
        push_for(&mut env, 25).y - 12.5
    };
    let (light, heavy) = (moved(ObjectKind::Cardbox1), moved(ObjectKind::Cardbox2));
    assert!(light > heavy + 0.5 && heavy > 0.5, "Cardbox1 moved {light} m, Cardbox2 {heavy} m");
}

#[test]
fn a_box_pushed_into_a_wall_stops_at_it() {
    let wall = ObjectSpec::new(ObjectKind::Wall, 20.0, 0.0, 20.0).size(10.0, 2.0, 1.0).rotation(0.0);
    let mut env = open_env(vec![wall, cardbox(ObjectKind::Cardbox1, 20.0, 12.5, 1.0)], 20.0, 10.0, 0.0);
    let end = push_for(&mut env, 60);
    let w = env.world();
    let b = &w.pushed[0].parts[0];
    // The wall's near face is at 19.5; the box's far corner may not pass it by more than rapier's
    // contact tolerance, however long the agent pushes.
    let reach = b.foot.corners().iter().map(|c| c.y).fold(f32::MIN, f32::max);
    assert!(reach < 19.5 + 0.02 && reach > 19.0, "the box reaches z {reach}, centre {end}");
    assert!(w.agent.pos.y < end.y, "the agent stays behind the box");
}

#[test]
fn a_goal_on_a_box_falls_when_the_box_is_pushed_away() {
    // 05-13-01's trick: a goal resting on a box, which the agent knocks from under it.
    let goal = ObjectSpec::new(ObjectKind::GoodGoal, 20.0, 1.0, 13.0);
    let mut env = open_env(vec![cardbox(ObjectKind::Cardbox1, 20.0, 13.0, 1.0), goal], 20.0, 10.0, 0.0);
    env.step(Action::NOOP).unwrap();
    let resting = env.world().goals[0].centre.y;
    assert!((resting - (0.999 + 0.4995)).abs() < 0.01, "the goal rests on the box at {resting}");
    // Forward until the goal is on the floor (or touched: then the episode ends).
    let mut fell = false;
    for _ in 0..40 {
        let terminated = env.step(Action::FORWARD).unwrap().terminated;
        let y = env.world().goals[0].centre.y;
        if terminated || (y - 0.4995).abs() < 0.01 {
            fell = true;
            break;
        }
    }
    assert!(fell, "the goal stayed at {} m", env.world().goals[0].centre.y);
}

#[test]
fn a_u_object_has_its_prefabs_three_boxes() {
    // v1's UObject prefab (beyretb/AnimalAI-Environment, TrainEnv/Prefab/Movable/UObject.prefab):
    // a bar of 0.99 x 10 at the pivot and arms of 3 x 1 at (1, +-5), scaled by ratioSize
    // (0.3, 1, 0.1) per unit of size, the prefab turned 90 degrees, mass 3, friction 0.5.
    assert_eq!((ObjectKind::UObject.mass(), ObjectKind::UObject.friction()), (Some(3.0), 0.5));
    let u = ObjectSpec::new(ObjectKind::UObject, 20.0, 0.0, 20.0).size(5.0, 1.0, 10.0).rotation(0.0);
    let env = open_env(vec![u], 5.0, 5.0, 0.0);
    let p = &env.world().pushed[0];
    assert_eq!(p.parts.len(), 3);
    let (sx, sz) = (5.0 * 0.999 * 0.3, 10.0 * 0.999 * 0.1);
    let close = |a: Vec2, b: Vec2| (a - b).length() < 1e-4;
    // Turned 90 degrees, the bar lies along world x and the arms reach towards -z.
    let bar = &p.parts[0].foot;
    assert!(close(bar.centre, Vec2::new(20.0, 20.0)) && close(bar.half, Vec2::new(0.495 * sx, 5.0 * sz)));
    for (part, side) in p.parts[1..].iter().zip([1.0, -1.0]) {
        let want = Vec2::new(20.0 + side * 5.0 * sz, 20.0 - sx);
        assert!(close(part.foot.centre, want), "arm at {}, expected {want}", part.foot.centre);
        assert!(close(part.foot.half, Vec2::new(1.5 * sx, 0.5 * sz)));
    }
    assert!(p.parts.iter().all(|b| b.colour == sec_playground::arena::WOOD && (b.height - 0.999).abs() < 1e-6));
    // The L keeps the bar and the arm at -5; its mirror has the arm on the other side.
    let l = |kind| {
        let spec = ObjectSpec::new(kind, 20.0, 0.0, 20.0).size(5.0, 1.0, 10.0).rotation(0.0);
        open_env(vec![spec], 5.0, 5.0, 0.0).world().pushed[0].parts[1].foot.centre
    };
    assert!(close(l(ObjectKind::LObject), Vec2::new(20.0 - 5.0 * sz, 20.0 - sx)));
    assert!(close(l(ObjectKind::LObject2), Vec2::new(20.0 - 5.0 * sz, 20.0 + sx)));
}

#[test]
fn a_pushed_u_object_pushes_the_goal_in_its_mouth() {
    // Category 10's trick: the goal sits where the agent may not go, in the U's mouth; pushing
    // the U's bar moves the goal. The U turned 180 in the file opens towards +z, its bar at z 15.
    let u = ObjectSpec::new(ObjectKind::UObject, 20.0, 0.0, 15.0).size(5.0, 1.0, 10.0).rotation(180.0);
    let goal = ObjectSpec::new(ObjectKind::GoodGoal, 20.0, 0.0, 17.0);
    let mut env = open_env(vec![u, goal], 20.0, 10.0, 0.0);
    let start = env.world().goals[0].centre;
    for _ in 0..40 {
        let step = env.step(Action::FORWARD).unwrap();
        assert!(!step.terminated, "the agent reached the goal through the U's bar");
    }
    let w = env.world();
    let end = w.goals[0].centre;
    assert!(end.z - start.z > 2.0, "the goal moved from {start} to {end}");
    assert!(w.pushed[0].pose.centre.y > 16.0, "the U's pivot is at {}", w.pushed[0].pose.centre);
    assert!(w.agent.pos.y < w.pushed[0].pose.centre.y, "the agent stays behind the bar");
}

#[test]
fn an_l_object_pushed_at_one_end_turns() {
    // One rigid body: pushed on its bar away from its centre of mass, it turns as well as slides.
    let l = ObjectSpec::new(ObjectKind::LObject, 20.0, 0.0, 15.0).size(5.0, 1.0, 10.0).rotation(0.0);
    let mut env = open_env(vec![l], 23.0, 10.0, 0.0);
    let before = env.world().pushed[0].pose;
    for _ in 0..30 {
        env.step(Action::FORWARD).unwrap();
    }
    let after = env.world().pushed[0].pose;
    let turned = libm::atan2f(after.sin, after.cos) - libm::atan2f(before.sin, before.cos);
    assert!(turned.abs() > 0.05, "turned {turned} rad");
    assert!(after.centre.y > before.centre.y + 0.5, "moved from {} to {}", before.centre, after.centre);
}

#[test]
fn no_preset_task_has_a_pushable_box() {
    // So none builds rigid bodies (the env builds them only for a layout with pushable boxes):
    // rapier is never called, and their goldens cannot move.
    for name in sec_playground::arena::TASK_NAMES {
        let env = Env::new(EnvConfig::new(Task::preset(name).unwrap()), 1).unwrap();
        assert!(env.world().pushed.is_empty(), "{name}");
    }
}
