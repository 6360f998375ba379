//! The task table: every built-in task declared once, with its layouts, model and Gymnasium id.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::arena::{Task, TaskInfo, TASKS, TASK_NAMES};
use sec_playground::encoder::bundled;

#[test]
fn every_task_row_builds_its_task_and_names_its_model() {
    assert_eq!(TASK_NAMES.to_vec(), TASKS.iter().map(|t| t.name).collect::<Vec<_>>());
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for t in &TASKS {
        let task = Task::preset(t.name).unwrap();
        assert!(!task.layouts.is_empty(), "{}", t.name);
        assert_eq!(task.description, t.description);
        assert_eq!(t.model_file, format!("{}.secae", t.name), "the page fetches assets/encoders/<name>.secae");
        let on_disk = std::fs::read(root.join("assets/encoders").join(t.model_file)).unwrap();
        assert_eq!(on_disk, t.model, "{}: the compiled-in model is the file", t.name);
        assert_eq!(bundled::autoencoder(t.name).unwrap().task, t.name);
        assert!(t.gym_id.starts_with("SecPlayground/") && t.gym_id.ends_with("-v0"), "{}", t.gym_id);
    }
    let e = TaskInfo::find("maze").unwrap_err();
    assert_eq!(e.field, "task");
    assert!(e.message.contains("double-t-maze"), "{e}");
    let json = serde_json::to_value(TASKS).unwrap();
    assert_eq!(json[0]["gymId"], "SecPlayground/DoubleTMaze-v0");
    assert!(json[0].get("model").is_none() && json[0].get("layouts").is_none());
}
