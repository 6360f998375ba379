//! SEC's memory parameters (docs/ALGORITHM.md): the value function, forgetting, `MemoryConfig`
//! and the ranges every front end checks against.

use crate::arena::ConfigError;

/// The option of `table` named `s`, or an error naming `param` and the choices.
fn parse_named<T: Copy>(param: &str, table: &[(&str, T)], s: &str) -> Result<T, ConfigError> {
    table.iter().find(|(n, _)| *n == s).map(|(_, v)| *v).ok_or_else(|| {
        let names: Vec<&str> = table.iter().map(|(n, _)| *n).collect();
        ConfigError::new(param, format!("'{s}' is not one of {}", names.join(", ")))
    })
}

/// How a selected couplet's value combines its similarity g, relative reward rr and distance d
/// (docs/ALGORITHM.md, retrieval). `Default` is the paper's SEC; the others are the ablations of experiment 3.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum ValueFn {
    /// g * rr * exp(-d / tau)
    Default,
    /// rr * exp(-d / tau)
    NoGi,
    /// g * rr
    NoDist,
    /// g * exp(-d / tau)
    #[serde(rename = "noRR")]
    NoRr,
    /// g
    SoloGi,
    /// exp(-d / tau)
    SoloDist,
    /// rr
    #[serde(rename = "soloRR")]
    SoloRr,
}

impl ValueFn {
    /// Every value function with its name.
    pub const ALL: [(&'static str, ValueFn); 7] = [
        ("default", ValueFn::Default),
        ("noGi", ValueFn::NoGi),
        ("noDist", ValueFn::NoDist),
        ("noRR", ValueFn::NoRr),
        ("soloGi", ValueFn::SoloGi),
        ("soloDist", ValueFn::SoloDist),
        ("soloRR", ValueFn::SoloRr),
    ];

    /// The value function of `s`; another name is refused.
    pub fn parse(s: &str) -> Result<Self, ConfigError> {
        parse_named("valueFunction", &Self::ALL, s)
    }

    /// The value of a couplet with similarity `g`, relative reward `rr` and distance weight
    /// `dist` = exp(-d / tau).
    pub fn value(self, g: f64, rr: f64, dist: f64) -> f64 {
        match self {
            // As numpy evaluates `collectors * (rewards * np.exp(-distances / tau))`.
            ValueFn::Default => g * (rr * dist),
            ValueFn::NoGi => rr * dist,
            ValueFn::NoDist => g * rr,
            ValueFn::NoRr => g * dist,
            ValueFn::SoloGi => g,
            ValueFn::SoloDist => dist,
            ValueFn::SoloRr => rr,
        }
    }
}

/// What happens when a sequence is stored into a full LTM (docs/ALGORITHM.md, storage and forgetting).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Forgetting {
    /// The LTM freezes at m; later sequences are not stored (the paper's main runs, D9).
    None,
    /// The oldest sequence goes.
    Fifo,
    /// A lowest-reward sequence goes (the oldest of equals).
    Rwd,
    /// The floor(10 % of m) lowest-reward sequences go.
    RwdProp,
    /// One sequence goes, drawn with probability proportional to (max reward + 1) - its reward.
    Prior,
}

impl Forgetting {
    /// Every forgetting rule with its name.
    pub const ALL: [(&'static str, Forgetting); 5] = [
        ("none", Forgetting::None),
        ("fifo", Forgetting::Fifo),
        ("rwd", Forgetting::Rwd),
        ("rwd-prop", Forgetting::RwdProp),
        ("prior", Forgetting::Prior),
    ];

    /// The forgetting rule of `s`; another name is refused.
    pub fn parse(s: &str) -> Result<Self, ConfigError> {
        parse_named("forgetting", &Self::ALL, s)
    }
}

/// The contextual layer's parameters. Defaults are the authors' code (the "code" preset).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", default, deny_unknown_fields)]
pub struct MemoryConfig {
    /// STM length n: couplets per sequence.
    pub n: usize,
    /// LTM capacity m: sequences.
    pub m: usize,
    /// Absolute threshold on the biased similarity G (strict).
    pub theta_abs: f64,
    /// Threshold on G / Gmax (strict).
    pub theta_prop: f64,
    /// T increment for the successor of a selected couplet.
    pub alpha: f64,
    /// T decay rate towards 1.
    pub beta: f64,
    /// Distance decay tau in exp(-d / tau).
    pub tau: f64,
    /// The sequential bias T; false is NSEC.
    pub sequential_bias: bool,
    /// How a couplet's terms make its value.
    pub value_function: ValueFn,
    /// What a full LTM does.
    pub forgetting: Forgetting,
}

impl Default for MemoryConfig {
    fn default() -> Self {
        MemoryConfig {
            n: 50,
            m: 500,
            theta_abs: 0.98,
            theta_prop: 0.995,
            alpha: 0.01,
            beta: 0.05,
            tau: 0.9,
            sequential_bias: true,
            value_function: ValueFn::Default,
            forgetting: Forgetting::None,
        }
    }
}

/// Allowed ranges, also shown by the page's controls.
pub const N_RANGE: (usize, usize) = (1, 1000);
/// The LTM capacity m's range.
pub const M_RANGE: (usize, usize) = (1, 100_000);
/// theta_abs's range.
pub const THETA_ABS_RANGE: (f64, f64) = (0.0, 2.0);
/// theta_prop's range.
pub const THETA_PROP_RANGE: (f64, f64) = (0.0, 1.0);
/// alpha's range.
pub const ALPHA_RANGE: (f64, f64) = (0.0, 1.0);
/// beta's range.
pub const BETA_RANGE: (f64, f64) = (0.0, 1.0);
/// From 0.01: below it exp(-d / tau) underflows to 0 for distant couplets and every value with
/// it, which made p 0 / 0 (the retrieval also refuses a zero total, see `retrieve`).
pub const TAU_RANGE: (f64, f64) = (0.01, 100.0);
/// The most couplets the LTM may hold, n x m: 80 MB of embeddings (the paper's largest is
/// 50 x 1000). The LTM grows as sequences arrive; nothing of this is reserved up front.
pub const MAX_COUPLETS: usize = 1_000_000;
/// The largest reward a sequence may carry (a memory file's; the tasks pay a few units), so that
/// PRIOR forgetting's sums of rewards stay finite.
pub const MAX_REWARD: f64 = 1e6;

fn check_f(name: &str, v: f64, lo: f64, hi: f64, lo_open: bool) -> Result<(), ConfigError> {
    let ok = v.is_finite() && v <= hi && if lo_open { v > lo } else { v >= lo };
    if ok {
        Ok(())
    } else {
        let open = if lo_open { "(" } else { "[" };
        Err(ConfigError::new(name, format!("{v} is out of range {open}{lo}, {hi}]")))
    }
}

impl MemoryConfig {
    /// Every parameter in its range; the error names the parameter and the range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if !(N_RANGE.0..=N_RANGE.1).contains(&self.n) {
            return Err(ConfigError::new("n", format!("{} is out of range {}..={}", self.n, N_RANGE.0, N_RANGE.1)));
        }
        if !(M_RANGE.0..=M_RANGE.1).contains(&self.m) {
            return Err(ConfigError::new("m", format!("{} is out of range {}..={}", self.m, M_RANGE.0, M_RANGE.1)));
        }
        check_f("thetaAbs", self.theta_abs, THETA_ABS_RANGE.0, THETA_ABS_RANGE.1, false)?;
        check_f("thetaProp", self.theta_prop, THETA_PROP_RANGE.0, THETA_PROP_RANGE.1, false)?;
        check_f("alpha", self.alpha, ALPHA_RANGE.0, ALPHA_RANGE.1, false)?;
        check_f("beta", self.beta, BETA_RANGE.0, BETA_RANGE.1, false)?;
        check_f("tau", self.tau, TAU_RANGE.0, TAU_RANGE.1, false)?;
        if self.n * self.m > MAX_COUPLETS {
            let message = format!("n x m = {} x {} is over {MAX_COUPLETS} couplets", self.n, self.m);
            return Err(ConfigError::new("m", message));
        }
        Ok(())
    }
}
