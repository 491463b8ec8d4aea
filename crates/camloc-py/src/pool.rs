//! Rayon's work in a process forked from the one that imported camloc (Python's
//! `multiprocessing` with the `fork` start method): the global pool's threads, started in the
//! parent, do not exist in the child, and work given to them waits forever. Such a child runs
//! its work on a pool of its own ([`run`]).

use std::sync::{Arc, Mutex, OnceLock};

use rayon::ThreadPool;

/// The process that imported camloc ([`note_importing_process`]).
static IMPORTING_PROCESS: OnceLock<u32> = OnceLock::new();

/// A forked process's own pool, with the process id it was built in.
static FORKED_POOL: Mutex<Option<(u32, Arc<ThreadPool>)>> = Mutex::new(None);

/// Records the current process as the one that imported camloc (at the module's import).
pub(crate) fn note_importing_process() {
    IMPORTING_PROCESS.get_or_init(std::process::id);
}

/// Runs `work` (which may use rayon): on the global pool in the process that imported camloc,
/// on a pool of the current process's own in a process forked from it (built at its first
/// call). Should that pool not start, `work` runs as it is.
pub(crate) fn run<R: Send>(work: impl FnOnce() -> R + Send) -> R {
    let process = std::process::id();
    if IMPORTING_PROCESS.get() == Some(&process) {
        return work();
    }
    let pool = {
        let mut slot = FORKED_POOL.lock().unwrap_or_else(|e| e.into_inner());
        match &*slot {
            Some((owner, pool)) if *owner == process => Some(Arc::clone(pool)),
            _ => rayon::ThreadPoolBuilder::new().build().ok().map(|pool| {
                let pool = Arc::new(pool);
                *slot = Some((process, Arc::clone(&pool)));
                pool
            }),
        }
    };
    match pool {
        Some(pool) => pool.install(work),
        None => work(),
    }
}
