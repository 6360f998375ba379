//! What a setting is, as the page shows it (`Param`: key, symbol, help, range, live or not, group)
//! and the values it takes (`Kind`). The run's settings (`experiment::settings`) and each agent's
//! (its section's `AgentConfig::settings`) are rows of this shape; the page builds its controls
//! from them, and Python and the CLI list them.

/// What values a setting takes.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "type", rename_all = "camelCase")]
pub enum Kind {
    /// A real number in [min, max] (or (min, max] when `min_open`); with `auto`, also the word
    /// `auto`, which leaves the value to the run (an empty control shows it).
    #[serde(rename_all = "camelCase")]
    Number {
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
        /// The lower bound itself is excluded.
        min_open: bool,
        /// The control's step.
        step: f64,
        /// `auto` is a value too.
        auto: bool,
    },
    /// A whole number in min..=max.
    Integer {
        /// Lower bound.
        min: u64,
        /// Upper bound.
        max: u64,
    },
    /// One of the options.
    Choice {
        /// The values, as the URL hash spells them.
        options: Vec<String>,
    },
    /// On ("1") or off ("0").
    Switch,
}

/// One setting as the page shows it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Param {
    /// The URL hash's key.
    pub key: &'static str,
    /// The paper's symbol (Greek letters as Unicode), or a short label.
    pub symbol: &'static str,
    /// One line on what it does.
    pub help: &'static str,
    /// What values it takes.
    pub kind: Kind,
    /// Applies to the running agent; otherwise a change starts a new run.
    pub live: bool,
    /// The page's group of controls: run, perception, memory or retrieval.
    pub group: &'static str,
    /// The page's agents (`page_agents()` keys) that use it; empty: every agent.
    pub agents: Vec<&'static str>,
}

impl Param {
    /// A real number in `range` (the lower bound excluded with `open`), stepped by `step`.
    pub fn number(
        key: &'static str,
        symbol: &'static str,
        help: &'static str,
        range: (f64, f64),
        open: bool,
        step: f64,
    ) -> Param {
        let kind = Kind::Number { min: range.0, max: range.1, min_open: open, step, auto: false };
        Param { key, symbol, help, kind, live: true, group: "run", agents: Vec::new() }
    }

    /// A whole number in `range`.
    pub fn integer(
        key: &'static str,
        symbol: &'static str,
        help: &'static str,
        range: (u64, u64),
        live: bool,
    ) -> Param {
        Param {
            key,
            symbol,
            help,
            kind: Kind::Integer { min: range.0, max: range.1 },
            live,
            group: "run",
            agents: Vec::new(),
        }
    }

    /// One of `options`.
    pub fn choice(key: &'static str, symbol: &'static str, help: &'static str, options: &[&str], live: bool) -> Param {
        let kind = Kind::Choice { options: options.iter().map(|s| s.to_string()).collect() };
        Param { key, symbol, help, kind, live, group: "run", agents: Vec::new() }
    }

    /// On or off.
    pub fn switch(key: &'static str, symbol: &'static str, help: &'static str, live: bool) -> Param {
        Param { key, symbol, help, kind: Kind::Switch, live, group: "run", agents: Vec::new() }
    }

    /// In the page's `group` of controls.
    pub fn group(self, group: &'static str) -> Param {
        Param { group, ..self }
    }

    /// For the page's `agents` only.
    pub fn agents(self, agents: Vec<&'static str>) -> Param {
        Param { agents, ..self }
    }

    /// Whether a change acts on the running agent (`false`: it starts a new run).
    pub fn live(self, live: bool) -> Param {
        Param { live, ..self }
    }
}

/// The names of a table of named values (a choice's options).
pub fn names<T>(table: &[(&'static str, T)]) -> Vec<&'static str> {
    table.iter().map(|(n, _)| *n).collect()
}

/// The name `table` gives `value`.
pub fn name_of<T: PartialEq>(table: &[(&'static str, T)], value: T) -> String {
    table.iter().find(|(_, v)| *v == value).expect("every option is listed").0.to_string()
}
