//! Playing a grid on all cores. Resumable: a finished run is a complete `.jsonl.gz` file and is
//! skipped; an unfinished one is a `.part` file, continued from its `.ckpt` checkpoint where its
//! agent writes them (SEC, NSEC, DQN and ERLAM), and started again otherwise (MFEC, the reactive
//! walk); runs are deterministic, so either way nothing differs but the time spent. An identical
//! finished run elsewhere in the tree is copied instead of played. Shards on several machines
//! write disjoint files into copies of the same tree, which merge by copying.

use crate::layout::{
    checkpoint_path, finished_episodes, read_run_text, remove_leftovers, run_path, write_atomically, write_gzip,
};
use crate::plan::{check_episodes, Job};
use crate::verify::{first_difference, Finished};
use indicatif::{ProgressBar, ProgressStyle};
use sec_playground::experiment::checkpoint::ResumeCheck;
use sec_playground::experiment::Run;
use std::fs;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// The run to continue, the episodes it has played and the length in bytes of their lines at
/// the head of its `.part` file: from the checkpoint an interrupted run left (any lines written
/// after it are played again), or a fresh run (0, 0).
pub(crate) fn start(job: &Job, part: &Path, ckpt: &Path, legacy: bool) -> Result<(Run, usize, u64), String> {
    if let (Ok(bytes), Ok(text)) = (fs::read(ckpt), fs::read_to_string(part)) {
        // The log bounds what the checkpoint may claim, and its head must be the lines the
        // checkpoint was written after (`ResumeCheck`): a count edited above or below is refused
        // before anything is replayed. Whole lines only: a last line cut by the interruption
        // does not count.
        let whole = text.split_inclusive('\n').take_while(|l| l.ends_with('\n')).count();
        let check = ResumeCheck { max_episodes: whole as u64, log: Some(&text), legacy };
        match Run::resume(job.config.clone(), job.seed, job.agents, &mut bytes.as_slice(), &check) {
            Ok(run) => {
                let played = run.env().episode() as usize;
                eprintln!("{}: resumed after episode {played}", ckpt.display());
                let kept = text.split_inclusive('\n').take(played).map(|l| l.len() as u64).sum();
                return Ok((run, played, kept));
            }
            Err(e) => eprintln!("{}: not resumed ({e}); the run starts again", ckpt.display()),
        }
    }
    let run =
        Run::with_agents(job.config.clone(), job.seed, job.agents).map_err(|e| format!("{}: {e}", job.condition))?;
    Ok((run, 0, 0))
}

/// Writes the run's checkpoint in place of the last (an interruption leaves the previous one
/// whole).
pub(crate) fn save_checkpoint(run: &Run, ckpt: &Path) -> Result<(), String> {
    write_atomically(ckpt, |w| run.save_checkpoint(w).map_err(|e| format!("{}: {e}", ckpt.display())))
}

/// Plays one job's episodes into `<file>.part`, up to `stop` of them (`episodes` but in tests),
/// with a checkpoint every `every` episodes (0: none) when the agent can write one. A resumed
/// run's file is cut after the lines its checkpoint continues and appended to, never rewritten,
/// so a second interruption, however early, still finds them.
pub(crate) fn play(
    job: &Job,
    out: &Path,
    episodes: usize,
    every: usize,
    stop: usize,
    bar: &ProgressBar,
) -> Result<(), String> {
    let path = run_path(out, &job.condition, job.seed);
    let (part, ckpt) = (path.with_extension("part"), checkpoint_path(out, &job.condition, job.seed));
    let (mut run, played, kept) = start(job, &part, &ckpt, job.legacy_checkpoint)?;
    let err = |e: std::io::Error| format!("{}: {e}", part.display());
    let file = fs::OpenOptions::new().write(true).create(true).truncate(false).open(&part).map_err(err)?;
    file.set_len(kept).map_err(err)?;
    let mut w = BufWriter::new(file);
    w.seek(SeekFrom::End(0)).map_err(err)?;
    bar.inc(played as u64);
    for i in played..stop.min(episodes) {
        let m = run.episode();
        writeln!(w, "{}", m.to_json()).map_err(err)?;
        bar.inc(1);
        let n = i + 1;
        if every > 0 && n % every == 0 && n < episodes && run.can_checkpoint() {
            // The log first: a checkpoint never runs ahead of the lines it continues.
            w.flush().map_err(err)?;
            save_checkpoint(&run, &ckpt)?;
        }
    }
    w.flush().map_err(err)
}

/// Plays one job's `episodes` (resuming an interrupted run from its checkpoint), then gzips the
/// log into place and removes the checkpoint. A shorter finished log of the job is replaced only
/// when it is the new log's head, line for line: a run is a pure function of (configuration,
/// seed), so a difference means one of them is wrong, and both are kept for a look.
pub(crate) fn run_job(job: &Job, out: &Path, episodes: usize, every: usize, bar: &ProgressBar) -> Result<(), String> {
    let path = run_path(out, &job.condition, job.seed);
    let shorter = read_run_text(&path).ok().filter(|t| !t.is_empty());
    let clock = crate::manifest::Clock::start();
    play(job, out, episodes, every, episodes, bar)?;
    let part = path.with_extension("part");
    let text = fs::read(&part).map_err(|e| format!("{}: {e}", part.display()))?;
    if let Some(old) = shorter {
        let new = String::from_utf8_lossy(&text);
        if let Some(line) = first_difference(&old, &new) {
            return Err(format!(
                "{}: the new {episodes}-episode log differs from the finished {}-episode log {} at episode {line}; \
                 both are kept",
                part.display(),
                old.lines().count(),
                path.display()
            ));
        }
    }
    write_gzip(&path, &text)?;
    crate::manifest::write(&path, &clock.finish(&job.config, job.seed, episodes))?;
    remove_leftovers(&path, &checkpoint_path(out, &job.condition, job.seed))
}

/// Makes one run of an experiment folder `out` (as `run_all` does, without its progress bar):
/// nothing when its log already has `episodes`, else it plays (from its checkpoint when an
/// interrupted run left one). Returns whether it played. A Ray task or a Slurm job calls this.
pub fn run_one(job: &Job, out: &Path, episodes: usize, every: usize) -> Result<bool, String> {
    check_episodes(episodes)?;
    if finished_episodes(&run_path(out, &job.condition, job.seed)) >= episodes {
        return Ok(false);
    }
    run_job(job, out, episodes, every, &ProgressBar::hidden())?;
    Ok(true)
}

/// Copies the head of `episodes` lines of the finished log `from` into `job`'s place under `out`
/// (the file itself when it has no more), removing what an interrupted play of the job left (its
/// `.part` log and checkpoint).
pub(crate) fn copy_run(from: &Path, job: &Job, out: &Path, episodes: usize) -> Result<(), String> {
    let bytes = fs::read(from).map_err(|e| format!("{}: {e}", from.display()))?;
    let path = run_path(out, &job.condition, job.seed);
    let text = read_run_text(from)?;
    if text.lines().count() == episodes {
        write_atomically(&path, |w| w.write_all(&bytes).map_err(|e| format!("{}: {e}", path.display())))?;
    } else {
        let head: String = text.split_inclusive('\n').take(episodes).collect();
        write_gzip(&path, head.as_bytes())?;
    }
    let mut manifest = crate::manifest::Clock::start().finish(&job.config, job.seed, episodes);
    manifest.copied_from = Some(from.display().to_string());
    crate::manifest::write(&path, &manifest)?;
    remove_leftovers(&path, &checkpoint_path(out, &job.condition, job.seed))
}

/// Runs the unfinished `jobs` on `threads` threads with a progress bar on standard error (a line
/// per finished run when it is not a terminal), each checkpointing every `every` episodes (0:
/// never; only agents that can: SEC, DQN and ERLAM). A job that `reuse` holds a finished run of
/// is copied from it instead of played. Returns (runs made, runs copied, runs already there).
pub fn run_all(
    jobs: &[Job],
    out: &Path,
    episodes: usize,
    every: usize,
    threads: usize,
    reuse: Option<&Finished>,
) -> Result<(usize, usize, usize), String> {
    let unfinished: Vec<&Job> =
        jobs.iter().filter(|j| finished_episodes(&run_path(out, &j.condition, j.seed)) < episodes).collect();
    let skipped = jobs.len() - unfinished.len();
    let mut todo = Vec::new();
    let mut copied = 0;
    for job in unfinished {
        match reuse.and_then(|r| r.find(job, out, episodes)) {
            Some(from) => {
                copy_run(&from, job, out, episodes)?;
                eprintln!(
                    "{} seed {}: copied from {} (the same configuration and seed)",
                    job.condition,
                    job.seed,
                    from.display()
                );
                copied += 1;
            }
            None => todo.push(job),
        }
    }
    let bar = ProgressBar::new((todo.len() * episodes) as u64);
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} episodes, eta {eta} {msg}")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    let next = AtomicUsize::new(0);
    let errors = Mutex::new(Vec::new());
    let done = AtomicUsize::new(0);
    std::thread::scope(|s| {
        for _ in 0..threads.max(1) {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(job) = todo.get(i) else { break };
                match run_job(job, out, episodes, every, &bar) {
                    Ok(()) => {
                        let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                        let line = format!("{}/{} runs: {} seed {}", n, todo.len(), job.condition, job.seed);
                        if bar.is_hidden() {
                            eprintln!("{line}");
                        } else {
                            bar.set_message(line);
                        }
                    }
                    Err(e) => errors.lock().expect("no thread panicked holding it").push(e),
                }
            });
        }
    });
    bar.finish();
    let errors = errors.into_inner().expect("no thread panicked holding it");
    if let Some(e) = errors.first() {
        return Err(format!("{} run(s) failed; the first: {e}", errors.len()));
    }
    Ok((todo.len(), copied, skipped))
}
