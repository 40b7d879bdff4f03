//! What every long command shares while it runs: a time bound
//! (`--max-seconds`) and Ctrl+C, which stop it cleanly with nothing
//! written; progress, as a bar on a terminal and as a line every few
//! seconds elsewhere; and writing to stdout with its failures reported.

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

use super::CliError;
use super::values::short;

/// Set by the Ctrl+C handler; polled by every long run.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// When a long run stops early: at `--max-seconds`, or on Ctrl+C.
#[derive(Debug)]
pub struct Limits {
    start: Instant,
    max_seconds: Option<f64>,
}

impl Limits {
    /// Starts the clock and installs the Ctrl+C handler (once per process),
    /// with the watchdog that ends a run which does not stop by itself.
    pub fn start(max_seconds: Option<f64>) -> Self {
        let limits = Self::start_polled(max_seconds);
        limits.spawn_watchdog();
        limits
    }

    /// [`Limits::start`] without the watchdog, for a run that writes what it
    /// computed when stopped (`continue`): it polls between points, and
    /// ending it from outside would lose them.
    pub fn start_polled(max_seconds: Option<f64>) -> Self {
        static HANDLER: std::sync::Once = std::sync::Once::new();
        HANDLER.call_once(|| {
            // Without a handler Ctrl+C still stops the run, writing nothing.
            ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::Relaxed)).ok();
        });
        Limits {
            start: Instant::now(),
            max_seconds,
        }
    }

    /// Every long loop polls [`Limits::stop`]; a computation with no poll
    /// of its own (an interpolant being built once ran 79.5 s past
    /// `--max-seconds 2`) is ended by this thread [`STOP_GRACE`] after the
    /// bound or Ctrl+C: with the same one line and exit code 1, between
    /// file writes, and only while nothing has been written (once a command
    /// writes, it is finishing).
    fn spawn_watchdog(&self) {
        let (start, max_seconds) = (self.start, self.max_seconds);
        std::thread::Builder::new()
            .name("oneblock-limits".into())
            .spawn(move || {
                let limits = Limits { start, max_seconds };
                while !limits.stop() {
                    std::thread::sleep(Duration::from_millis(50));
                }
                std::thread::sleep(STOP_GRACE);
                let written = crate::output::writes_lock();
                if *written == 0 {
                    let e = limits.stopped(&run_name());
                    eprintln!("error: {e}");
                    std::process::exit(e.exit_code());
                }
            })
            .ok();
    }

    /// Whether the run should stop now.
    pub fn stop(&self) -> bool {
        INTERRUPTED.load(Ordering::Relaxed)
            || self
                .max_seconds
                .is_some_and(|m| self.start.elapsed().as_secs_f64() >= m)
    }

    /// The error of a run that stopped early: why, and that nothing was
    /// written (exit code 1).
    pub fn stopped(&self, what: &str) -> CliError {
        let after = self.start.elapsed().as_secs_f64();
        if INTERRUPTED.load(Ordering::Relaxed) {
            CliError::Failed(format!(
                "{what}: interrupted (Ctrl+C) after {after:.1} s: nothing was written"
            ))
        } else {
            CliError::Failed(format!(
                "{what}: stopped by --max-seconds = {} after {after:.1} s: nothing was written",
                short(self.max_seconds.unwrap_or(0.0))
            ))
        }
    }
}

/// How long a run past its bound may take to notice by itself before the
/// watchdog ends it.
pub const STOP_GRACE: Duration = Duration::from_secs(1);

/// The subcommand this process runs, for the watchdog's message.
fn run_name() -> String {
    use clap::CommandFactory as _;
    let arg = std::env::args().nth(1).unwrap_or_default();
    if super::Cli::command().find_subcommand(&arg).is_some() {
        arg
    } else {
        "oneblock".into()
    }
}

/// Runs `work` on a thread of its own and waits for it under `limits`:
/// a spinner with the time so far on a terminal (a line every
/// [`PROGRESS_EVERY`] elsewhere), and on Ctrl+C or at --max-seconds the
/// wait ends with [`Limits::stopped`] (exit 1, one line). The work is then
/// left to end with the process: it writes nothing itself, so nothing is
/// half-written. For computations with no stop hook of their own (a
/// Newton solve, a benchmark's report).
pub fn run_bounded<T: Send + 'static>(
    what: &'static str,
    limits: &Limits,
    work: impl FnOnce() -> T + Send + 'static,
) -> Result<T, CliError> {
    let (tx, rx) = crossbeam_channel::bounded(1);
    std::thread::Builder::new()
        .name(format!("oneblock-{what}"))
        .spawn(move || {
            tx.send(work()).ok();
        })
        .map_err(|e| CliError::Failed(format!("{what}: cannot start a thread: {e}")))?;
    let spinner = stderr_is_terminal().then(|| {
        let b = ProgressBar::new_spinner();
        if let Ok(style) = ProgressStyle::with_template("{spinner} {msg}, {elapsed}") {
            b.set_style(style);
        }
        b.set_message(format!("{what}: working (Ctrl+C stops)"));
        b.enable_steady_tick(Duration::from_millis(120));
        b
    });
    let clear = || {
        if let Some(b) = &spinner {
            b.finish_and_clear();
        }
    };
    let start = Instant::now();
    let mut shown = start;
    loop {
        match rx.recv_timeout(Duration::from_millis(50)) {
            Ok(v) => {
                clear();
                return Ok(v);
            }
            Err(crossbeam_channel::RecvTimeoutError::Disconnected) => {
                clear();
                return Err(CliError::Failed(format!(
                    "{what}: the computation ended without a result"
                )));
            }
            Err(crossbeam_channel::RecvTimeoutError::Timeout) => {}
        }
        if limits.stop() {
            clear();
            return Err(limits.stopped(what));
        }
        if spinner.is_none() && shown.elapsed() >= PROGRESS_EVERY {
            shown = Instant::now();
            eprintln!("{what}: working, {:.0} s", start.elapsed().as_secs_f64());
        }
    }
}

/// How often a progress line is printed when stderr is not a terminal.
pub const PROGRESS_EVERY: Duration = Duration::from_secs(5);

/// Progress of a long run, from any number of threads: a bar on a terminal,
/// else a line on stderr every [`PROGRESS_EVERY`]. The counts shown never
/// go down (they are read and shown under one lock).
pub struct Progress {
    label: &'static str,
    unit: &'static str,
    total: u64,
    done: AtomicU64,
    extra: AtomicU64,
    extra_unit: Option<&'static str>,
    bar: Option<ProgressBar>,
    shown: Mutex<Instant>,
    start: Instant,
    /// Shows nothing (the run prints lines of its own).
    silent: bool,
}

impl Progress {
    /// Progress towards `total` `unit`s (e.g. "iterates").
    pub fn new(label: &'static str, unit: &'static str, total: u64) -> Self {
        Self::build(label, unit, total, None)
    }

    /// The same with a second count shown beside it (e.g. iterates beside
    /// cells), added with [`Progress::add_extra`].
    pub fn with_extra(
        label: &'static str,
        unit: &'static str,
        total: u64,
        extra_unit: &'static str,
    ) -> Self {
        Self::build(label, unit, total, Some(extra_unit))
    }

    fn build(
        label: &'static str,
        unit: &'static str,
        total: u64,
        extra_unit: Option<&'static str>,
    ) -> Self {
        let bar = stderr_is_terminal().then(|| {
            let b = ProgressBar::new(total);
            let extra = extra_unit.map_or(String::new(), |u| format!(", {{msg}} {u}"));
            let template = format!(
                "{label} {{bar:40}} {{human_pos}}/{{human_len}} {unit}{extra}, eta {{eta}}"
            );
            if let Ok(style) = ProgressStyle::with_template(&template) {
                b.set_style(style);
            }
            b
        });
        let now = Instant::now();
        Progress {
            label,
            unit,
            total,
            done: AtomicU64::new(0),
            extra: AtomicU64::new(0),
            extra_unit,
            bar,
            shown: Mutex::new(now),
            start: now,
            silent: false,
        }
    }

    /// The same, showing nothing: for a run that prints a line per step
    /// itself.
    pub fn quiet(mut self) -> Self {
        self.bar = None;
        self.silent = true;
        self
    }

    /// Adds to the second count.
    pub fn add_extra(&self, n: u64) {
        self.extra.fetch_add(n, Ordering::Relaxed);
    }

    /// Units counted so far.
    pub fn done(&self) -> u64 {
        self.done.load(Ordering::Relaxed)
    }

    /// Counts `n` more units done.
    pub fn inc(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
        self.show();
    }

    /// Moves the count to `fraction` of the total (never back): a job's
    /// `Progress` update.
    pub fn to_fraction(&self, fraction: f64) {
        let n = (fraction.clamp(0.0, 1.0) * self.total as f64) as u64;
        self.done.fetch_max(n, Ordering::Relaxed);
        self.show();
    }

    fn show(&self) {
        if self.silent {
            return;
        }
        let now = Instant::now();
        // Only one thread shows at a time, and one that finds the lock
        // taken skips: the next call shows the newer count.
        let Ok(mut shown) = self.shown.try_lock() else {
            return;
        };
        let done = self.done.load(Ordering::Relaxed);
        let extra = self.extra.load(Ordering::Relaxed);
        match &self.bar {
            Some(b) => {
                b.set_position(done);
                if self.extra_unit.is_some() {
                    b.set_message(extra.to_string());
                }
            }
            None if now.duration_since(*shown) >= PROGRESS_EVERY => {
                *shown = now;
                let extra = self
                    .extra_unit
                    .map_or(String::new(), |u| format!(", {extra} {u}"));
                eprintln!(
                    "{}: {done} of {} {} ({:.0}%){extra}, {:.0} s",
                    self.label,
                    self.total,
                    self.unit,
                    100.0 * done as f64 / self.total.max(1) as f64,
                    now.duration_since(self.start).as_secs_f64()
                );
            }
            None => {}
        }
    }

    /// Prints a line without tearing the bar.
    pub fn println(&self, line: &str) {
        match &self.bar {
            Some(b) => b.suspend(|| eprintln!("{line}")),
            None => eprintln!("{line}"),
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

/// Whether stdout was closed when the program started. The standard
/// library then points it at /dev/null, opened read-write (a shell's
/// `> /dev/null` opens it write-only), and every write would vanish.
#[cfg(target_os = "linux")]
pub fn stdout_was_closed() -> bool {
    // SAFETY: fcntl and fstat only read the state of descriptor 1; the
    // stat buffer is a plain C struct that fstat fills.
    unsafe {
        let flags = libc::fcntl(1, libc::F_GETFL);
        if flags < 0 {
            return true;
        }
        if flags & libc::O_ACCMODE != libc::O_RDWR {
            return false;
        }
        let mut fd_stat: libc::stat = std::mem::zeroed();
        let mut null_stat: libc::stat = std::mem::zeroed();
        libc::fstat(1, &mut fd_stat) == 0
            && libc::stat(c"/dev/null".as_ptr(), &mut null_stat) == 0
            && (fd_stat.st_mode & libc::S_IFMT) == libc::S_IFCHR
            && fd_stat.st_rdev == null_stat.st_rdev
    }
}

/// Whether stdout was closed when the program started (not detectable here).
#[cfg(not(target_os = "linux"))]
pub fn stdout_was_closed() -> bool {
    false
}

/// Refuses, before any work, to run a command whose results go to a
/// closed stdout.
pub fn check_stdout() -> Result<(), CliError> {
    if stdout_was_closed() {
        Err(CliError::Failed(
            "cannot write to stdout: it is closed (redirect it to a file, or give --out FILE)"
                .into(),
        ))
    } else {
        Ok(())
    }
}

/// Writes to stdout, flushing at once: a failure (a full disk, a closed
/// descriptor) is an error with exit code 1; a reader that has gone
/// (`| head`) is not, it has what it wanted.
pub fn write_stdout(bytes: &[u8]) -> Result<(), CliError> {
    check_stdout()?;
    let mut out = std::io::stdout().lock();
    match out.write_all(bytes).and_then(|_| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(CliError::Failed(format!("cannot write to stdout: {e}"))),
    }
}

/// One line to stdout, as [`write_stdout`].
pub fn say(line: &str) -> Result<(), CliError> {
    write_stdout(format!("{line}\n").as_bytes())
}

/// Whether stderr is a terminal (progress bars) or not (progress lines).
pub fn stderr_is_terminal() -> bool {
    std::io::stderr().is_terminal()
}

/// Runs the job of `spec` to its end on `threads` threads (the command
/// line's host, [`crate::jobs::run_collect`]), its `Progress` updates
/// moving `progress`, stopped by `limits`: every update it sent. A stop
/// is `what`'s "stopped" error, a failure the job's.
pub fn run_job(
    what: &str,
    spec: crate::jobs::Spec,
    threads: usize,
    progress: &Progress,
    limits: &Limits,
) -> Result<Vec<crate::jobs::Update>, CliError> {
    collect_job(spec, threads, progress, limits, &|_| {}, |_| true)
        .map_err(|e| job_error(what, limits, e))
}

/// [`run_job`] with the job's own error, for a caller that words one
/// itself, `each` told of every update as it comes, and only the updates
/// `keep` says yes to kept.
pub fn collect_job(
    spec: crate::jobs::Spec,
    threads: usize,
    progress: &Progress,
    limits: &Limits,
    each: &(dyn Fn(&crate::jobs::Update) + Sync),
    keep: fn(&crate::jobs::Update) -> bool,
) -> Result<Vec<crate::jobs::Update>, crate::jobs::JobError> {
    use crate::jobs::{Update, run_collect_some};
    let on_update = |u: &Update| {
        if let Update::Progress { fraction, .. } = u {
            progress.to_fraction(*fraction);
        }
        each(u);
    };
    let run = run_collect_some(spec, threads, on_update, || limits.stop(), keep);
    progress.finish();
    run
}

/// What a job's error is on the command line: a stop is `what`'s
/// "stopped" error.
pub fn job_error(what: &str, limits: &Limits, e: crate::jobs::JobError) -> CliError {
    use crate::jobs::JobError;
    match e {
        JobError::Stop => limits.stopped(what),
        JobError::Sim(e) => e.into(),
        JobError::Failed(m) => CliError::Failed(m),
    }
}
