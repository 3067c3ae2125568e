//! What `rayforge bench` prints: Markdown tables (so a run pastes straight into
//! `docs/performance.md`), the targets each comparison is held to, and `bench.md`, the whole
//! report as a file.

use rayforge_cli::atomic_write::write_atomically;
use rayforge_cli::failure::Failure;
use std::fmt::Write as _;
use std::path::Path;

/// One table: a title, its column headers and rows of cells, printed as Markdown.
#[derive(Debug, Clone)]
pub struct Table {
    title: String,
    headers: Vec<String>,
    rows: Vec<Vec<String>>,
    notes: Vec<String>,
}

impl Table {
    /// An empty table with these columns.
    pub fn new(title: impl Into<String>, headers: &[&str]) -> Self {
        Self {
            title: title.into(),
            headers: headers.iter().map(|h| h.to_string()).collect(),
            rows: Vec::new(),
            notes: Vec::new(),
        }
    }

    /// Adds a row; missing cells are left empty, extra ones dropped, so a table never comes out
    /// ragged.
    pub fn row(&mut self, cells: Vec<String>) {
        let mut cells = cells;
        cells.resize(self.headers.len(), String::new());
        self.rows.push(cells);
    }

    /// A line printed under the table (a skipped peer and how to install it, a caveat).
    pub fn note(&mut self, text: impl Into<String>) {
        self.notes.push(text.into());
    }

    /// The table as Markdown, columns padded to line up in a terminal too.
    pub fn to_markdown(&self) -> String {
        let width = |i: usize| {
            self.rows
                .iter()
                .map(|r| r[i].chars().count())
                .chain([self.headers[i].chars().count(), 3])
                .max()
                .unwrap_or(3)
        };
        let widths: Vec<usize> = (0..self.headers.len()).map(width).collect();
        let line = |cells: &[String]| {
            let padded: Vec<String> = cells
                .iter()
                .zip(&widths)
                .map(|(c, w)| format!("{c}{}", " ".repeat(w - c.chars().count())))
                .collect();
            format!("| {} |\n", padded.join(" | "))
        };
        let mut out = format!("### {}\n\n", self.title);
        out += &line(&self.headers);
        let rule: Vec<String> = widths.iter().map(|w| "-".repeat(*w)).collect();
        out += &line(&rule);
        for row in &self.rows {
            out += &line(row);
        }
        for note in &self.notes {
            let _ = write!(out, "\n{note}\n");
        }
        out
    }
}

/// A target of the performance issue and how this run fared against it.
#[derive(Debug, Clone)]
pub struct Check {
    /// What was compared, e.g. "primary rays, bumpy sphere 1.0 M triangles, vs Embree".
    pub what: String,
    /// The measured figure, e.g. "38 % of Embree".
    pub measured: String,
    /// The target, e.g. "≥ 50 %".
    pub target: String,
    /// Met or not; `None` when it could not be measured (a peer or a model missing).
    pub met: Option<bool>,
}

/// Everything printed so far, kept to write `bench.md` at the end.
#[derive(Debug, Default)]
pub struct Report {
    text: String,
    checks: Vec<Check>,
}

impl Report {
    /// A report that starts with these lines (the machine, the settings).
    pub fn new(preamble: &str) -> Self {
        println!("{preamble}");
        Self {
            text: format!("{preamble}\n"),
            checks: Vec::new(),
        }
    }

    /// Prints a table now and keeps it for the file.
    pub fn table(&mut self, table: &Table) {
        let md = table.to_markdown();
        println!("\n{md}");
        self.text += &format!("\n{md}");
    }

    /// Records a target's outcome for the summary.
    pub fn check(&mut self, check: Check) {
        self.checks.push(check);
    }

    /// Prints the summary of every target, writes the report to `path` and returns how many
    /// targets were met, missed and not measured.
    pub fn finish(mut self, path: &Path) -> Result<(usize, usize, usize), Failure> {
        let mut summary = Table::new(
            "Summary: the targets of the performance issue",
            &["comparison", "measured", "target", "met"],
        );
        let (mut met, mut missed, mut unknown) = (0, 0, 0);
        for c in &self.checks {
            let verdict = match c.met {
                Some(true) => {
                    met += 1;
                    "yes"
                }
                Some(false) => {
                    missed += 1;
                    "**no**"
                }
                None => {
                    unknown += 1;
                    "not measured"
                }
            };
            summary.row(vec![
                c.what.clone(),
                c.measured.clone(),
                c.target.clone(),
                verdict.to_string(),
            ]);
        }
        summary.note(format!(
            "{met} met, {missed} missed, {unknown} not measured (a peer or a model missing)."
        ));
        self.table(&summary);
        write_atomically(path, self.text.as_bytes())?;
        println!("\nreport written to {}", path.display());
        Ok((met, missed, unknown))
    }
}

/// Seconds with three significant figures: `12.3 s`, `1.23 s`, `123 ms`, `1.23 ms`.
pub fn seconds(s: f64) -> String {
    match s {
        s if s >= 100.0 => format!("{s:.0} s"),
        s if s >= 10.0 => format!("{s:.1} s"),
        s if s >= 1.0 => format!("{s:.2} s"),
        s if s >= 0.1 => format!("{:.0} ms", s * 1e3),
        s if s >= 0.01 => format!("{:.1} ms", s * 1e3),
        s => format!("{:.2} ms", s * 1e3),
    }
}

/// A count with an SI prefix: `1.00 M`, `23.5 k`, `512`.
pub fn si(v: f64) -> String {
    match v {
        v if v >= 1e9 => format!("{:.2} G", v / 1e9),
        v if v >= 1e6 => format!("{:.2} M", v / 1e6),
        v if v >= 1e3 => format!("{:.1} k", v / 1e3),
        v => format!("{v:.0}"),
    }
}

/// A ratio of times as the issue states them: `2.31×`.
pub fn times(ratio: f64) -> String {
    format!("{ratio:.2}×")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_lines_up_and_pads_short_rows() {
        let mut t = Table::new("T", &["a", "long header"]);
        t.row(vec!["wide cell".into()]);
        let md = t.to_markdown();
        assert_eq!(
            md,
            "### T\n\n| a         | long header |\n| --------- | ----------- |\n| wide cell |             |\n"
        );
    }

    #[test]
    fn durations_keep_three_figures() {
        assert_eq!(seconds(12.345), "12.3 s");
        assert_eq!(seconds(1.2345), "1.23 s");
        assert_eq!(seconds(0.1234), "123 ms");
        assert_eq!(seconds(0.001234), "1.23 ms");
        assert_eq!(si(1_002_252.0), "1.00 M");
    }
}
