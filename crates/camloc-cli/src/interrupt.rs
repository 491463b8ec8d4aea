//! Ctrl-C, `SIGTERM` and `SIGHUP`: an interrupted run removes its unfinished output files
//! (hidden temporaries beside the outputs, `camloc_store::remove_unfinished`) and exits with
//! [`EXIT_INTERRUPTED`]; nothing it would replace has been touched unless its files were
//! already being moved into place, which ends first.

/// The exit code of a run ended by Ctrl-C, `SIGTERM` or `SIGHUP` (128 + SIGINT's number, as
/// shells report an interrupted command).
pub const EXIT_INTERRUPTED: i32 = 130;

/// Installs the handler. A signal the process was started with ignored stays ignored: `nohup`
/// ignores `SIGHUP`, and a shell ignores `SIGINT` in the commands it runs in the background.
/// Without a handler (the platform refused one) a signal ends the run as before.
pub fn install() {
    let ignored = inherited::ignored();
    if ctrlc::set_handler(on_signal).is_ok() {
        inherited::ignore_again(&ignored);
    }
}

/// What the handler does: says what it removes (deleting thousands of files takes seconds),
/// removes it and ends the process. The message is written so that a standard error that
/// cannot be written (a closed terminal) cannot stop the exit.
fn on_signal() {
    camloc::store::remove_unfinished(|count, placed| {
        let message = match (count, placed) {
            (0, true) => "camloc: interrupted after its output files were written".to_string(),
            (0, false) => "camloc: interrupted".to_string(),
            (1, _) => "camloc: interrupted; removing 1 unfinished output file".to_string(),
            (n, _) => format!("camloc: interrupted; removing {n} unfinished output files"),
        };
        inherited::write_error(&format!("\n{message}\n"));
    });
    std::process::exit(EXIT_INTERRUPTED);
}

/// The signals' dispositions the process was started with (Unix).
#[cfg(unix)]
mod inherited {
    /// The signals the handler is installed for (`ctrlc` with its `termination` feature).
    const SIGNALS: [libc::c_int; 3] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP];

    /// The signals of [`SIGNALS`] that are ignored now.
    pub fn ignored() -> Vec<libc::c_int> {
        SIGNALS
            .into_iter()
            .filter(|&signal| {
                // SAFETY: a null new action only reads the current one into `old`, a plain
                // C struct for which all zero bytes are a valid value.
                let mut old: libc::sigaction = unsafe { std::mem::zeroed() };
                let read = unsafe { libc::sigaction(signal, std::ptr::null(), &mut old) };
                read == 0 && old.sa_sigaction == libc::SIG_IGN
            })
            .collect()
    }

    /// Ignores `signals` again (after the handler was installed for them).
    pub fn ignore_again(signals: &[libc::c_int]) {
        for &signal in signals {
            // SAFETY: setting a signal's disposition to "ignore" has no other effect.
            unsafe { libc::signal(signal, libc::SIG_IGN) };
        }
    }

    /// Writes `text` to descriptor 2 directly, ignoring failures, without the lock of Rust's
    /// standard error (which the interrupted thread may hold).
    pub fn write_error(text: &str) {
        // SAFETY: writes at most `text.len()` bytes from `text`'s buffer.
        let _ = unsafe { libc::write(2, text.as_ptr().cast(), text.len()) };
    }
}

/// Other platforms: no dispositions are read; the message goes through standard error,
/// failures ignored.
#[cfg(not(unix))]
mod inherited {
    pub fn ignored() -> Vec<i32> {
        Vec::new()
    }

    pub fn ignore_again(_: &[i32]) {}

    pub fn write_error(text: &str) {
        use std::io::Write;
        let _ = std::io::stderr().write_all(text.as_bytes());
    }
}
