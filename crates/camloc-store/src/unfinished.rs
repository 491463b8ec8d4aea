//! The temporary files of the outputs still being written, kept on one list so that an
//! interrupted run can remove them ([`remove_unfinished`]) instead of leaving hidden
//! `.NAME.XXXXXX.tmp` files beside its outputs.

use std::collections::HashSet;
use std::io;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, MutexGuard};

use tempfile::NamedTempFile;

/// The temporary files in the making (written or staged, not yet moved into place).
static UNFINISHED: Mutex<Option<HashSet<PathBuf>>> = Mutex::new(None);

/// Held while files are moved into place, so that an interrupt waits for the moves (and a
/// failed commit's roll-back) to end: a user's replaced file is never left under a
/// temporary name.
static MOVING: Mutex<()> = Mutex::new(());

/// Set once files have been moved into place in this process ([`placed`]).
static PLACED: AtomicBool = AtomicBool::new(false);

/// `mutex` locked, whether or not a thread panicked while holding it.
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// A temporary file's place on the list of unfinished ones, which it leaves when this is
/// dropped: after the file was moved into place, or with the file (whose own drop deletes
/// it).
#[derive(Debug)]
pub(crate) struct Listed(PathBuf);

impl Listed {
    /// Creates a temporary file with `create` and puts it on the list, both under the list's
    /// lock, so that an interrupt cannot fall between them.
    pub(crate) fn create(
        create: impl FnOnce() -> io::Result<NamedTempFile>,
    ) -> io::Result<(NamedTempFile, Listed)> {
        let mut list = lock(&UNFINISHED);
        let file = create()?;
        let path = file.path().to_path_buf();
        list.get_or_insert_with(HashSet::new).insert(path.clone());
        Ok((file, Listed(path)))
    }
}

impl Drop for Listed {
    fn drop(&mut self) {
        if let Some(list) = lock(&UNFINISHED).as_mut() {
            list.remove(&self.0);
        }
    }
}

/// Holds off [`remove_unfinished`] while files are moved into place (until the guard is
/// dropped).
pub(crate) fn moving() -> MutexGuard<'static, ()> {
    lock(&MOVING)
}

/// Records that output files were moved into place (for [`remove_unfinished`]'s `announce`).
pub(crate) fn placed() {
    PLACED.store(true, Ordering::Relaxed);
}

/// What [`remove_unfinished`] tells its caller, in order, so that an interrupted run can say
/// what it is waiting for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unfinished {
    /// Files are being moved into place; they are waited for (thousands of replaced files
    /// take seconds). Told before the waiting.
    Moving,
    /// This many temporary files are about to be removed (thousands of files take a while).
    Removing(usize),
    /// No temporary file is left, and output files were moved into place in this process.
    Written,
    /// No temporary file is left, and none was moved into place.
    Nothing,
}

/// Removes every temporary output file still in the making. For an interrupted run (Ctrl-C, `SIGTERM`): it first waits for files being moved into
/// place to be in place (or put back), telling `announce` ([`Unfinished::Moving`]) before it
/// waits, then tells `announce` what it finds ([`Unfinished::Removing`], `Written` or
/// `Nothing`), removes the temporaries, and keeps the list locked afterwards, so that no new
/// temporary is made before the process ends. Call it only right before ending the process.
pub fn remove_unfinished(mut announce: impl FnMut(Unfinished)) {
    let moving = match MOVING.try_lock() {
        Ok(guard) => guard,
        Err(std::sync::TryLockError::Poisoned(poisoned)) => poisoned.into_inner(),
        Err(std::sync::TryLockError::WouldBlock) => {
            announce(Unfinished::Moving);
            lock(&MOVING)
        }
    };
    let mut list = lock(&UNFINISHED);
    let paths = list.take().unwrap_or_default();
    announce(match paths.len() {
        0 if PLACED.load(Ordering::Relaxed) => Unfinished::Written,
        0 => Unfinished::Nothing,
        n => Unfinished::Removing(n),
    });
    for path in &paths {
        // Nothing more can be done for a file that cannot be removed (or is gone already).
        let _ = std::fs::remove_file(path);
    }
    // Neither lock is released: the process is about to end.
    std::mem::forget(list);
    std::mem::forget(moving);
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    fn listed(path: &Path) -> bool {
        lock(&UNFINISHED)
            .as_ref()
            .is_some_and(|list| list.contains(path))
    }

    #[test]
    fn a_file_is_listed_until_its_place_is_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let (file, place) =
            Listed::create(|| tempfile::Builder::new().tempfile_in(dir.path())).unwrap();
        let path = file.path().to_path_buf();
        assert!(listed(&path));
        file.into_temp_path()
            .persist(dir.path().join("out"))
            .unwrap();
        assert!(listed(&path));
        drop(place);
        assert!(!listed(&path));
        assert!(dir.path().join("out").exists());
    }
}
