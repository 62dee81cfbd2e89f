//! Cancellation shared by every long computation.
//!
//! A [`Cancel`] is a cheap, cloneable token. The caller (the command line on Ctrl-C or
//! SIGTERM, the Python binding on `KeyboardInterrupt`, the server when a client cancels)
//! keeps one clone and calls [`Cancel::cancel`]; each long stage (the greedy, the local
//! search, the certificate, the exact and exhaustive searches, the pictures) polls
//! [`Cancel::is_cancelled`] between units of work short enough that it stops within a
//! fraction of a second, keeps what it has recorded and returns [`Cancelled`] (or its own
//! error variant wrapping it).
//!
//! Polling is a relaxed atomic load: cheap enough to do once per candidate, per Newton step
//! or per picture row. A token made with [`Cancel::never`] holds no flag and is never
//! cancelled.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A cancellation token; clones share one flag.
#[derive(Clone, Debug, Default)]
pub struct Cancel {
    flag: Option<Arc<AtomicBool>>,
}

/// The error of a computation that stopped because its [`Cancel`] token was set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("cancelled")]
pub struct Cancelled;

impl Cancel {
    /// A token that can be cancelled (through any of its clones).
    pub fn new() -> Self {
        Cancel {
            flag: Some(Arc::new(AtomicBool::new(false))),
        }
    }

    /// A token that is never cancelled.
    pub fn never() -> Self {
        Cancel { flag: None }
    }

    /// Asks every computation polling this token (or a clone) to stop. Does nothing on
    /// [`Cancel::never`].
    pub fn cancel(&self) {
        if let Some(f) = &self.flag {
            f.store(true, Ordering::Relaxed);
        }
    }

    /// Whether [`Cancel::cancel`] was called on this token or a clone.
    pub fn is_cancelled(&self) -> bool {
        self.flag
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
    }

    /// `Err(Cancelled)` once the token is cancelled: `cancel.check()?` between units of work.
    pub fn check(&self) -> Result<(), Cancelled> {
        if self.is_cancelled() {
            Err(Cancelled)
        } else {
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clones_share_the_flag() {
        let a = Cancel::new();
        let b = a.clone();
        assert!(!b.is_cancelled());
        assert_eq!(b.check(), Ok(()));
        a.cancel();
        assert!(b.is_cancelled());
        assert_eq!(b.check(), Err(Cancelled));
    }

    #[test]
    fn never_is_never_cancelled() {
        let n = Cancel::never();
        n.cancel();
        assert!(!n.is_cancelled());
        assert!(!Cancel::default().is_cancelled());
    }
}
