//! Progress of a batch: one bar for the whole (caches finished of all) and one per cache being
//! tracked (its frames); a line per finished cache, printed even where bars are hidden (a farm's
//! log), so each task's log says what became of its cache.

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

pub(super) struct BatchProgress {
    multi: MultiProgress,
    overall: ProgressBar,
    quiet: bool,
}

impl BatchProgress {
    pub fn new(caches: usize, quiet: bool) -> Self {
        let multi = MultiProgress::new();
        if quiet {
            multi.set_draw_target(ProgressDrawTarget::hidden());
        }
        let overall = multi.add(ProgressBar::new(caches as u64));
        if let Ok(style) = ProgressStyle::with_template("{bar:30} {pos}/{len} caches  {elapsed}") {
            overall.set_style(style);
        }
        Self {
            multi,
            overall,
            quiet,
        }
    }

    /// A bar for the frames of cache `name`, shown while it tracks.
    pub fn cache(&self, name: &str, frames: usize) -> ProgressBar {
        let bar = self.multi.add(ProgressBar::new(frames as u64));
        if let Ok(style) =
            ProgressStyle::with_template("{bar:30} {pos}/{len} frames  ETA {eta}  {msg}")
        {
            bar.set_style(style);
        }
        bar.set_message(name.to_string());
        bar
    }

    pub fn cache_finished(&self) {
        self.overall.inc(1);
    }

    /// Prints `text` above the bars, unless quiet.
    pub fn line(&self, text: String) {
        if !self.quiet {
            self.multi.suspend(|| println!("{text}"));
        }
    }

    pub fn finish(&self) {
        self.overall.finish_and_clear();
    }
}
