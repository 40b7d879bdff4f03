//! Background threads yield the CPU to the window.
//!
//! Without a GPU the window is drawn by Mesa's llvmpipe, whose rasteriser
//! threads share the machine's cores with the simulation. A trajectory that
//! streams without end keeps one core busy and took the bifurcation tab's
//! frame from 12.7–15.0 ms to 14.1–18.4 ms (README, "The window"). At a
//! lower scheduling priority the simulation still gets every cycle the
//! window leaves idle, so on an otherwise idle machine it loses next to
//! nothing, while the frame no longer waits for it.

/// The nice value the worker's threads run at (0 is the default, 19 the
/// lowest priority).
pub const WORKER_NICE: i32 = 10;

/// Lowers the calling thread's scheduling priority to [`WORKER_NICE`]. On
/// Linux the nice value is per thread. Elsewhere, or if the call fails (a
/// sandbox may forbid it), the thread simply keeps its priority: this is
/// a courtesy to the window, never a reason to fail.
pub fn lower_current_thread() {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: gettid takes no arguments and cannot fail; setpriority
        // only reads its three integer arguments.
        unsafe {
            let tid = libc::syscall(libc::SYS_gettid) as libc::id_t;
            libc::setpriority(libc::PRIO_PROCESS, tid, WORKER_NICE);
        }
    }
}

/// The calling thread's nice value (Linux; `None` elsewhere).
pub fn current_thread_nice() -> Option<i32> {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: as above. getpriority returns the nice value (−1 is also
        // a valid value, so errno would be needed to tell an error; a
        // thread can always read its own priority).
        unsafe {
            let tid = libc::syscall(libc::SYS_gettid) as libc::id_t;
            return Some(libc::getpriority(libc::PRIO_PROCESS, tid));
        }
    }
    #[allow(unreachable_code)]
    None
}
