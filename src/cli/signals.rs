//! Ctrl-C and SIGTERM for `run` and `batch`.
//!
//! The first signal sets the cancel flag the pipeline and the batch loop
//! watch ([`grime::progress::Progress`]): the image being aged stops, a
//! batch starts no new image and prints its summary so far (JSON too with
//! `--json`), and grime exits with 130. Temporary files of interrupted
//! writes are removed as those writes fail. A second signal removes every
//! temporary file still being written and exits at once.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

static CANCEL: AtomicBool = AtomicBool::new(false);
static SIGNALS: AtomicUsize = AtomicUsize::new(0);

/// The exit code after an interruption (128 + SIGINT).
pub const EXIT_INTERRUPTED: i32 = 130;

/// Installs the handler (once; later calls do nothing).
pub fn install() {
    // ctrlc runs the handler on its own thread, so it may take locks and
    // touch files.
    let _ = ctrlc::set_handler(|| {
        CANCEL.store(true, Ordering::Relaxed);
        if SIGNALS.fetch_add(1, Ordering::Relaxed) >= 1 {
            grime::io::temp::remove_live();
            eprintln!("grime: interrupted twice; stopped at once");
            std::process::exit(EXIT_INTERRUPTED);
        }
    });
}

/// The flag a signal sets; give it to [`grime::progress::Progress::new`]
/// or `grime::batch::run`.
pub fn cancel_flag() -> &'static AtomicBool {
    &CANCEL
}

/// True once Ctrl-C or SIGTERM has arrived.
pub fn interrupted() -> bool {
    CANCEL.load(Ordering::Relaxed)
}
