//! Background threads that use mostly the cores a computation leaves idle.
//!
//! A run's computation keeps a two-core machine's cores busy most of the time, and some of its
//! side work (saving each iteration's files, the viewer's gravity deflections solved ahead)
//! can wait. Such a thread gives itself the lowest priority of the normal scheduling class
//! (nice 19): while the computation's threads want the cores it gets little of them, so the
//! work is done mostly in the computation's gaps (docs/benchmarks.md, *Figures behind the
//! code's rules*).
//!
//! The rule for using it: the computation never waits for such a thread. While other programs
//! keep every core busy it gets little CPU time, and an unprivileged thread cannot raise its
//! priority again. Its work is either abandonable (whoever needs it and finds it not done does
//! it at its own priority, as the gravity deflections are) or handed to a thread at the
//! computation's priority the moment the computation would wait (the run's writer and its
//! relief, `io::background`).
//!
//! Why not Linux's idle class (`SCHED_IDLE`), which runs a thread only on a core nobody else
//! wants: with two other programs keeping both cores busy, a thread of that class got so
//! little time that a process with one busy such thread took 0.9–1.3 s to end instead of
//! 0.1 s (the kernel ends a process's threads one by one, each when it next runs; nice 19:
//! 0.10–0.18 s), and a run waiting on its writer in that class took seven times as long.

/// Gives the calling thread the lowest priority of its scheduling class (nice 19). Best
/// effort: a refusal leaves it as it was. Elsewhere than on Linux the thread keeps its
/// priority.
pub fn background_priority() {
    #[cfg(target_os = "linux")]
    {
        #[allow(unsafe_code)]
        // SAFETY: gettid takes no argument; setpriority on a thread id changes only that
        // thread's nice value (Linux keeps it per thread) and touches no memory.
        let _ = unsafe {
            let tid = libc::gettid();
            libc::setpriority(libc::PRIO_PROCESS, tid as libc::id_t, 19)
        };
    }
}
