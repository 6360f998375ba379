#!/usr/bin/env bash
# Follows docs/ARCHITECTURE.md's recipes on a copy of the committed tree and checks that each
# works with the files it names and no others: "Add an agent" (an always-forward agent: its
# module, its row and variant in the table, one line in mod.rs) and "Add a setting" (a SEC
# setting: the field, its row, its declaration for JS), each with the checks the recipe says
# follow (the agent table lists it; Python's and the CLI's `parameters` list the setting; the
# settings, agents and TypeScript tests pass; without its declaration the TypeScript test names
# what is missing). Not part of the test command (it compiles the core twice more, several
# minutes): run it after changing the recipes or the seams they touch.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
repo=$(pwd)
work=$(mktemp -d)
# The repository's target dir: dependencies are shared (the copy's own crates build beside the
# repository's); the binaries it links are the repository's again at the end.
export CARGO_TARGET_DIR="$repo/target"
restore() { rm -rf "$work"; (cd "$repo" && cargo build -q -p sec-tools --bin sec-experiment) || true; }
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

echo "== Add an agent: an always-forward walker in 3 files"
fresh
cd "$work/tree"
cat > src/agent/always_forward.rs <<'EOF'
//! A throwaway agent that always moves forward (scripts/check-recipes.sh).

use super::controller::{Controller, EpisodeEnd, MemoryUse, Observation, Step};
use super::{Decision, Layer};
use crate::arena::Action;
use rand_chacha::ChaCha8Rng;

/// Always forward.
pub struct AlwaysForward;

impl Controller for AlwaysForward {
    fn on_step(&mut self, _: &Step, _: Option<&[f32]>, _: &mut ChaCha8Rng) -> bool {
        false
    }
    fn decide(&mut self, _: &Observation, _: &mut dyn FnMut() -> f32, _: &mut ChaCha8Rng) -> Decision {
        Decision { action: Action::FORWARD, layer: Layer::Reactive, selected: false }
    }
    fn on_episode_end(&mut self, _: &EpisodeEnd) {}
    fn entropy(&self) -> f64 {
        0.0
    }
    fn memory_use(&self) -> MemoryUse {
        MemoryUse::default()
    }
}
EOF
python3 - <<'EOF'
p = 'src/agent/table.rs'
s = open(p).read()
s = s.replace("    Erlam,\n}", "    Erlam,\n    /// Always forward (a recipe check).\n    AlwaysForward,\n}", 1)
row = '''    AgentInfo {
        key: "always-forward", label: "always forward", unbiased_label: None,
        about: "Walks forward, always.", explores: Some("It never explores."),
        section: None, reads: Input::Nothing,
        has_memory: false, has_gate: false, native_only: false, can_be_driven: false,
        kind: AgentKind::AlwaysForward, embedding: None,
        build: Some(|_, _, _, _| Ok(Box::new(super::always_forward::AlwaysForward))),
    },
];'''
i = s.index('\n];\n', s.index('pub const AGENTS'))
s = s[:i + 1] + row + s[i + 4:]
open(p, 'w').write(s)
p = 'src/agent/mod.rs'
s = open(p).read()
s = s.replace("pub mod controller;", "pub mod always_forward;\npub mod controller;", 1)
open(p, 'w').write(s)
EOF
expect_files "src/agent/always_forward.rs src/agent/mod.rs src/agent/table.rs" "Add an agent"
cargo test -q -p sec-playground --test agents --test settings --test typescript 2>&1 | grep -E '^test result|FAILED|panicked' || true
cargo test -q -p sec-playground --test agents --test settings --test typescript >/dev/null 2>&1 \
  || { echo "FAIL: the core's tests with the new agent" >&2; exit 1; }
cargo run -q -p sec-tools --bin sec-experiment -- agents | grep -q always-forward \
  || { echo "FAIL: sec-experiment agents does not list it" >&2; exit 1; }
cargo run -q -p sec-tools --bin sec-experiment -- parameters --agent always-forward --json >/dev/null \
  || { echo "FAIL: sec-experiment parameters --agent always-forward" >&2; exit 1; }
echo "ok: 3 files; the table, the CLI's agents and parameters, the core's tests"
cd "$repo"

echo "== Add a setting: a SEC setting in the recipe's files"
fresh
cd "$work/tree"
python3 - <<'EOF'
p = 'src/agent/sec.rs'
s = open(p).read()
s = s.replace("    pub reset_stm_on_episode: bool,\n}", "    pub reset_stm_on_episode: bool,\n    /// A recipe check's setting.\n    pub recipe_demo: f64,\n}", 1)
s = s.replace("            reset_stm_on_episode: false,\n        }", "            reset_stm_on_episode: false,\n            recipe_demo: 0.5,\n        }", 1)
s = s.replace("        self.memory.validate()?;", "        self.memory.validate()?;\n        if !(0.0..=1.0).contains(&self.recipe_demo) {\n            return Err(ConfigError::new(\"recipeDemo\", format!(\"{} is out of range [0, 1]\", self.recipe_demo)));\n        }", 1)
open(p, 'w').write(s)
p = 'src/experiment/settings.rs'
s = open(p).read()
anchor = '        Setting {\n            param: choice("forgetting",'
row = '''        Setting {
            param: Param { key: "recipeDemo", symbol: "demo", help: "A recipe check's setting.", kind: Kind::Number { min: 0.0, max: 1.0, min_open: false, step: 0.1, auto: false }, live: true, group: "memory", agents: sec_only() },
            get: |c, _| c.agent.recipe_demo.to_string(),
            set: |c, _, v| c.agent.recipe_demo = v,
        },
'''
s = s.replace(anchor, row + anchor, 1)
open(p, 'w').write(s)
EOF
# Without its declaration for JS, the TypeScript test names it.
if out=$(cargo test -q -p sec-playground --test typescript 2>&1); then
  echo "FAIL: the TypeScript test passed without the declaration" >&2
  exit 1
fi
grep -q 'RunConfig.agent.recipeDemo' <<<"$out" || { echo "FAIL: the TypeScript test did not name the field" >&2; exit 1; }
sed -i 's/resetStmOnEpisode?: boolean;/resetStmOnEpisode?: boolean; recipeDemo?: number;/' src/web/types.d.ts
expect_files "src/agent/sec.rs src/experiment/settings.rs src/web/types.d.ts" "Add a setting"
cargo test -q -p sec-playground --test settings --test typescript --test agents >/dev/null 2>&1 \
  || { echo "FAIL: the core's tests with the new setting" >&2; exit 1; }
cargo run -q -p sec-tools --bin sec-experiment -- parameters --agent sec | grep -q recipeDemo \
  || { echo "FAIL: sec-experiment parameters does not list it" >&2; exit 1; }
echo "ok: 3 files (the recipe's 2 and the declaration); its row is live, the tests pass, the CLI lists it"
