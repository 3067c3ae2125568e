//! The memory the renders in flight hold together (`--max-render-memory`). Each render's own
//! check (`crate::memory`) asks the system only for its own memory, so several large requests
//! at once each passed it alone and together aborted the server (at 4.3 GB). A render now
//! reserves its memory here before it starts: one that needs more than the whole budget is
//! refused with a message naming the flag, and one that does not fit beside the others waits
//! for them to end (heeding its cancel meanwhile).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// How often a waiting render looks at its cancel flag: the condition variable wakes it when
/// memory is given back, but not when it is cancelled.
const CANCEL_POLL: Duration = Duration::from_millis(20);

/// The budget: its total and what the renders in flight hold of it, in bytes.
#[derive(Debug)]
pub struct MemoryBudget {
    total: u64,
    held: Mutex<u64>,
    given_back: Condvar,
}

/// Why a render got no memory.
#[derive(Debug, PartialEq, Eq)]
pub enum Refusal {
    /// It alone needs more than the budget; the message says so, naming the flag.
    TooLarge(String),
    /// Its cancel flag was set while it waited.
    Cancelled,
}

/// Memory held by one render, given back when dropped.
#[derive(Debug)]
pub struct Reservation<'a> {
    budget: &'a MemoryBudget,
    bytes: u64,
}

impl MemoryBudget {
    /// A budget of `total` bytes.
    pub fn new(total: u64) -> Self {
        Self {
            total,
            held: Mutex::new(0),
            given_back: Condvar::new(),
        }
    }

    /// Reserves `bytes` for `what` (a render, named in the refusal): at once when they fit
    /// beside what the others hold, after waiting for them when not, never when they exceed
    /// the whole budget or `cancel` is set first.
    pub fn reserve(
        &self,
        bytes: u64,
        what: &str,
        cancel: &AtomicBool,
    ) -> Result<Reservation<'_>, Refusal> {
        if bytes > self.total {
            let mib = |b: u64| b.div_ceil(1 << 20);
            return Err(Refusal::TooLarge(format!(
                "{what} needs about {} MiB, more than the {} MiB the server's renders may hold \
                 together (--max-render-memory); a smaller image needs less",
                mib(bytes),
                mib(self.total)
            )));
        }
        // A poisoned lock means a render panicked while it held it: the count is still sound.
        let mut held = self.held.lock().unwrap_or_else(|p| p.into_inner());
        while *held + bytes > self.total {
            if cancel.load(Ordering::Relaxed) {
                return Err(Refusal::Cancelled);
            }
            held = self
                .given_back
                .wait_timeout(held, CANCEL_POLL)
                .unwrap_or_else(|p| p.into_inner())
                .0;
        }
        *held += bytes;
        Ok(Reservation {
            budget: self,
            bytes,
        })
    }

    /// What the renders in flight hold now, in bytes.
    #[cfg(test)]
    fn held(&self) -> u64 {
        *self.held.lock().unwrap_or_else(|p| p.into_inner())
    }
}

impl Drop for Reservation<'_> {
    fn drop(&mut self) {
        let mut held = self.budget.held.lock().unwrap_or_else(|p| p.into_inner());
        *held -= self.bytes;
        self.budget.given_back.notify_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc;

    #[test]
    fn a_render_larger_than_the_budget_is_refused_naming_the_flag() {
        let budget = MemoryBudget::new(10 << 20);
        let no = AtomicBool::new(false);
        let Err(Refusal::TooLarge(message)) = budget.reserve(11 << 20, "a 100×100 render", &no)
        else {
            panic!("granted");
        };
        assert!(
            message.contains("a 100×100 render needs about 11 MiB"),
            "{message}"
        );
        assert!(message.contains("--max-render-memory"), "{message}");
        assert_eq!(budget.held(), 0);
    }

    /// The finding: renders that each fit passed one by one and aborted together. Here the
    /// second waits until the first gives its memory back (an event, not a time).
    #[test]
    fn renders_that_do_not_fit_together_take_turns() {
        let budget = MemoryBudget::new(100);
        let no = AtomicBool::new(false);
        let first = budget.reserve(60, "first", &no).expect("fits");
        let (took, taken) = mpsc::channel();
        std::thread::scope(|scope| {
            scope.spawn(|| {
                let second = budget.reserve(60, "second", &no).expect("fits once alone");
                took.send(budget.held()).expect("sent");
                drop(second);
            });
            // It cannot have its memory while the first holds 60 of 100.
            assert!(taken.recv_timeout(Duration::from_millis(200)).is_err());
            assert_eq!(budget.held(), 60);
            drop(first);
            let held = taken
                .recv_timeout(Duration::from_secs(60))
                .expect("the second went ahead once the first was done");
            assert_eq!(held, 60);
        });
        assert_eq!(budget.held(), 0);
    }

    #[test]
    fn a_waiting_render_that_is_cancelled_gives_up() {
        let budget = MemoryBudget::new(100);
        let no = AtomicBool::new(false);
        let _first = budget.reserve(100, "first", &no).expect("fits");
        let cancel = AtomicBool::new(false);
        std::thread::scope(|scope| {
            let waiting = scope.spawn(|| budget.reserve(1, "second", &cancel).map(|_| ()));
            cancel.store(true, Ordering::Relaxed);
            assert_eq!(waiting.join().expect("returned"), Err(Refusal::Cancelled));
        });
        assert_eq!(budget.held(), 100);
    }
}
