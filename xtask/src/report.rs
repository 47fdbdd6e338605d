//! The Markdown report `docs/results/REPORT.md`: one section per study.

use std::fmt::Write;
use std::path::{Path, PathBuf};

/// A report under construction.
pub struct Report {
    /// Directory of REPORT.md and the charts.
    pub dir: PathBuf,
    body: String,
    /// Files written (charts), for the summary printed at the end.
    pub files: Vec<PathBuf>,
}

impl Report {
    /// A new report written into `dir`.
    pub fn new(dir: &Path) -> std::io::Result<Self> {
        std::fs::create_dir_all(dir)?;
        Ok(Report {
            dir: dir.to_path_buf(),
            body: String::new(),
            files: Vec::new(),
        })
    }

    /// Append Markdown text.
    pub fn text(&mut self, md: &str) {
        self.body.push_str(md);
        if !md.ends_with('\n') {
            self.body.push('\n');
        }
        self.body.push('\n');
    }

    /// Append a Markdown table.
    pub fn table(&mut self, header: &[&str], rows: &[Vec<String>]) {
        let _ = writeln!(self.body, "| {} |", header.join(" | "));
        let _ = writeln!(self.body, "|{}", "---|".repeat(header.len()));
        for r in rows {
            let _ = writeln!(self.body, "| {} |", r.join(" | "));
        }
        self.body.push('\n');
    }

    /// Path of a chart file in the report directory, recorded for the summary.
    pub fn chart_path(&mut self, file: &str) -> PathBuf {
        let p = self.dir.join(file);
        self.files.push(p.clone());
        p
    }

    /// Reference a chart from the Markdown.
    pub fn image(&mut self, file: &str, alt: &str) {
        let _ = writeln!(self.body, "![{alt}]({file})\n");
    }

    /// Write REPORT.md with a header stating the machine and settings.
    pub fn write(&self, header: &str) -> std::io::Result<PathBuf> {
        let path = self.dir.join("REPORT.md");
        std::fs::write(&path, format!("{header}\n{}", self.body))?;
        Ok(path)
    }
}
