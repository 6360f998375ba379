//! The Animal-AI YAML loader: the v1 files load into the same worlds as the presets, and bad
//! files are refused with the line and the field.
#![cfg(not(target_arch = "wasm32"))]

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use sec_playground::arena::yaml::load_task;
use sec_playground::arena::{Layout, Task, World};

const TMAZE: &str = include_str!("../assets/arenas/sec_doubletmaze_corner1.yaml");
const DETOUR: &str = include_str!("../assets/arenas/v1_3-4-1.yml");
const GLASS: &str = include_str!("../assets/arenas/v1_3-5-1.yml");
const CYLINDER: &str = include_str!("../assets/arenas/v1_3-13-1.yml");
const PERMANENCE: &str = include_str!("../assets/arenas/v1_8-7-1.yml");

fn one(name: &str, src: &str) -> Layout {
    let t = load_task(name, src).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(t.layouts.len(), 1);
    t.layouts.into_iter().next().unwrap()
}

/// Same objects and agent, and the same spawned world from the same generator state.
fn assert_same_world(from_file: &Layout, preset: &Layout) {
    assert_eq!(from_file.objects, preset.objects);
    assert_eq!(from_file.agent, preset.agent);
    let a = World::spawn(from_file, &mut ChaCha8Rng::seed_from_u64(3));
    let b = World::spawn(preset, &mut ChaCha8Rng::seed_from_u64(3));
    assert_eq!(a, b);
}

#[test]
fn the_v1_files_give_the_preset_worlds() {
    // Detour, transparent detour and object permanence: identical but for t (250 in the files,
    // the project's 1000 in the presets).
    for (name, src, preset, k) in [
        ("3-4-1", DETOUR, "detour", 0),
        ("3-5-1", GLASS, "detour-transparent", 0),
        ("8-7-1", PERMANENCE, "object-permanence", 0),
    ] {
        let l = one(name, src);
        assert_eq!(l.t, 250);
        assert_same_world(&l, &Task::preset(preset).unwrap().layouts[k]);
    }
    // The T-maze generator's corner 1, with its random heading filled as 0 in the file.
    let l = one("tmaze", TMAZE);
    assert_eq!(l.t, 1000);
    let mut preset = Task::preset("double-t-maze").unwrap().layouts[0].clone();
    assert_eq!(preset.agent.rotation, None, "the preset draws the heading");
    preset.agent.rotation = Some(0.0);
    assert_same_world(&l, &preset);
    // 3-13-1 has a size-1 goal; SEC's cylinder (and the preset) uses size 2.
    let mut l = one("3-13-1", CYLINDER);
    assert_eq!(l.objects[1].size, [Some(1.0); 3]);
    l.objects[1].size = [Some(2.0), Some(1.0), Some(1.0)];
    assert_same_world(&l, &Task::preset("cylinder").unwrap().layouts[0]);
}

fn err(src: &str) -> sec_playground::FileError {
    load_task("bad", src).unwrap_err()
}

#[test]
fn bad_files_name_the_line_and_the_field() {
    let unknown = DETOUR.replace("name: GoodGoal", "name: Pillar");
    let e = err(&unknown);
    assert_eq!(e.file, "arena", "a file error");
    assert_eq!(e.line, Some(20), "{e}");
    assert_eq!(e.field, "arenas.0.items[1].name");
    assert!(e.message.contains("unknown item 'Pillar'"), "{e}");

    // A size outside its object's range is clamped, as v1 does (beyretb/AnimalAI-Environment,
    // `TrainEnv/Prefab/Scripts/Prefab.cs` `SetSize`), and the task says so; one that is not a
    // number is still refused.
    let too_big = DETOUR.replace("{x: 35, y: .5, z: 1}", "{x: 45, y: 12, z: 1}");
    let t = load_task("big", &too_big).unwrap();
    assert_eq!(t.layouts[0].objects[0].size, [Some(40.0), Some(10.0), Some(1.0)]);
    assert_eq!(t.warnings.len(), 2, "{:?}", t.warnings);
    assert!(
        t.warnings[1]
            .starts_with("line 14: arenas.0.items[0].sizes[0].y: 12 is outside 0.1..=10 for a Wall; clamped to 10"),
        "{:?}",
        t.warnings
    );
    assert!(load_task("detour", DETOUR).unwrap().warnings.is_empty());
    // A goal's size is its x: y and z are clamped too, without a word (v1 ignores them).
    let ball = load_task("ball", &DETOUR.replace("{x: 1, y: 1, z: 1}", "{x: 1, y: 8, z: 8}")).unwrap();
    assert!(ball.warnings.is_empty(), "{:?}", ball.warnings);
    assert_eq!(ball.layouts[0].objects[2].size, [Some(1.0), Some(5.0), Some(5.0)]);
    let e = err(&DETOUR.replace("{x: 35, y: .5, z: 1}", "{x: 35, y: tall, z: 1}"));
    assert_eq!((e.line, e.field.as_str()), (Some(14), "arenas.0.items[0].sizes[0].y"), "{e}");
    assert!(e.message.contains("'tall' is not a number"), "{e}");

    let e = err(&DETOUR.replace("      rotations: [0,0]\n", "      rotations: [0,0]\n      colour: 3\n"));
    assert_eq!(e.field, "arenas.0.items[0].colour");
    assert!(e.message.contains("unknown field"));

    let e = err("!ArenaConfig\narenas:\n  0: !Arena\n    t: 250\n    items: [\n");
    assert_eq!(e.field, "yaml");
    assert!(e.line.is_some(), "{e}");

    let e = err(&DETOUR.replace("t: 250", "t: 2.5"));
    assert_eq!((e.line, e.field.as_str()), (Some(5), "arenas.0.t"));

    let e = err(&DETOUR.replace("{x: 5, y: 0, z: 38}", "{x: 45, y: 0, z: 38}"));
    assert_eq!(e.field, "arenas.0.items[1].positions[0].x");
    assert!(e.message.contains("0..=40"), "{e}");

    let e = err(&DETOUR.replace("{x: 5, y: 0, z: 38}", "{x: 5, y: 0}"));
    assert_eq!(e.field, "arenas.0.items[1].positions[0].z");

    let e = err(&DETOUR.replace("t: 250", "t: 250\n    blackouts: [5, -20]"));
    assert_eq!(e.field, "arenas.0.blackouts[1]");
    assert!(e.message.contains("must be the list's only entry"), "{e}");
    let e = err(&DETOUR.replace("t: 250", "t: 250\n    blackouts: [5.5]"));
    assert!(e.message.contains("whole number"), "{e}");
    let lit = load_task("lit", &DETOUR.replace("t: 250", "t: 250\n    blackouts: [-20]")).unwrap();
    assert_eq!(lit.layouts[0].blackouts.0, [-20]);

    assert_eq!(err("").field, "yaml");
    assert_eq!(err("arenas: 3").field, "arenas");
}

#[test]
fn random_values_and_several_arenas() {
    let src = "!ArenaConfig\narenas:\n  0: !Arena\n    t: 100\n    items:\n    - !Item\n      name: GoodGoal\n      positions: [!Vector3 {x: -1, y: 0, z: -1}]\n  1: !Arena\n    t: 0\n    items: []\n";
    let t = load_task("mine", src).unwrap();
    assert_eq!(t.layouts.len(), 2);
    assert_eq!(t.layouts[0].name, "mine#0");
    assert_eq!(t.layouts[0].objects[0].position, [None, Some(0.0), None]);
    assert_eq!(t.layouts[1].agent.position, [None, None]);
    let a = World::spawn(&t.layouts[0], &mut ChaCha8Rng::seed_from_u64(1));
    let b = World::spawn(&t.layouts[0], &mut ChaCha8Rng::seed_from_u64(2));
    assert_ne!(a.goals[0].centre, b.goals[0].centre, "-1 draws a position per seed");
    let g = a.goals[0].centre;
    assert!((0.0..=40.0).contains(&g.x) && (0.0..=40.0).contains(&g.z));
}

/// Issue 20's reproducers: a deeply nested file, an arena of 10,000 random walls, a huge name.
#[test]
fn hostile_files_are_refused_quickly_with_the_line_and_field() {
    use sec_playground::arena::yaml::{MAX_DEPTH, MAX_OBJECTS};
    for deep in [
        format!("arenas:\n  0: !Arena\n    items:\n    {}x\n", "- ".repeat(20_000)),
        format!("arenas: {}{}", "[".repeat(20_000), "]".repeat(20_000)),
        format!("arenas: {}", "{a: ".repeat(5_000)),
    ] {
        let e = err(&deep);
        assert_eq!(e.field, "yaml", "{e}");
        // Our depth limit, or the scanner's own on flow collections.
        let refused = e.message.contains(&format!("deeper than {MAX_DEPTH}")) || e.message.contains("recursion limit");
        assert!(refused, "{e}");
    }
    let walls = format!(
        "arenas:\n  0: !Arena\n    items:\n    - !Item\n      name: Wall\n      colors:\n{}",
        "      - !RGB {r: 1, g: 2, b: 3}\n".repeat(10_000)
    );
    let t0 = std::time::Instant::now();
    let e = err(&walls);
    assert_eq!((e.line, e.field.as_str()), (Some(5), "arenas.0.items[0]"));
    assert!(e.message.contains(&format!("more than {MAX_OBJECTS}")), "{e}");
    assert!(t0.elapsed().as_secs_f64() < 5.0, "refused, not spawned: {:?}", t0.elapsed());
    // At the bound, the arena loads and spawns.
    let bounded = walls.replace(
        &"      - !RGB {r: 1, g: 2, b: 3}\n".repeat(10_000),
        &"      - !RGB {r: 1, g: 2, b: 3}\n".repeat(MAX_OBJECTS),
    );
    let t = load_task("bounded", &bounded).unwrap();
    World::spawn(&t.layouts[0], &mut ChaCha8Rng::seed_from_u64(1));
    let long = "W".repeat(1 << 20);
    for src in [
        format!("arenas:\n  0: !Arena\n    items:\n    - !Item\n      name: {long}\n"),
        format!("arenas:\n  0: !Arena\n    {long}: 3\n"),
        format!("arenas:\n  0: !Arena\n    t: {long}\n"),
    ] {
        let e = err(&src);
        assert!(e.to_string().len() < 300, "a message of {} bytes", e.to_string().len());
    }
    let e = err("arenas:\n  0: !Arena\n    \"\": 3\n");
    assert_eq!(e.field, "arenas.0.\"\"");
}

/// An arena that leaves a random agent no free spot is refused when the env is built (the agent
/// used to be put inside the wall); an object written where another already is, is left out, as
/// v1 does, and the task says so.
#[test]
fn an_arena_without_room_for_the_agent_is_refused_and_an_object_on_a_taken_spot_left_out() {
    use sec_playground::env::{Env, EnvConfig};
    let full = "arenas:\n  0: !Arena\n    items:\n    - !Item\n      name: Wall\n      positions: [!Vector3 {x: 20, y: 0, z: 20}]\n      sizes: [!Vector3 {x: 40, y: 5, z: 40}]\n      rotations: [0]\n";
    let task = load_task("full", full).unwrap();
    let e = Env::new(EnvConfig::new(task), 1).unwrap_err();
    assert_eq!(e.field, "layout", "{e}");
    assert!(e.message.contains("the agent finds no free spot"), "{e}");
    let half = full.replace("z: 40}", "z: 20}").replace("z: 20}]\n      sizes", "z: 30}]\n      sizes");
    assert!(Env::new(EnvConfig::new(load_task("half", &half).unwrap()), 1).is_ok());
    let twice = "arenas:\n  0: !Arena\n    items:\n    - !Item\n      name: Wall\n      positions: [!Vector3 {x: 10, y: 0, z: 10}, !Vector3 {x: 10, y: 0, z: 10}]\n      rotations: [0, 0]\n";
    let task = load_task("twice", twice).unwrap();
    assert_eq!(task.layouts[0].objects.len(), 1, "the second wall is left out");
    assert_eq!(
        task.warnings,
        ["line 5: arenas.0.items[0]: its Wall (object 1 of the item) at (10, 0, 10) overlaps what is placed \
          before it; left out, as v1 does"]
    );
    assert_eq!(Env::new(EnvConfig::new(task), 1).unwrap().world().walls.len(), 1);
    // Every preset fits.
    for task in sec_playground::arena::TASK_NAMES {
        let t = sec_playground::arena::Task::preset(task).unwrap();
        assert!(Env::new(EnvConfig::new(t), 1).is_ok(), "{task}");
    }
}
