#!/usr/bin/env bash
# Follows docs/ARCHITECTURE.md's recipes on a copy of the committed tree (HEAD) and checks that
# each works with the files it names and no others: "Add an agent" (an always-forward walker with
# one live setting: its module, its row and variant in the table, one line in mod.rs) and "Add a
# setting" (a SEC setting: its field, row and declaration for JS, all in sec.rs) and "Add a task"
# (its row and layouts in tasks.rs, its model, the page's list in www/tasks.js), each with the
# checks the recipe says follow (the agents, settings, TypeScript and layers tests pass: the row is
# in the table, its setting in the settings table and live on a running agent; without its
# declaration the TypeScript test names what is missing). Not part of the test command (it
# compiles the core again, in its own target dir): run it after changing a recipe or a seam it
# touches.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
repo=$(pwd)
work=$(mktemp -d)
# A target dir of its own: cargo names a workspace crate's artifacts by its path relative to the
# workspace root, so a copy built in the repository's target dir would overwrite the
# repository's own (and leave them counted as fresh). The first run compiles the core's
# dependencies there once.
export CARGO_TARGET_DIR="$repo/target/recipes"
restore() { rm -rf "$work"; }
trap restore EXIT

fresh() {
  rm -rf "$work/tree" && mkdir -p "$work/tree"
  git archive HEAD | tar -x -C "$work/tree"
  (cd "$work/tree" && git init -q && git add -A && git -c user.email=r@x -c user.name=r commit -qm base)
}

# The files a recipe changed, against the copy's first commit.
changed() { (cd "$work/tree" && git add -A && git diff --cached --name-only); }

expect_files() {
  local got
  got=$(changed | sort | tr '\n' ' ')
  if [ "$got" != "$1 " ]; then
    echo "FAIL: $2 changed [$got], the recipe says [$1]" >&2
    exit 1
  fi
}

echo "== Add an agent: an always-forward walker with one live setting, in 3 files"
fresh
cd "$work/tree"
cat > src/agent/always_forward.rs <<'RSEOF'
//! A throwaway agent that walks forward and turns right every `turnEvery` decisions
//! (scripts/check-recipes.sh).

use super::controller::{Controller, EpisodeEnd, MemoryUse, Observation, Step};
use super::section::{own_section, AgentConfig, SectionSetting};
use super::{Decision, Layer};
use crate::arena::{Action, ConfigError};
use crate::param::Param;
use rand_chacha::ChaCha8Rng;
use std::any::Any;

/// Its configuration.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", default, deny_unknown_fields)]
pub struct ForwardConfig {
    /// Turns right every this many decisions (0: never).
    pub turn_every: u64,
}

impl AgentConfig for ForwardConfig {
    const KEY: &'static str = "forward";
    const TYPESCRIPT: &'static str = "export interface RunConfig { forward?: { turnEvery?: number } }";
    fn validate(&self) -> Result<(), ConfigError> {
        if self.turn_every > 1000 {
            return Err(ConfigError::new("forward.turnEvery", format!("{} is out of range 0..=1000", self.turn_every)));
        }
        Ok(())
    }
    fn settings() -> Vec<SectionSetting> {
        vec![SectionSetting::of(
            Param::integer("turnEvery", "turn", "Turns right every this many decisions (0: never).", (0, 1000), true),
            |c: &ForwardConfig| c.turn_every.to_string(),
            |c: &mut ForwardConfig, v| c.turn_every = v as u64,
        )]
    }
}

#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen(typescript_custom_section)]
const FORWARD_TYPESCRIPT: &str = <ForwardConfig as AgentConfig>::TYPESCRIPT;

/// Forward, and right now and then.
pub struct AlwaysForward {
    cfg: ForwardConfig,
    decisions: u64,
}

impl AlwaysForward {
    /// A walker of `cfg`.
    pub fn new(cfg: ForwardConfig) -> Self {
        AlwaysForward { cfg, decisions: 0 }
    }
}

impl Controller for AlwaysForward {
    fn on_step(&mut self, _: &Step, _: Option<&[f32]>, _: &mut ChaCha8Rng) -> bool {
        false
    }
    fn decide(&mut self, _: &Observation, _: &mut dyn FnMut() -> f32, _: &mut ChaCha8Rng) -> Decision {
        self.decisions += 1;
        let turn = self.cfg.turn_every > 0 && self.decisions % self.cfg.turn_every == 0;
        let action = if turn { Action::RIGHT } else { Action::FORWARD };
        Decision { action, layer: Layer::Reactive, selected: false }
    }
    fn on_episode_end(&mut self, _: &EpisodeEnd) {}
    fn entropy(&self) -> f64 {
        0.0
    }
    fn memory_use(&self) -> MemoryUse {
        MemoryUse::default()
    }
    fn reconfigure(&mut self, section: &dyn Any) -> Result<(), ConfigError> {
        self.cfg = own_section::<ForwardConfig>(section, "forward")?.clone();
        Ok(())
    }
}
RSEOF
python3 - <<'PYEOF'
p = 'src/agent/table.rs'
s = open(p).read()
s = s.replace("    Erlam,\n}", "    Erlam,\n    /// Always forward (a recipe check).\n    AlwaysForward,\n}", 1)
row = '''    AgentInfo {
        key: "always-forward", label: "always forward", unbiased_label: None,
        about: "Walks forward, turning right every turnEvery decisions.", explores: Some("It never explores."),
        section: Some(SectionSpec::of::<super::always_forward::ForwardConfig>()), reads: Input::Nothing,
        has_memory: false, has_gate: false, native_only: false, can_be_driven: false,
        kind: AgentKind::AlwaysForward, embedding: None,
        build: Some(|section, _, _, _| {
            let cfg = own_section::<super::always_forward::ForwardConfig>(section, "forward")?;
            Ok(Box::new(super::always_forward::AlwaysForward::new(cfg.clone())))
        }),
    },
];'''
i = s.index('\n];\n', s.index('pub const AGENTS'))
s = s[:i + 1] + row + s[i + 4:]
open(p, 'w').write(s)
p = 'src/agent/mod.rs'
s = open(p).read()
s = s.replace("pub mod controller;", "pub mod always_forward;\npub mod controller;", 1)
open(p, 'w').write(s)
PYEOF
expect_files "src/agent/always_forward.rs src/agent/mod.rs src/agent/table.rs" "Add an agent"
cargo test -q -p sec-playground --test agents --test settings --test typescript --test layers >/dev/null 2>&1 \
  || { echo "FAIL: the core's tests with the new agent" >&2; exit 1; }
echo "ok: 3 files; the core's agents, settings (its row is live), TypeScript and layers tests pass"
cd "$repo"

echo "== Add a setting: a SEC setting in the recipe's one file"
fresh
cd "$work/tree"
python3 - <<'PYEOF'
p = 'src/agent/sec.rs'
s = open(p).read()
s = s.replace("    pub reset_stm_on_episode: bool,\n}", "    pub reset_stm_on_episode: bool,\n    /// A recipe check's setting.\n    pub recipe_demo: f64,\n}", 1)
s = s.replace("            reset_stm_on_episode: false,\n        }", "            reset_stm_on_episode: false,\n            recipe_demo: 0.5,\n        }", 1)
s = s.replace("        self.memory.validate()?;", "        self.memory.validate()?;\n        if !(0.0..=1.0).contains(&self.recipe_demo) {\n            return Err(ConfigError::new(\"recipeDemo\", format!(\"{} is out of range [0, 1]\", self.recipe_demo)));\n        }", 1)
anchor = "        vec![\n"
i = s.index(anchor, s.index("fn settings() -> Vec<SectionSetting>")) + len(anchor)
row = '''            SectionSetting::of(
                Param::number("recipeDemo", "demo", "A recipe check's setting.", (0.0, 1.0), false, 0.1).group("memory"),
                |c: &SecConfig| c.recipe_demo.to_string(),
                |c: &mut SecConfig, v| c.recipe_demo = v,
            ),
'''
s = s[:i] + row + s[i:]
open(p, 'w').write(s)
PYEOF
# Without its declaration for JS, the TypeScript test names it.
if out=$(cargo test -q -p sec-playground --test typescript 2>&1); then
  echo "FAIL: the TypeScript test passed without the declaration" >&2
  exit 1
fi
grep -q 'RunConfig.agent.recipeDemo' <<<"$out" || { echo "FAIL: the TypeScript test did not name the field" >&2; exit 1; }
sed -i 's/resetStmOnEpisode?: boolean;/resetStmOnEpisode?: boolean; recipeDemo?: number;/' src/agent/sec.rs
expect_files "src/agent/sec.rs" "Add a setting"
cargo test -q -p sec-playground --test settings --test typescript --test agents >/dev/null 2>&1 \
  || { echo "FAIL: the core's tests with the new setting" >&2; exit 1; }
echo "ok: 1 file (its field, row and declaration, all in sec.rs); the settings, TypeScript and agents tests pass"

echo "== Add a task: a row and its layouts in tasks.rs, its model, the page's list"
cd "$repo"
fresh
cd "$work/tree"
python3 - <<'PYEOF'
p = 'src/arena/tasks.rs'
s = open(p).read()
s = s.replace('pub const TASKS: [TaskInfo; 6] = [', 'pub const TASKS: [TaskInfo; 7] = [', 1)
row = '''    TaskInfo {
        name: "recipe-arch",
        title: "the recipe's arch",
        description: "The cylinder's arch again, as a recipe check's task (scripts/check-recipes.sh).",
        gym_id: "SecPlayground/RecipeArch-v0",
        model_file: "recipe-arch.secae",
        layouts: recipe_arch,
        model: model!("recipe-arch.secae"),
        textured_model: &[],
    },
];'''
i = s.index('\n];\n', s.index('pub const TASKS'))
s = s[:i + 1] + row + s[i + 3:]
s += '''
/// The recipe check's layouts: the cylinder's.
fn recipe_arch() -> Vec<Layout> {
    vec![cylinder()]
}
'''
open(p, 'w').write(s)
PYEOF
# Its model: sec-train would train one (docs/ENCODER.md); here the cylinder's weights under the
# new task's name (a model file names its task, and a file of another task is refused).
python3 - <<'PYEOF'
body = open('assets/encoders/cylinder.secae', 'rb').read()[:-8]
n = int.from_bytes(body[16:18], 'little')
name = b'recipe-arch'
body = body[:16] + len(name).to_bytes(2, 'little') + name + body[18 + n:]
h = 0xcbf29ce484222325
for x in body:
    h = ((h ^ x) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
open('assets/encoders/recipe-arch.secae', 'wb').write(body + h.to_bytes(8, 'little'))
PYEOF
sed -i "s/'object-permanence-pits'\]/'object-permanence-pits', 'recipe-arch']/" www/tasks.js
expect_files "assets/encoders/recipe-arch.secae src/arena/tasks.rs www/tasks.js" "Add a task"
cargo test -q -p sec-playground --test tasks --test settings --test layers >/dev/null 2>&1 \
  || { echo "FAIL: the core's tests with the new task" >&2; exit 1; }
echo "ok: 2 files and the model; the tasks, settings and layers tests pass"
