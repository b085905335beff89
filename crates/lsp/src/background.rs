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
    let spawned = std::thread::Builder::new()
        .name(name.to_string())
        // As the runtime's threads: analyses recurse over syntax trees.
        .stack_size(16 << 20)
        .spawn(move || {
            lower_priority();
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

/// Lowers the calling thread's priority (Linux keeps a nice value per
/// thread, and threads it starts inherit it); best effort, and nothing
/// elsewhere.
pub(crate) fn lower_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: plain system calls on the calling thread (`who` 0); errno is
    // thread-local and reset first, as getpriority's -1 can be a real value.
    unsafe {
        *libc::__errno_location() = 0;
        let current = libc::getpriority(libc::PRIO_PROCESS, 0);
        if *libc::__errno_location() == 0 {
            libc::setpriority(libc::PRIO_PROCESS, 0, (current + NICE_INCREMENT).min(19));
        }
    }
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    fn nice() -> i32 {
        // SAFETY: as in `lower_priority`.
        unsafe { libc::getpriority(libc::PRIO_PROCESS, 0) }
    }

    #[test]
    fn background_threads_run_at_a_lower_priority_and_leave_the_caller_alone() {
        let before = nice();
        let runtime = tokio::runtime::Runtime::new().unwrap();
        let shared = crate::state::Shared::new(runtime.handle().clone());
        let (tx, rx) = std::sync::mpsc::channel();
        super::spawn(&shared, "test-background", move || tx.send(nice()).unwrap());
        let theirs = rx.recv().unwrap();
        assert_eq!(theirs, (before + super::NICE_INCREMENT).min(19));
        assert_eq!(nice(), before, "the calling thread kept its priority");
    }
}
