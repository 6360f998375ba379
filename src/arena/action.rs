//! The agent's action: one of Animal-AI v1's 9 discrete moves (its two branches flattened).

use super::ConfigError;

/// One of the 9 flat actions, index `3*a0 + a1`: a0 0 none / 1 forward / 2 backward,
/// a1 0 none / 1 right / 2 left (the index SEC's baselines use). Serialised as its index, so
/// logs and files hold plain numbers; a number out of range does not deserialise.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "u32", into = "u8")]
pub struct Action(u8);

impl TryFrom<u32> for Action {
    type Error = ConfigError;
    fn try_from(index: u32) -> Result<Action, ConfigError> {
        Action::new(index)
    }
}

impl From<Action> for u8 {
    fn from(a: Action) -> u8 {
        a.0
    }
}

impl Action {
    /// Stand still.
    pub const NOOP: Action = Action(0);
    /// Move forward.
    pub const FORWARD: Action = Action(3);
    /// Move back.
    pub const BACKWARD: Action = Action(6);
    /// Turn right.
    pub const RIGHT: Action = Action(1);
    /// Turn left.
    pub const LEFT: Action = Action(2);
    /// Actions there are: 3 movements x 3 rotations.
    pub const COUNT: usize = 9;
    /// Every action, in index order (an index below `COUNT` picks one without a check).
    pub const ALL: [Action; Action::COUNT] =
        [Action(0), Action(1), Action(2), Action(3), Action(4), Action(5), Action(6), Action(7), Action(8)];

    /// The action of index 0..=8; another index is refused by name.
    pub fn new(index: u32) -> Result<Action, ConfigError> {
        if (index as usize) < Self::COUNT {
            Ok(Action(index as u8))
        } else {
            Err(ConfigError::new("action", format!("{index} is out of range 0..={}", Self::COUNT - 1)))
        }
    }
    /// The action of Animal-AI's two branches (movement, rotation), each 0..=2.
    pub fn from_branches(a0: u8, a1: u8) -> Result<Action, ConfigError> {
        if a0 > 2 || a1 > 2 {
            return Err(ConfigError::new("action", format!("branches ({a0}, {a1}) are out of range 0..=2")));
        }
        Ok(Action(3 * a0 + a1))
    }
    /// Its index, 0..=8.
    pub const fn index(self) -> usize {
        self.0 as usize
    }
    /// (a0 movement, a1 rotation).
    pub fn branches(self) -> (u8, u8) {
        (self.0 / 3, self.0 % 3)
    }
}
