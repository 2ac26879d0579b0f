//! Stopping long work early ([`Interrupt`]): a deadline, a flag another thread sets (the
//! server sets it when the client of a request has gone), or both. A photo's fit
//! ([`crate::fit::fit_scene_until`]) looks at one before each start and each
//! Levenberg-Marquardt iteration; the room fit ([`crate::room::fit_room_until`]) before each
//! photo's own fit (and inside it, as a photo's fit), before each placement hypothesis and at
//! every evaluation of its Levenberg-Marquardt iterations;
//! `vpmap_vision`'s box proposals before each candidate corner. Without a deadline or a flag
//! ([`Interrupt::default`]) nothing is ever interrupted.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// When long work must stop early (see the [module docs](self)).
///
/// # Example
/// ```
/// use std::sync::{Arc, atomic::{AtomicBool, Ordering}};
/// use vpmap_metrology::interrupt::{Interrupt, Interruption};
/// let flag = Arc::new(AtomicBool::new(false));
/// let stop = Interrupt::default().with_flag(Arc::clone(&flag));
/// assert_eq!(stop.check(), None);
/// flag.store(true, Ordering::Relaxed);
/// assert_eq!(stop.check(), Some(Interruption::Cancelled));
/// ```
#[derive(Clone, Debug, Default)]
pub struct Interrupt {
    /// The deadline and the time it allowed when it was set.
    deadline: Option<(Instant, Duration)>,
    /// Set by another thread to stop the work.
    flag: Option<Arc<AtomicBool>>,
}

/// Why an [`Interrupt`] stopped the work.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Interruption {
    /// The deadline passed.
    TimeLimit {
        /// The time the deadline allowed, seconds.
        allowed_s: f64,
    },
    /// The flag was set (the request was cancelled: its client has gone).
    Cancelled,
}

impl std::fmt::Display for Interruption {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::TimeLimit { allowed_s } => {
                write!(
                    f,
                    "it did not finish within its time limit of {allowed_s:.1} s"
                )
            }
            Self::Cancelled => write!(f, "the request was cancelled"),
        }
    }
}

impl Interrupt {
    /// Stop `timeout` from now (or at the earlier deadline already set).
    #[must_use]
    pub fn with_timeout(self, timeout: Duration) -> Self {
        match Instant::now().checked_add(timeout) {
            Some(at) => self.with_deadline(at),
            None => self,
        }
    }

    /// Stop at `deadline` (or at the earlier deadline already set).
    #[must_use]
    pub fn with_deadline(mut self, deadline: Instant) -> Self {
        let allowed = deadline.saturating_duration_since(Instant::now());
        if self.deadline.is_none_or(|(at, _)| deadline < at) {
            self.deadline = Some((deadline, allowed));
        }
        self
    }

    /// Stop when `flag` is set.
    #[must_use]
    pub fn with_flag(mut self, flag: Arc<AtomicBool>) -> Self {
        self.flag = Some(flag);
        self
    }

    /// Whether the work must stop now, and why (the flag first).
    #[must_use]
    pub fn check(&self) -> Option<Interruption> {
        if self
            .flag
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
        {
            return Some(Interruption::Cancelled);
        }
        match self.deadline {
            Some((at, allowed)) if Instant::now() >= at => Some(Interruption::TimeLimit {
                allowed_s: allowed.as_secs_f64(),
            }),
            _ => None,
        }
    }
}

impl PartialEq for Interrupt {
    /// The same deadline and the same flag (not merely an equal one).
    fn eq(&self, other: &Self) -> bool {
        self.deadline == other.deadline
            && match (&self.flag, &other.flag) {
                (None, None) => true,
                (Some(a), Some(b)) => Arc::ptr_eq(a, b),
                _ => false,
            }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_deadline_in_the_past_stops_at_once_and_none_never_stops() {
        assert_eq!(Interrupt::default().check(), None);
        let past = Interrupt::default().with_timeout(Duration::ZERO);
        assert!(matches!(past.check(), Some(Interruption::TimeLimit { .. })));
        let later = Interrupt::default().with_timeout(Duration::from_secs(3600));
        assert_eq!(later.check(), None);
        // The earlier deadline holds.
        assert!(later.with_timeout(Duration::ZERO).check().is_some());
        let text = Interruption::TimeLimit { allowed_s: 6.0 }.to_string();
        assert_eq!(text, "it did not finish within its time limit of 6.0 s");
    }
}
