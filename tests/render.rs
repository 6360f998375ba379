//! Golden images of every task's first frame, and pixel checks of what the agent must (not) see.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::arena::{Action, Task, TASK_NAMES};
use sec_playground::env::{Env, EnvConfig};
use sec_playground::render::{colours, Frame, Surface, TopDown, HEIGHT, WIDTH};
use std::path::PathBuf;

fn first_frame(task: &str) -> (Env, Frame) {
    first_frame_of(task, Surface::Flat)
}

fn first_frame_of(task: &str, surface: Surface) -> (Env, Frame) {
    let mut env = Env::new(EnvConfig { surface, ..EnvConfig::new(Task::preset(task).unwrap()) }, 1).unwrap();
    let f = env.observation().clone();
    (env, f)
}

fn golden_path(task: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden").join(format!("{task}.png"))
}

fn read_png(path: &PathBuf) -> Vec<u8> {
    let dec = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())),
    ));
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width as usize, info.height as usize), (WIDTH, HEIGHT));
    assert_eq!(info.color_type, png::ColorType::Rgba);
    buf.truncate(info.buffer_size());
    buf
}

fn write_png(path: &PathBuf, rgba: &[u8]) {
    let mut enc = png::Encoder::new(std::fs::File::create(path).unwrap(), WIDTH as u32, HEIGHT as u32);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header().unwrap().write_image_data(rgba).unwrap();
}

/// Compares with the checked-in PNGs: at most 1% of pixels may differ, none by more than 8 per
/// channel. `SEC_UPDATE_GOLDEN=1` rewrites them (look at them before committing).
#[test]
fn first_frames_match_the_golden_images() {
    let update = std::env::var("SEC_UPDATE_GOLDEN").is_ok_and(|v| v == "1");
    for task in TASK_NAMES {
        let (_, frame) = first_frame(task);
        let path = golden_path(task);
        if update {
            write_png(&path, &frame.rgba);
            continue;
        }
        let want = read_png(&path);
        let mut differing = 0;
        for (a, b) in frame.rgba.chunks_exact(4).zip(want.chunks_exact(4)) {
            let d = (0..3).map(|k| a[k].abs_diff(b[k])).max().unwrap();
            assert!(d <= 8, "{task}: a pixel differs by {d}");
            differing += (d > 0) as usize;
        }
        assert!(differing * 100 <= WIDTH * HEIGHT, "{task}: {differing} pixels differ");
    }
}

/// The textured first frames equal their checked-in PNGs exactly (`tests/golden/<task>-textured.png`;
/// the traces prove every target draws the same bits). `SEC_UPDATE_GOLDEN=1` rewrites them.
#[test]
fn textured_first_frames_match_their_golden_images_exactly() {
    let update = std::env::var("SEC_UPDATE_GOLDEN").is_ok_and(|v| v == "1");
    for task in TASK_NAMES {
        let (_, frame) = first_frame_of(task, Surface::Textured);
        let path = golden_path(&format!("{task}-textured"));
        if update {
            write_png(&path, &frame.rgba);
            continue;
        }
        assert!(read_png(&path) == frame.rgba, "{task}: the textured first frame differs from {}", path.display());
        assert!(frame != first_frame(task).1, "{task}: the textured frame is the flat one");
    }
}

/// Textures change only the floor and the fences: every pixel that is neither is the same in both
/// (in the tasks without glass, which blends over the floor and fences behind it).
#[test]
fn textures_change_the_floor_and_fences_only() {
    for task in TASK_NAMES.iter().filter(|t| !t.contains("transparent")) {
        let ((_, flat), (_, textured)) = (first_frame(task), first_frame_of(task, Surface::Textured));
        let (floor, fence) = (
            [colours::FLOOR.0, colours::FLOOR.1, colours::FLOOR.2],
            [colours::FENCE.0, colours::FENCE.1, colours::FENCE.2],
        );
        let sky = [colours::SKY.0, colours::SKY.1, colours::SKY.2];
        for r in 0..HEIGHT {
            for c in 0..WIDTH {
                let (a, b) = (flat.pixel(c, r), textured.pixel(c, r));
                // Posts stand above the panels: a textured post may cover flat sky.
                if a != floor && a != fence && a != sky {
                    assert_eq!(a, b, "{task}: pixel ({c}, {r}) changed");
                }
            }
        }
    }
}

fn count(frame: &Frame, rgb: [u8; 3], cols: std::ops::Range<usize>, rows: std::ops::Range<usize>) -> usize {
    rows.flat_map(|r| cols.clone().map(move |c| (c, r))).filter(|&(c, r)| frame.pixel(c, r) == rgb).count()
}

const GOAL: [u8; 3] = [colours::GOOD_GOAL.0, colours::GOOD_GOAL.1, colours::GOOD_GOAL.2];

#[test]
fn the_sky_is_exactly_the_v1_background() {
    let (_, f) = first_frame("detour");
    assert_eq!(f.pixel(83, 0), [49, 77, 121]);
    // Every task shows some sky above the horizon... except where a wall fills the view.
    for task in ["detour", "cylinder", "object-permanence"] {
        let (_, f) = first_frame(task);
        assert!(count(&f, [49, 77, 121], 0..WIDTH, 0..HEIGHT / 2) > 500, "{task}: no sky");
    }
}

#[test]
fn the_detour_goal_shows_above_the_low_wall_from_the_start() {
    let (env, f) = first_frame("detour");
    assert_eq!(env.world().agent.pos.y, 1.0);
    assert!(count(&f, GOAL, 0..WIDTH, 0..HEIGHT / 2) >= 1, "the goal is not visible above the horizon");
    // It lies left of the centre: bearing -7.7 degrees (docs/ARENAS.md section 7.4).
    assert_eq!(count(&f, GOAL, WIDTH / 2..WIDTH, 0..HEIGHT), 0);
    // Behind the glass the goal is tinted but still green.
    let (_, f) = first_frame("detour-transparent");
    let greenish = (0..HEIGHT)
        .flat_map(|r| (0..WIDTH / 2).map(move |c| (c, r)))
        .filter(|&(c, r)| {
            let [r_, g, b] = f.pixel(c, r);
            g as i32 > r_ as i32 + 20 && g as i32 > b as i32 + 40
        })
        .count();
    assert!(greenish >= 1, "the goal is not visible through the glass");
    // The opaque 0.5-high wall is a thin band at the horizon; behind the glass the floor is tinted.
    let (_, f) = first_frame("detour");
    let grey = f.pixel(60, HEIGHT / 2);
    assert!(grey[0] == grey[1] && grey[1] == grey[2], "wall band at the horizon is grey: {grey:?}");
}

#[test]
fn the_dropped_goal_is_visible_while_falling_and_hidden_once_landed() {
    let (mut env, f) = first_frame("object-permanence");
    // The big goal falls left of the centre, the small one is to the right.
    assert!(count(&f, GOAL, 0..WIDTH / 2, 0..HEIGHT) > 20, "the big goal is not visible at the start");
    assert!(count(&f, GOAL, WIDTH / 2..WIDTH, 0..HEIGHT) > 0, "the small goal is not visible");
    for _ in 0..40 {
        env.step(Action::NOOP).unwrap();
    }
    assert!(env.world().goals[0].resting);
    let f = env.observation().clone();
    assert_eq!(count(&f, GOAL, 0..WIDTH / 2, 0..HEIGHT), 0, "the landed goal must be hidden by the wall");
    assert!(count(&f, GOAL, WIDTH / 2..WIDTH, 0..HEIGHT) > 0, "the small goal stays visible");
}

#[test]
fn the_cylinder_goal_is_hidden_side_on_and_visible_along_the_axis() {
    let (mut env, f) = first_frame("cylinder");
    assert_eq!(count(&f, GOAL, 0..WIDTH, 0..HEIGHT), 0, "side-on, the arch hides the goal");
    // From (27, 13) looking up the axis (heading 315), the goal shows through the opening.
    {
        let a = &mut env.world_mut().agent;
        a.pos = glam::Vec2::new(27.0, 13.0);
        a.heading = 315.0;
    }
    let f = env.observation().clone();
    assert!(count(&f, GOAL, 30..54, 0..HEIGHT) > 20, "the goal is visible along the axis");
}

#[test]
fn frames_are_deterministic_and_the_top_down_view_draws_the_agent() {
    let (_, a) = first_frame("double-t-maze");
    let (env, b) = first_frame("double-t-maze");
    assert_eq!(a, b);
    let mut top = TopDown::new(210);
    top.render(env.world(), &[env.world().agent.pos]);
    let p = env.world().agent.pos;
    let (px, py) = (((p.x + 1.0) * 5.0) as usize, ((41.0 - p.y) * 5.0) as usize);
    let i = (py * 210 + px) * 4;
    let ag = colours::AGENT;
    let got = &top.rgba[i..i + 3];
    assert!(got == [ag.0, ag.1, ag.2] || got == [255, 255, 255], "agent pixel {got:?}");
    // The goal in the middle.
    let i = (105 * 210 + 105) * 4;
    assert_eq!(&top.rgba[i..i + 3], GOAL);
}

#[test]
fn a_transparent_arch_shows_the_goal_inside_tinted() {
    use sec_playground::arena::{AgentSpec, Layout, ObjectKind, ObjectSpec};
    let layout = |kind| Layout {
        name: "glass-arch".into(),
        t: 1000,
        objects: vec![
            ObjectSpec::new(kind, 20.0, 0.0, 20.0).size(10.0, 10.0, 10.0).rotation(90.0),
            ObjectSpec::new(ObjectKind::GoodGoal, 20.0, 0.0, 20.0).size(2.0, 2.0, 2.0),
        ],
        agent: AgentSpec { position: [Some(20.0), Some(5.0)], y: 0.0, rotation: Some(0.0) },
        blackouts: Default::default(),
    };
    let frame = |kind, with_goal: bool| {
        let mut l = layout(kind);
        if !with_goal {
            l.objects.pop();
        }
        let task = Task { name: "t".into(), description: String::new(), layouts: vec![l], warnings: Vec::new() };
        Env::new(EnvConfig::new(task), 1).unwrap().observation().clone()
    };
    // Side-on, the opaque arch hides the goal; the transparent one shows it through two layers,
    // tinted: greener than the same view without the goal.
    let opaque = frame(ObjectKind::CylinderTunnel, true);
    assert_eq!(count(&opaque, GOAL, 0..WIDTH, 0..HEIGHT), 0);
    let glass = frame(ObjectKind::CylinderTunnelTransparent, true);
    let empty = frame(ObjectKind::CylinderTunnelTransparent, false);
    let (c, r) = (WIDTH / 2, 40);
    let green = |p: [u8; 3]| p[1] as i32 - (p[0] as i32 + p[2] as i32) / 2;
    assert!(
        green(glass.pixel(c, r)) > green(empty.pixel(c, r)) + 20,
        "{:?} vs {:?}",
        glass.pixel(c, r),
        empty.pixel(c, r)
    );
    assert_ne!(glass.pixel(c, r), GOAL, "tinted, not the bare goal colour");
}

/// The floats of a frame are each byte divided by 255 (from a table: the same bits as the
/// division), channel-last, the alpha byte dropped.
#[test]
fn rgb_floats_are_the_bytes_over_255() {
    let mut frame = Frame::new();
    for (i, px) in frame.rgba.chunks_exact_mut(4).enumerate() {
        px.copy_from_slice(&[(i % 256) as u8, ((i * 7) % 256) as u8, (255 - i % 256) as u8, 0]);
    }
    let mut out = vec![0.0; WIDTH * HEIGHT * 3];
    frame.to_rgb_f32(&mut out);
    for (i, o) in out.chunks_exact(3).enumerate() {
        let want = [(i % 256) as u8, ((i * 7) % 256) as u8, (255 - i % 256) as u8].map(|v| v as f32 / 255.0);
        let got: Vec<u32> = o.iter().map(|v| v.to_bits()).collect();
        assert_eq!(got, want.map(f32::to_bits), "pixel {i}");
    }
}

/// The eye is at the agent's centre wherever it stands: on a platform the camera sees the
/// platform's top below it, lit from above (an eye still 0.5 above the floor would be inside the
/// box and see none of it); from the floor beside the platform it sees its side, lit less.
#[test]
fn on_a_platform_the_camera_sees_its_top_from_the_eye_height() {
    use sec_playground::arena::{AgentSpec, Layout, ObjectKind, ObjectSpec};
    let blue = (0u8, 0u8, 255u8);
    let frame = |x: f32, y: f32, heading: f32| {
        let l = Layout {
            name: "platform".into(),
            t: 1000,
            objects: vec![ObjectSpec::new(ObjectKind::Wall, 20.0, 0.0, 20.0)
                .size(4.0, 2.0, 30.0)
                .colour(blue.0, blue.1, blue.2)],
            agent: AgentSpec { position: [Some(x), Some(10.0)], y, rotation: Some(heading) },
            blackouts: Default::default(),
        };
        let task = Task { name: "t".into(), description: String::new(), layouts: vec![l], warnings: Vec::new() };
        let mut env = Env::new(EnvConfig::new(task), 1).unwrap();
        env.step(sec_playground::arena::Action::NOOP).unwrap();
        (env.world().agent.y, env.observation().clone())
    };
    let is_blue = |p: [u8; 3]| p[2] > 100 && p[0] < 40 && p[1] < 40;
    // Standing on it, looking along it (+z): the bottom rows are its top, bright.
    let (y, on) = frame(20.0, 2.0, 0.0);
    assert!((y - 1.998).abs() < 1e-6, "on the top: {y}");
    let top = on.pixel(WIDTH / 2, HEIGHT - 1);
    assert!(is_blue(top), "{top:?}");
    // From the floor 3 m east, looking west at it: its side, darker than its top.
    let (_, beside) = frame(25.0, 0.0, 270.0);
    let side = beside.pixel(WIDTH / 2, HEIGHT / 2 + 5);
    assert!(is_blue(side) && side[2] < top[2], "side {side:?}, top {top:?}");
}
