//! Panics inside FMI calls, as messages. A panic within a call (a defect, or a restored
//! state whose meaning the checks did not catch) is caught by [`crate::ffi`] and
//! reported through the master's logger as fmi2Error; the panic hook installed here
//! keeps the default hook from also printing it (and a backtrace) on the host's stderr,
//! and records where it happened for that message.
//!
//! The hook is process-wide, as Rust's panic hook is: while any FMI call of this library
//! is running it records the first panic's message and place instead of printing them
//! (a solver panic may happen on a worker thread of the thread pool, not on the calling
//! thread); at any other time it hands the panic to the hook it replaced.

use std::any::Any;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, Once};

/// FMI calls of this library in progress (on any thread).
static ACTIVE: AtomicUsize = AtomicUsize::new(0);
/// The first panic recorded during a call: "message at file:line:column".
static LAST: Mutex<Option<String>> = Mutex::new(None);
static INSTALL: Once = Once::new();

fn install() {
    INSTALL.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if ACTIVE.load(Ordering::SeqCst) == 0 {
                return previous(info);
            }
            let place = info
                .location()
                .map(|l| format!(" at {}:{}:{}", l.file(), l.line(), l.column()))
                .unwrap_or_default();
            let text = format!("{}{place}", message(info.payload()));
            if let Ok(mut last) = LAST.lock() {
                last.get_or_insert(text);
            }
        }));
    });
}

/// The text of a panic payload.
fn message(payload: &(dyn Any + Send)) -> String {
    payload
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "panic".to_string())
}

/// Run `f`, catching a panic as its message and place.
pub fn catch<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    install();
    if ACTIVE.fetch_add(1, Ordering::SeqCst) == 0 {
        // a panic caught inside an earlier call (not by us) is not this call's
        if let Ok(mut last) = LAST.lock() {
            *last = None;
        }
    }
    let r = catch_unwind(AssertUnwindSafe(f));
    ACTIVE.fetch_sub(1, Ordering::SeqCst);
    r.map_err(|p| {
        let recorded = LAST.lock().ok().and_then(|mut l| l.take());
        recorded.unwrap_or_else(|| message(p.as_ref()))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_its_message_and_place() {
        let e = catch(|| -> u32 { panic!("index 7 out of range") }).unwrap_err();
        assert!(e.starts_with("index 7 out of range at "), "{e}");
        assert!(e.contains("panics.rs:"), "{e}");
        assert_eq!(catch(|| 3), Ok(3));
        // nothing is left over for the next call
        let e = catch(|| -> u32 { panic!("second") }).unwrap_err();
        assert!(e.starts_with("second at "), "{e}");
    }
}
