//! Progress bars for long work (the multi-view bake of a detailed mesh, the points of a
//! sweep): drawn on stderr when stderr is a terminal, with the elapsed time and an estimate
//! of the time left; hidden otherwise (tests, pipes, CI) and when `BUMPSIM_PROGRESS=0`.
//! They never touch an output, so runs stay byte-identical. One bar at a time: a bar asked
//! for while another is live (a bake inside a sweep's point) is hidden.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Bars alive now, drawn or not.
static LIVE: AtomicUsize = AtomicUsize::new(0);

/// A progress bar; hidden where [`enabled`] is false or another bar is live.
pub struct Progress(ProgressBar);

impl std::ops::Deref for Progress {
    type Target = ProgressBar;
    fn deref(&self) -> &ProgressBar {
        &self.0
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.0.finish_and_clear();
        LIVE.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Whether bars are drawn: stderr is a terminal and `BUMPSIM_PROGRESS` is not `0`.
pub fn enabled() -> bool {
    drawn(
        std::io::stderr().is_terminal(),
        std::env::var_os("BUMPSIM_PROGRESS").as_deref(),
    )
}

fn drawn(terminal: bool, setting: Option<&std::ffi::OsStr>) -> bool {
    terminal && setting.is_none_or(|v| v != "0")
}

/// A bar of `len` steps titled `what`.
pub fn bar(len: u64, what: &str) -> Progress {
    let first = LIVE.fetch_add(1, Ordering::SeqCst) == 0;
    if !first || !enabled() {
        return Progress(ProgressBar::hidden());
    }
    let b = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(
        "{prefix} [{bar:30}] {pos}/{len} {msg} ({elapsed}, about {eta} left)",
    ) {
        b.set_style(style.progress_chars("=> "));
    }
    b.set_prefix(what.to_string());
    Progress(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::OsStr;

    #[test]
    fn bars_are_drawn_on_a_terminal_unless_turned_off() {
        assert!(drawn(true, None));
        assert!(drawn(true, Some(OsStr::new("1"))));
        assert!(!drawn(true, Some(OsStr::new("0"))));
        assert!(!drawn(false, None));
    }

    #[test]
    fn a_bar_inside_a_bar_is_hidden() {
        let outer = bar(2, "outer");
        let inner = bar(2, "inner");
        assert!(inner.is_hidden());
        drop(inner);
        drop(outer);
    }
}
