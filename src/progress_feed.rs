//! Progress for a caller that is not a terminal (the Python package): the bars a run
//! creates ([`crate::run::progress_bar`]) are registered in a [`Feed`] instead of drawn,
//! and the caller reads their state ([`Feed::snapshot`]) on its own thread, at its own
//! pace.
//!
//! Why a feed and not a callback: the stepping runs on a worker thread with the GIL
//! released, while the Python thread that called `impact.run` already wakes every 20 ms
//! to check for Ctrl-C (crates/impact-py, `detached`). Reading the feed there costs the
//! step loop nothing (a bar's position is an atomic the observer sets anyway), the
//! worker never waits on the GIL, and the Python callback runs on the caller's thread,
//! where a notebook widget (tqdm) expects to be updated. The step loop is unchanged:
//! the observers ([`crate::run::Progress`], [`crate::output::FileWriter`]) move their
//! `indicatif` bar as for the terminal; only its draw target is hidden.
//!
//! The feed is installed per thread ([`Feed::install`]): bars are created on the thread
//! that runs the study (never inside a rayon task), so two runs from two Python threads
//! each see their own bars.
use std::cell::RefCell;
use std::sync::{Arc, Mutex, PoisonError};

/// The bars created on the threads where this feed is installed, in creation order.
#[derive(Clone, Default)]
pub struct Feed {
    bars: Arc<Mutex<Vec<indicatif::ProgressBar>>>,
}

/// One bar's state: what it measures, how far it is, whether it is done.
#[derive(Debug, Clone, PartialEq)]
pub struct BarState {
    /// The bar's label: a method name (`dgmpm`, `mpm`, `fem`) or `reference`.
    pub label: String,
    /// The fraction done in `[0, 1]`: `t / t_end` of the run, to 1/1000.
    pub fraction: f64,
    /// The run behind the bar has ended (completed, stopped or failed).
    pub finished: bool,
}

thread_local! {
    static INSTALLED: RefCell<Option<Feed>> = const { RefCell::new(None) };
}

/// Removes the feed from its thread when dropped (see [`Feed::install`]).
pub struct Installed {
    previous: Option<Feed>,
}

impl Drop for Installed {
    fn drop(&mut self) {
        let previous = self.previous.take();
        INSTALLED.with(|slot| *slot.borrow_mut() = previous);
    }
}

impl Feed {
    /// Collect the bars created on this thread until the returned guard is dropped.
    pub fn install(&self) -> Installed {
        let previous = INSTALLED.with(|slot| slot.borrow_mut().replace(self.clone()));
        Installed { previous }
    }

    /// Every bar registered so far, in creation order.
    pub fn snapshot(&self) -> Vec<BarState> {
        let bars = self.bars.lock().unwrap_or_else(PoisonError::into_inner);
        bars.iter()
            .map(|bar| BarState {
                label: bar.prefix(),
                fraction: match bar.length() {
                    Some(len) if len > 0 => (bar.position() as f64 / len as f64).min(1.0),
                    _ => 0.0,
                },
                finished: bar.is_finished(),
            })
            .collect()
    }
}

/// Register `bar` with the feed installed on this thread, if any, and hide it there
/// (the feed's reader draws it); without a feed the bar draws on stderr as before.
pub(crate) fn register(bar: &indicatif::ProgressBar) {
    INSTALLED.with(|slot| {
        if let Some(feed) = slot.borrow().as_ref() {
            bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
            let mut bars = feed.bars.lock().unwrap_or_else(PoisonError::into_inner);
            bars.push(bar.clone());
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bars_reach_the_feed_of_their_thread_only() {
        let feed = Feed::default();
        let outside = crate::run::progress_bar("mpm");
        {
            let _installed = feed.install();
            let bar = crate::run::progress_bar("dgmpm");
            bar.set_position(crate::run::progress_position(0.25, 1.0));
            assert_eq!(
                feed.snapshot(),
                vec![BarState {
                    label: "dgmpm".into(),
                    fraction: 0.25,
                    finished: false
                }]
            );
            bar.finish_and_clear();
            // another thread's bars are not this feed's
            std::thread::spawn(|| crate::run::progress_bar("fem"))
                .join()
                .unwrap();
        }
        let after = crate::run::progress_bar("reference");
        let states = feed.snapshot();
        assert_eq!(states.len(), 1);
        assert!(states[0].finished && states[0].fraction == 1.0);
        drop((outside, after));
    }
}
