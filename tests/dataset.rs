//! The autoencoder's training data: the authors' pose distribution, deterministic per seed.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::arena::Task;
use sec_playground::encoder::dataset::{generate, FRAME_BYTES};
use sec_playground::render::Surface;

#[test]
fn poses_follow_the_authors_generator_and_frames_are_deterministic() {
    let task = Task::preset("double-t-maze").unwrap();
    let (rgb, poses) = generate(&task, Surface::Flat, 300, 5).unwrap();
    assert_eq!(rgb.len(), 300 * FRAME_BYTES);
    for p in &poses {
        assert!(p.x.fract() == 0.0 && (5.0..=34.0).contains(&p.x), "{p:?}");
        assert!(p.z.fract() == 0.0 && (5.0..=34.0).contains(&p.z), "{p:?}");
        assert!(p.heading.fract() == 0.0 && (0.0..=358.0).contains(&p.heading), "{p:?}");
    }
    // Poses spread over the whole range.
    assert!(poses.iter().any(|p| p.x == 5.0) && poses.iter().any(|p| p.x == 34.0));
    let (again, _) = generate(&task, Surface::Flat, 300, 5).unwrap();
    assert_eq!(rgb, again);
    let (other, _) = generate(&task, Surface::Flat, 300, 6).unwrap();
    assert_ne!(rgb, other, "another seed is another (held-out) set");
    // Frames differ from each other: views from different poses.
    let distinct: std::collections::HashSet<&[u8]> = rgb.chunks_exact(FRAME_BYTES).collect();
    assert!(distinct.len() > 290, "{} distinct frames", distinct.len());
}

#[test]
fn the_permanence_frames_show_the_goal_at_its_spawn_height() {
    // First frames only: the big goal is still up in the air, as in the authors' data.
    let task = Task::preset("object-permanence").unwrap();
    let (rgb, _) = generate(&task, Surface::Flat, 200, 1).unwrap();
    let goal = [129u8, 191, 65];
    // The top 6 rows look at least 27 degrees up: only the falling goal, 11.5 up, gets there.
    let high = rgb.chunks_exact(FRAME_BYTES).filter(|f| f[..6 * 84 * 3].chunks_exact(3).any(|p| p == goal)).count();
    assert!(high > 5, "{high} frames show the goal high in the air");
}

#[test]
fn a_textured_data_set_has_the_same_poses_and_other_frames() {
    let task = Task::preset("double-t-maze").unwrap();
    let (flat, poses) = generate(&task, Surface::Flat, 50, 3).unwrap();
    let (textured, textured_poses) = generate(&task, Surface::Textured, 50, 3).unwrap();
    assert_eq!(poses, textured_poses);
    let differ = flat.chunks_exact(FRAME_BYTES).zip(textured.chunks_exact(FRAME_BYTES)).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 50, "every textured frame shows floor or fence");
}
