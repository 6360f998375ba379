//! Autoencoder training data exactly as the authors made it (docs/ALGORITHM.md, D10):
//! single first-frame views from uniformly random agent poses in the task's arena, not
//! trajectories. Their generator drew x, z with `randint(5, 35)` (whole numbers 5..=34) and the
//! heading with `randint(0, 359)` (0..=358 degrees).

use crate::arena::{AgentSpec, ConfigError, Layout, Task, World};
use crate::render::{Camera, Frame, Surface, PIXELS};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Bytes of one RGB frame, channel-last (84 x 84 x 3).
pub const FRAME_BYTES: usize = PIXELS * 3;

/// An agent pose of the data set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Position x.
    pub x: f32,
    /// Position z.
    pub z: f32,
    /// Heading, radians.
    pub heading: f32,
}

/// Draws a pose as the authors' generator did: whole-number x, z in 5..=34, heading in 0..=358.
pub fn random_pose(rng: &mut ChaCha8Rng) -> Pose {
    Pose {
        x: rng.gen_range(5..35u32) as f32,
        z: rng.gen_range(5..35u32) as f32,
        heading: rng.gen_range(0..359u32) as f32,
    }
}

/// The first frame of `layout` with the agent placed at `pose`. As in Animal-AI, the placed agent
/// spawns first, so an object that would overlap it is left out of that frame.
pub fn first_frame(layout: &Layout, pose: Pose, rng: &mut ChaCha8Rng, camera: &mut Camera, frame: &mut Frame) {
    let mut l = layout.clone();
    l.agent = AgentSpec { position: [Some(pose.x), Some(pose.z)], y: 0.0, rotation: Some(pose.heading) };
    let world = World::spawn(&l, rng);
    camera.render(&world, frame);
}

/// `n` frames of `task` (its layouts taken in turn) as RGB bytes, channel-last, one after another,
/// with the poses, drawn with `surface`. A pure function of (task, surface, n, seed): the held-out
/// set is another seed. The poses do not depend on the surface.
pub fn generate(task: &Task, surface: Surface, n: usize, seed: u64) -> Result<(Vec<u8>, Vec<Pose>), ConfigError> {
    if task.layouts.is_empty() {
        return Err(ConfigError::new("task", "has no layout"));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut camera = Camera::with_surface(surface);
    let mut frame = Frame::new();
    let mut rgb = Vec::with_capacity(n * FRAME_BYTES);
    let mut poses = Vec::with_capacity(n);
    for i in 0..n {
        let pose = random_pose(&mut rng);
        first_frame(&task.layouts[i % task.layouts.len()], pose, &mut rng, &mut camera, &mut frame);
        rgb.extend(frame.rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]));
        poses.push(pose);
    }
    Ok((rgb, poses))
}
