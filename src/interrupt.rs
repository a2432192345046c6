//! SIGINT and SIGTERM end a run cleanly. [`install`] makes either signal set a flag
//! (signal-hook); the step loop reads it after every step ([`guard`] puts it in the
//! controller's [`Guard`]) and stops with [`Interrupted`], so the run's staging folder is
//! removed and the output folder keeps its previous complete content. A second signal
//! while the first is being handled ends the process at once (exit status 130).
use impact_core::controller::Guard;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();

/// A run stopped by SIGINT or SIGTERM (the CLI exits with status 130).
#[derive(Debug, thiserror::Error)]
#[error("{0} (stopped by a signal; the output folder keeps its previous content)")]
pub struct Interrupted(pub String);

/// Route SIGINT and SIGTERM to the stop flag (once per process).
pub fn install() -> std::io::Result<()> {
    let flag = FLAG.get_or_init(|| Arc::new(AtomicBool::new(false)));
    for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        // the conditional shutdown first: it acts only when the flag is already set
        signal_hook::flag::register_conditional_shutdown(signal, 130, Arc::clone(flag))?;
        signal_hook::flag::register(signal, Arc::clone(flag))?;
    }
    Ok(())
}

/// The stop flag, made without signal handlers where [`install`] did not run: a host
/// that handles the signals itself (the Python package: `KeyboardInterrupt`) sets it to
/// stop the run between two steps, and clears it once the run has returned.
pub fn stop_flag() -> &'static AtomicBool {
    FLAG.get_or_init(|| Arc::new(AtomicBool::new(false)))
}

/// The stop flag, once [`install`] ran.
pub fn flag() -> Option<&'static AtomicBool> {
    FLAG.get().map(|f| &**f)
}

/// The default guard with the stop flag.
pub fn guard() -> Guard {
    Guard {
        stop: flag(),
        ..Guard::default()
    }
}

/// `Err(Interrupted)` once a signal arrived (checked before an output folder is committed).
pub fn check() -> Result<(), Interrupted> {
    if flag().is_some_and(|f| f.load(Ordering::Relaxed)) {
        return Err(Interrupted("interrupted while writing outputs".into()));
    }
    Ok(())
}
