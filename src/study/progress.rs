//! Progress of long work on rank 0: a bar (indicatif) with the stage's name, where it is and
//! an estimate of the time left, drawn only when a person watches (see [`interactive`]); the per-step log lines
//! stay in every case (through [`LogWriter`], which prints them above the bar while one is
//! drawn, so the two never tear each other). Other ranks draw nothing.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::Write;
use std::sync::Mutex;

/// The bar being drawn, if any: the log writer needs it to print above it.
static CURRENT: Mutex<Option<ProgressBar>> = Mutex::new(None);

/// The current step's own message ("mu 0.300"), which the latest log line then follows on
/// the bar: inside one friction value the solvers' steps (Newton increments, CEA shifts, a
/// super-element's constraint and interior modes) show where the point is.
static STEP: Mutex<String> = Mutex::new(String::new());

/// How much of a log line the bar shows after the step's message.
const DETAIL_CHARS: usize = 60;

/// A bar over `total` steps of one stage; hidden on ranks other than 0, when stdout is not a
/// terminal, and in quiet runs (indicatif hides a bar whose target is not a terminal).
pub struct Progress {
    bar: ProgressBar,
}

impl Progress {
    pub fn new(rank: usize, stage: &str, total: usize) -> Progress {
        let bar = if rank == 0 && tracing::enabled!(tracing::Level::INFO) && interactive() {
            ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stdout())
        } else {
            ProgressBar::hidden()
        };
        bar.set_style(
            ProgressStyle::with_template(
                "{prefix} [{bar:30}] {pos}/{len} {msg} ({elapsed_precise}, about {eta} left)",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
        );
        bar.set_prefix(stage.to_string());
        if let Ok(mut c) = CURRENT.lock() {
            *c = Some(bar.clone());
        }
        Progress { bar }
    }

    /// What the current step is doing, e.g. "mu 0.300".
    pub fn message(&self, text: impl Into<String>) {
        let text = text.into();
        if let Ok(mut s) = STEP.lock() {
            s.clone_from(&text);
        }
        self.bar.set_message(text);
    }

    /// `n` more steps than the bar was made with (points a sweep decided to add).
    pub fn grow(&self, n: u64) {
        self.bar.inc_length(n);
    }

    /// One step done.
    pub fn step(&self) {
        self.bar.inc(1);
    }
}

/// Whether a person watches stdout. Under mpirun a rank's stdout is a pseudo-terminal of
/// OpenMPI's whatever mpirun's own is (a log file too), and its stderr always a pipe, so the
/// launcher's stdout is asked: mpirun starts the ranks of its own node itself.
fn interactive() -> bool {
    use std::io::IsTerminal;
    if !std::io::stdout().is_terminal() {
        return false;
    }
    if std::env::var_os("OMPI_COMM_WORLD_SIZE").is_none() {
        return true;
    }
    let launcher = std::os::unix::process::parent_id();
    std::fs::File::open(format!("/proc/{launcher}/fd/1")).is_ok_and(|f| f.is_terminal())
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
        if let Ok(mut c) = CURRENT.lock() {
            *c = None;
        }
    }
}

/// The log's writer: stderr, or, while a bar is drawn, the terminal above the bar.
pub struct LogWriter;

impl Write for LogWriter {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let bar = CURRENT.lock().ok().and_then(|c| c.clone());
        match bar {
            // Drawn, the bar is on a terminal stdout: the line goes there too, above it, so
            // that mpirun (which forwards a rank's stdout and stderr apart) cannot reorder them.
            Some(bar) if !bar.is_hidden() => {
                let step = STEP.lock().map(|s| s.clone()).unwrap_or_default();
                bar.set_message(format!("{step}: {}", detail(buf)));
                bar.suspend(|| {
                    let mut out = std::io::stdout();
                    out.write_all(buf)?;
                    out.flush()?;
                    Ok(buf.len())
                })
            }
            _ => std::io::stderr().write(buf),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        std::io::stderr().flush()
    }
}

/// A log line as the bar shows it: without its level, on one line, cut at a character
/// boundary.
fn detail(line: &[u8]) -> String {
    let text = without_colours(&String::from_utf8_lossy(line));
    let text = text.trim();
    let text = ["INFO ", "WARN ", "DEBUG "]
        .iter()
        .find_map(|level| text.strip_prefix(level))
        .unwrap_or(text)
        .trim();
    let first = text.lines().next().unwrap_or_default();
    match first.char_indices().nth(DETAIL_CHARS) {
        Some((at, _)) => format!("{}...", &first[..at]),
        None => first.to_string(),
    }
}

/// `text` without its ANSI colour sequences (ESC [ ... letter): a log line coloured for a
/// terminal.
fn without_colours(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars();
    while let Some(c) = chars.next() {
        if c == '\u{1b}' {
            for d in chars.by_ref() {
                if d.is_ascii_alphabetic() {
                    break;
                }
            }
        } else {
            out.push(c);
        }
    }
    out
}

impl<'a> tracing_subscriber::fmt::MakeWriter<'a> for LogWriter {
    type Writer = LogWriter;
    fn make_writer(&'a self) -> LogWriter {
        LogWriter
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_line_on_the_bar_loses_its_level_and_is_cut_short() {
        assert_eq!(
            detail(b" INFO CEA shift 1 at 7746 Hz: 96 pairs\n"),
            "CEA shift 1 at 7746 Hz: 96 pairs"
        );
        assert_eq!(
            detail(b"\x1b[32m INFO\x1b[0m mu 0.30 (1/9): static\n"),
            "mu 0.30 (1/9): static"
        );
        let long = format!(" WARN {}\n", "\u{e9}".repeat(100));
        assert_eq!(
            detail(long.as_bytes()),
            format!("{}...", "\u{e9}".repeat(60))
        );
    }
}
