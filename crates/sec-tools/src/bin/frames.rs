//! Writes the first frame of every task as PNGs: the 84x84 camera image, a 4x enlargement and
//! the top-down view. Usage: `cargo run -p sec-tools --bin frames -- [OUT_DIR] [--seed N]
//! [--surface flat|textured]` (textured frames are named `<task>-textured*.png`).

use sec_playground::arena::{Task, TASK_NAMES};
use sec_playground::env::{Env, EnvConfig};
use sec_playground::render::{Surface, TopDown, HEIGHT, WIDTH};
use sec_tools::{upscale, write_png};
use std::path::PathBuf;

fn main() {
    if let Err(e) = run() {
        eprintln!("frames: {e}");
        std::process::exit(2);
    }
}

fn run() -> Result<(), String> {
    let mut out = PathBuf::from("docs/frames");
    let mut seed = 1u64;
    let mut surface = Surface::Flat;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--seed" => {
                let v = args.next().ok_or("--seed needs a value")?;
                seed = v
                    .parse()
                    .map_err(|_| format!("--seed: '{v}' is not a whole number in 0..=18446744073709551615"))?;
            }
            "--surface" => {
                surface =
                    Surface::from_name(&args.next().unwrap_or_default()).map_err(|e| format!("--surface: {e}"))?;
            }
            "-h" | "--help" => {
                println!("usage: frames [OUT_DIR] [--seed N] [--surface flat|textured]  (default OUT_DIR docs/frames, seed 1, flat)");
                return Ok(());
            }
            s if s.starts_with('-') => return Err(format!("unknown option '{s}'")),
            s => out = PathBuf::from(s),
        }
    }
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    for name in TASK_NAMES {
        let task = Task::preset(name).map_err(|e| e.to_string())?;
        let mut env = Env::new(EnvConfig { surface, ..EnvConfig::new(task) }, seed).map_err(|e| e.to_string())?;
        let frame = env.observation().clone();
        let stem = sec_playground::encoder::model_name(name, surface);
        write_png(&out.join(format!("{stem}.png")), WIDTH, HEIGHT, &frame.rgba)?;
        write_png(&out.join(format!("{stem}_x4.png")), WIDTH * 4, HEIGHT * 4, &upscale(&frame.rgba, WIDTH, HEIGHT, 4))?;
        if surface == Surface::Flat {
            let mut top = TopDown::new(336);
            top.render(env.world(), &[]);
            write_png(&out.join(format!("{name}_top.png")), 336, 336, &top.rgba)?;
        }
        println!("{name}: layout {} -> {}", env.layout_name(), out.join(format!("{stem}.png")).display());
    }
    Ok(())
}
