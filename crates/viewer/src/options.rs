//! What the viewer page shows first and how it plays.

/// Options of [`crate::render_html`].
#[derive(Clone, Debug, PartialEq)]
pub struct ViewOptions {
    /// Page title; `None`: the page's own ([`crate::Page::title`]).
    pub title: Option<String>,
    /// Index into `plan.plans` shown first (clamped to the plans present).
    pub initial_plan: usize,
    /// Playback speed factor (1.0 = real time; the page offers 0.25× … 8×).
    pub speed: f64,
    /// Start playing as soon as the page has loaded.
    pub autoplay: bool,
}

impl Default for ViewOptions {
    fn default() -> Self {
        ViewOptions {
            title: None,
            initial_plan: 0,
            speed: 1.0,
            autoplay: true,
        }
    }
}
