//! Wall times of a run's phases, for `render --timings` (stderr only: the report stays
//! deterministic).

/// Wall times of a run's phases.
#[derive(Debug, Clone, Default)]
pub struct Timings {
    pub phases: Vec<(&'static str, std::time::Duration)>,
    /// Tasks that ran concurrently within a phase: (index of the phase, name, wall time).
    pub parts: Vec<(usize, &'static str, std::time::Duration)>,
    last: Option<std::time::Instant>,
}

impl Timings {
    /// Start timing.
    pub fn start() -> Self {
        Timings {
            phases: Vec::new(),
            parts: Vec::new(),
            last: Some(std::time::Instant::now()),
        }
    }
    /// End the phase `name` (it began where the last one ended).
    pub fn lap(&mut self, name: &'static str) {
        let now = std::time::Instant::now();
        let since = self.last.unwrap_or(now);
        self.phases.push((name, now - since));
        self.last = Some(now);
    }
    /// Record `d`, the wall time of `name`, one of the tasks that ran concurrently in the
    /// last phase (shown under it, not added to the total).
    pub fn part(&mut self, name: &'static str, d: std::time::Duration) {
        let phase = self.phases.len().saturating_sub(1);
        self.parts.push((phase, name, d));
    }
    /// One line per phase (its concurrent tasks indented under it) and the total, e.g.
    /// `  simulation      12.3 ms`.
    pub fn to_text(&self) -> String {
        let total: std::time::Duration = self.phases.iter().map(|p| p.1).sum();
        let mut s = String::new();
        let mut line = |indent: &str, name: &str, d: &std::time::Duration| {
            let name = format!("{indent}{name}");
            s.push_str(&format!(
                "  {name:<18} {:>10.1} ms\n",
                d.as_secs_f64() * 1e3
            ));
        };
        for (k, (name, d)) in self.phases.iter().enumerate() {
            line("", name, d);
            for (_, name, d) in self.parts.iter().filter(|p| p.0 == k) {
                line("  ", name, d);
            }
        }
        line("", "total", &total);
        s
    }
}
