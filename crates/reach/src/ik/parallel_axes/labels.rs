//! The branch labels of the parallel-axes solver: shoulder (`w`, `−w`), configuration
//! (`+β`, `−β`) and wrist (`e5`, `−e5`), and their keys.

use serde::Serialize;

/// Shoulder branch: the sign of the arm-plane normal w = e2 = z1 (notes 003 §3.7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Shoulder {
    /// The paper's `w = (e_r1 × k)/‖e_r1 × k‖` (z1·(C × k) > 0).
    W,
    /// The opposite normal: θ1 + 180° when the arm plane has no lateral offset.
    MinusW,
}

impl Shoulder {
    /// The branch label: `w` or `−w`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Shoulder::W => "w",
            Shoulder::MinusW => "−w",
        }
    }
}

/// Wrist branch: the sign of e5 = z4 (notes 003 §3.7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Wrist {
    /// The paper's `e5 = (w × e6)/‖w × e6‖` (eq. 11).
    E5,
    /// The wrist flip, `−e5`.
    MinusE5,
}

impl Wrist {
    /// The branch label: `e5` or `−e5`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Wrist::E5 => "e5",
            Wrist::MinusE5 => "−e5",
        }
    }

    pub(super) fn sign(self) -> f64 {
        match self {
            Wrist::E5 => 1.0,
            Wrist::MinusE5 => -1.0,
        }
    }
}

/// The paper's configuration of links 2 and 3 (eq. 20, Fig. 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Config {
    /// ξ = +1: (a2, e_r2, w) right-handed.
    PlusBeta,
    /// ξ = −1: (a2, e_r2, w) left-handed.
    MinusBeta,
}

impl Config {
    /// The branch label: `+β` or `−β`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Config::PlusBeta => "+β",
            Config::MinusBeta => "−β",
        }
    }
}

/// The keys of the branch labels.
pub(super) const KEYS: [&str; 3] = ["shoulder", "config", "wrist"];
