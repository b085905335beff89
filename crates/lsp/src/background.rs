//! Threads for work nobody is waiting on right now: the check of a file
//! after an edit, its helper, re-publishing, verification runs. They run at a lower CPU
//! priority than the threads answering requests, so that a hover or a jump
//! to a definition sent while a large file is being checked gets a core
//! first; when nothing else wants the CPU, background work runs at full
//! speed. Threads of tokio's shared blocking pool are not used for this: a
//! thread's priority cannot be raised back without privileges.

use std::sync::Arc;

use crate::state::Shared;

/// How much lower than the server's: on Linux's scheduler a nice value 5
/// higher gives a thread about a third of the weight, so two busy
/// background threads on two cores leave a request thread a whole core.
#[cfg(target_os = "linux")]
const NICE_INCREMENT: i32 = 5;

/// Runs `f` on a new background thread; on the runtime's blocking pool when
/// no thread can be started.
pub(crate) fn spawn(shared: &Arc<Shared>, name: &str, f: impl FnOnce() + Send + 'static) {
    // `f` moves into the thread or, if that fails, to the pool: keep it in
    // an Option the failure path can take back.
    let slot = Arc::new(std::sync::Mutex::new(Some(f)));
    let for_thread = slot.clone();
    let nice = shared.background_nice;
    let spawned = std::thread::Builder::new()
        .name(name.to_string())
        // As the runtime's threads: analyses recurse over syntax trees.
        .stack_size(16 << 20)
        .spawn(move || {
            lower_priority(nice);
            let f = for_thread.lock().unwrap_or_else(|e| e.into_inner()).take();
            if let Some(f) = f {
                f();
            }
        });
    if spawned.is_err() {
        if let Some(f) = slot.lock().unwrap_or_else(|e| e.into_inner()).take() {
            shared.runtime.spawn_blocking(f);
        }
    }
}

/// The nice value one step below the calling thread's (`None` where
/// priorities are not handled).
pub(crate) fn level_below_caller() -> Option<i32> {
    #[cfg(target_os = "linux")]
    {
        current_nice().map(|n| (n + NICE_INCREMENT).min(19))
    }
    #[cfg(not(target_os = "linux"))]
    {
        None
    }
}

#[cfg(target_os = "linux")]
fn current_nice() -> Option<i32> {
    // SAFETY: plain system calls on the calling thread (`who` 0); errno is
    // thread-local and reset first, as getpriority's -1 can be a real value.
    unsafe {
        *libc::__errno_location() = 0;
        let n = libc::getpriority(libc::PRIO_PROCESS, 0);
        (*libc::__errno_location() == 0).then_some(n)
    }
}

/// Moves the calling thread down to `nice` (Linux keeps a nice value per
/// thread, and threads it starts inherit it), never up; best effort.
pub(crate) fn lower_priority(nice: Option<i32>) {
    #[cfg(target_os = "linux")]
    if let (Some(target), Some(current)) = (nice, current_nice()) {
        if target > current {
            // SAFETY: a plain system call on the calling thread.
            unsafe {
                libc::setpriority(libc::PRIO_PROCESS, 0, target);
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = nice;
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use std::sync::mpsc::channel;

    use super::current_nice;

    #[test]
    fn background_threads_run_one_level_lower_however_deep() {
        let before = current_nice().unwrap();
        let runtime = tokio::runtime::Runtime::new().unwrap();
        let shared = crate::state::Shared::new(runtime.handle().clone());
        let (tx, rx) = channel();
        let inner = shared.clone();
        // A background thread that starts another, as a check starts its
        // helper: both at the same level.
        super::spawn(&shared, "test-background", move || {
            tx.send(current_nice()).unwrap();
            let tx2 = tx.clone();
            super::spawn(&inner, "test-nested", move || tx2.send(current_nice()).unwrap());
        });
        let expected = Some((before + super::NICE_INCREMENT).min(19));
        assert_eq!(rx.recv().unwrap(), expected);
        assert_eq!(rx.recv().unwrap(), expected, "a nested background thread sank further");
        assert_eq!(current_nice(), Some(before), "the calling thread kept its priority");
    }
}
