//! Ctrl-C, `SIGTERM`, `SIGHUP` and `SIGQUIT` (Unix): an interrupted run removes its unfinished
//! output files (hidden temporaries beside the outputs, `camloc_store::remove_unfinished`),
//! then ends as the signal would have ended it, so that a shell sees a command killed by Ctrl-C
//! and stops its loop or script. Nothing the run would replace has been touched, unless its
//! files were already being moved into place, which ends first.

/// Installs the handler for the signals the process was not started with ignored: `nohup`
/// ignores `SIGHUP`, and a shell ignores `SIGINT` in the commands it runs in the background;
/// those stay ignored. Without a handler (the platform refused one, or not Unix) a signal ends
/// the run as before.
pub fn install() {
    #[cfg(unix)]
    unix::install();
}

#[cfg(unix)]
mod unix {
    use std::sync::mpsc;
    use std::time::Duration;

    use camloc::store::{Unfinished, remove_unfinished};
    use signal_hook::consts::{SIGHUP, SIGINT, SIGQUIT, SIGTERM};
    use signal_hook::iterator::Signals;

    /// How long the handler waits for its message to be written before it ends the process
    /// (a standard error nobody reads, a full pipe, must not keep the run alive).
    const MESSAGE_WAIT: Duration = Duration::from_secs(1);

    /// See [`super::install`].
    pub fn install() {
        let handled: Vec<libc::c_int> = [SIGINT, SIGTERM, SIGHUP, SIGQUIT]
            .into_iter()
            .filter(|&signal| !ignored(signal))
            .collect();
        let Ok(mut signals) = Signals::new(&handled) else {
            return;
        };
        let _ = std::thread::Builder::new()
            .name("camloc signals".to_owned())
            .spawn(move || {
                if let Some(signal) = signals.forever().next() {
                    clean_up();
                    end_by(signal);
                }
            });
    }

    /// Ends the process by `signal`'s default action (killed by it, as without a handler), or,
    /// where that action does not end it (the first process of a container, which the kernel
    /// does not let default actions kill), by exiting with 128 + the signal's number, as a
    /// shell reports a killed command.
    fn end_by(signal: libc::c_int) -> ! {
        // SAFETY: plain calls on a signal number and a local signal set: the default action
        // back, the signal unblocked in this thread, then sent to it.
        unsafe {
            libc::signal(signal, libc::SIG_DFL);
            let mut set: libc::sigset_t = std::mem::zeroed();
            libc::sigemptyset(&mut set);
            libc::sigaddset(&mut set, signal);
            libc::pthread_sigmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut());
            libc::raise(signal);
        }
        std::process::exit(128 + signal)
    }

    /// Whether `signal` is ignored now (as the process was started).
    fn ignored(signal: libc::c_int) -> bool {
        // SAFETY: a null new action only reads the current one into `old`, a plain C struct
        // for which all zero bytes are a valid value.
        let mut old: libc::sigaction = unsafe { std::mem::zeroed() };
        let read = unsafe { libc::sigaction(signal, std::ptr::null(), &mut old) };
        read == 0 && old.sa_sigaction == libc::SIG_IGN
    }

    /// Removes the unfinished output files, saying first what it waits for and removes. The
    /// messages go out from their own thread, straight to descriptor 2 (not through Rust's
    /// standard error, whose lock the interrupted thread may hold), failures ignored: a
    /// standard error that cannot be written, or a pipe nobody reads, delays nothing.
    fn clean_up() {
        let (say, said) = mpsc::channel::<String>();
        let (done, written) = mpsc::channel::<()>();
        let _ = std::thread::Builder::new()
            .name("camloc interrupted".to_owned())
            .spawn(move || {
                for message in said {
                    let text = format!("\ncamloc: {message}\n");
                    // SAFETY: writes at most `text.len()` bytes from `text`'s buffer.
                    let _ = unsafe { libc::write(2, text.as_ptr().cast(), text.len()) };
                }
                let _ = done.send(());
            });
        remove_unfinished(|state| {
            let message = match state {
                Unfinished::Moving => {
                    "interrupted; waiting for the output files being moved into place".to_owned()
                }
                Unfinished::Removing(1) => "interrupted; removing 1 unfinished output file".into(),
                Unfinished::Removing(n) => {
                    format!("interrupted; removing {n} unfinished output files")
                }
                Unfinished::Written => "interrupted after its output files were written".into(),
                Unfinished::Nothing => "interrupted".into(),
            };
            let _ = say.send(message);
        });
        drop(say);
        let _ = written.recv_timeout(MESSAGE_WAIT);
    }
}
