//! A bound on how much one scene file may build, so that a few lines of defines that use each
//! other twice over cannot expand exponentially into all memory and time.
//!
//! Everything the reader builds spends from one budget: each object, each part of a pattern,
//! each entry of a transform list (every time the list is used) and each expansion of a
//! defined name. No hand-written scene comes near the limit (the book's
//! cover spends about 80); ten defines that each use the one before twice spend over a
//! thousand, thirty spend over a billion and are refused.

use std::cell::Cell;

/// How many parts (objects, pattern parts, transform entries, define expansions) one scene
/// may build. An object
/// with its material takes about a kilobyte, so the limit keeps a scene under about a gigabyte
/// before any mesh data.
pub const MAX_PARTS: usize = 1_000_000;

/// What is left of a scene's budget.
#[derive(Debug)]
pub struct Budget {
    left: Cell<usize>,
}

impl Default for Budget {
    fn default() -> Self {
        Self {
            left: Cell::new(MAX_PARTS),
        }
    }
}

impl Budget {
    /// Spends one part; the message of the error when the budget is spent.
    pub fn spend(&self) -> Result<(), String> {
        match self.left.get().checked_sub(1) {
            Some(left) => {
                self.left.set(left);
                Ok(())
            }
            None => Err(format!(
                "the scene builds more than {MAX_PARTS} parts (objects, pattern parts, transform \
                 entries and uses of defined names); is a define used many times over inside \
                 other defines?"
            )),
        }
    }
}
