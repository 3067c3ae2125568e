//! The progress bar on stderr while rendering (rows done of all rows).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

/// A bar over `rows` rows, hidden when `quiet` or when stderr is not a terminal.
pub fn row_bar(rows: usize, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::with_draw_target(Some(rows as u64), ProgressDrawTarget::hidden());
    }
    let bar = ProgressBar::new(rows as u64);
    let style = ProgressStyle::with_template(
        "{spinner} rendering [{bar:40}] {pos}/{len} rows, {elapsed} elapsed, ~{eta} left",
    )
    .unwrap_or_else(|_| ProgressStyle::default_bar())
    .progress_chars("=> ");
    bar.set_style(style);
    bar
}
