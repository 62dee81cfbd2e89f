//! Background threads that use only the cores a computation leaves idle.
//!
//! A run's computation keeps a two-core machine's cores busy most of the time, and its side
//! work (the files of each iteration, the viewer's gravity deflections solved ahead) can
//! wait. Such a thread puts itself in Linux's idle scheduling class (`SCHED_IDLE`): the
//! kernel runs it only on a core no other thread wants, and preempts it as soon as one does,
//! so the computation is not slowed by work that could be done in its gaps (docs/benchmarks.md,
//! *Figures behind the code's rules*).

/// Puts the calling thread in Linux's idle scheduling class (`SCHED_IDLE`): it runs only on a
/// core no other thread wants. Best effort: a refusal leaves it as it was. Elsewhere than on
/// Linux the thread keeps its priority.
pub fn idle_priority() {
    #[cfg(target_os = "linux")]
    {
        let param = libc::sched_param { sched_priority: 0 };
        #[allow(unsafe_code)]
        // SAFETY: `param` is a valid `sched_param` that outlives the call (priority 0, as
        // SCHED_IDLE requires); pid 0 names the calling thread; nothing else is touched.
        let _ = unsafe { libc::sched_setscheduler(0, libc::SCHED_IDLE, &param) };
    }
}
