//! The measurements' progress ([`vpmap_eval::Progress`]) as an indicatif bar on a terminal,
//! and as plain lines on stderr otherwise.

use std::io::IsTerminal as _;
use std::sync::OnceLock;

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar drawn from the first [`vpmap_eval::Progress::start`].
pub struct Bar {
    template: &'static str,
    width: &'static str,
    shown: OnceLock<ProgressBar>,
}

impl Bar {
    /// A bar with an indicatif template (`{bar}` is replaced by the bar of `width` chars).
    pub fn new(template: &'static str, width: &'static str) -> Self {
        Self {
            template,
            width,
            shown: OnceLock::new(),
        }
    }
}

impl vpmap_eval::Progress for Bar {
    fn start(&self, total: u64) {
        let bar = if std::io::stderr().is_terminal() {
            let bar = ProgressBar::new(total);
            let template = self
                .template
                .replace("{bar}", &format!("{{bar:{}}}", self.width));
            if let Ok(style) = ProgressStyle::with_template(&template) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar
        } else {
            ProgressBar::hidden()
        };
        let _ = self.shown.set(bar);
    }

    fn message(&self, text: &str) {
        if let Some(bar) = self.shown.get() {
            bar.set_message(text.to_owned());
        }
    }

    fn step(&self) {
        if let Some(bar) = self.shown.get() {
            bar.inc(1);
        }
    }

    fn note(&self, line: &str) {
        match self.shown.get() {
            Some(bar) if !bar.is_hidden() => bar.println(line),
            _ => eprintln!("{line}"),
        }
    }

    fn milestone(&self, line: &str) {
        // A bar on a terminal already says where the run is.
        match self.shown.get() {
            Some(bar) if !bar.is_hidden() => {}
            _ => eprintln!("{line}"),
        }
    }

    fn warn(&self, line: &str) {
        eprintln!("warning: {line}");
    }

    fn finish(&self) {
        if let Some(bar) = self.shown.get() {
            bar.finish_and_clear();
        }
    }
}
