//! Progress where no one watches a terminal (a Slurm log, `2> run.log`): indicatif draws nothing
//! when stderr is not a terminal, so a long run would print nothing for hours. This target prints
//! every line printed above the bar (a step's start and end) and indicatif's rendered bar as a
//! plain log line at most every [`LOG_EVERY`] of silence.

use indicatif::{ProgressDrawTarget, TermLike};
use std::io::{self, Write};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The longest silence between two progress lines in a log.
pub const LOG_EVERY: Duration = Duration::from_secs(30);

/// Lines of progress for a log.
#[derive(Debug)]
pub struct LogLines {
    state: Mutex<LogState>,
    every: Duration,
}

#[derive(Debug, Default)]
struct LogState {
    /// The line indicatif is drawing.
    line: String,
    printed: Option<Instant>,
    /// Lines written (for tests: the sink is stderr).
    written: Vec<String>,
}

impl LogLines {
    /// Lines at most every `every` of silence, the first bar line after `every` (a step's start
    /// is printed above the bar).
    pub fn new(every: Duration) -> Self {
        Self {
            state: Mutex::new(LogState {
                printed: Some(Instant::now()),
                ..LogState::default()
            }),
            every,
        }
    }

    /// A draw target printing to stderr at most once a second.
    pub fn target() -> ProgressDrawTarget {
        ProgressDrawTarget::term_like_with_hz(Box::new(Self::new(LOG_EVERY)), 1)
    }

    /// The lines printed so far.
    pub fn written(&self) -> Vec<String> {
        self.state.lock().expect("log state").written.clone()
    }
}

impl TermLike for LogLines {
    /// Wider than any line: indicatif pads a line printed above the bar to this width, and a
    /// line wider would be wrapped.
    fn width(&self) -> u16 {
        1000
    }

    fn move_cursor_up(&self, _: usize) -> io::Result<()> {
        Ok(())
    }

    fn move_cursor_down(&self, _: usize) -> io::Result<()> {
        Ok(())
    }

    fn move_cursor_right(&self, _: usize) -> io::Result<()> {
        Ok(())
    }

    fn move_cursor_left(&self, _: usize) -> io::Result<()> {
        Ok(())
    }

    fn write_line(&self, s: &str) -> io::Result<()> {
        self.write_str(&format!("{s}\n"))
    }

    fn write_str(&self, s: &str) -> io::Result<()> {
        self.state.lock().expect("log state").line.push_str(s);
        Ok(())
    }

    fn clear_line(&self) -> io::Result<()> {
        Ok(())
    }

    fn flush(&self) -> io::Result<()> {
        let mut state = self.state.lock().expect("log state");
        let text = std::mem::take(&mut state.line);
        // indicatif pads a line above the bar to the terminal's width instead of ending it
        let width = usize::from(self.width());
        let rows: Vec<String> = text
            .lines()
            .flat_map(|line| {
                let chars: Vec<char> = line.chars().collect();
                chars
                    .chunks(width)
                    .map(|c| c.iter().collect::<String>())
                    .collect::<Vec<_>>()
            })
            .collect();
        let lines: Vec<&str> = rows.iter().map(|l| l.trim()).filter(|l| !l.is_empty()).collect();
        let stamp = chrono::Utc::now().format("%H:%M:%S");
        let mut err = io::stderr().lock();
        // the last line is the bar; those above it were printed above the bar (`println`)
        let Some((bar, above)) = lines.split_last() else {
            return Ok(());
        };
        for line in above {
            writeln!(err, "[{stamp}] {line}")?;
            state.written.push(line.to_string());
            state.printed = Some(Instant::now());
        }
        // the spinner's frame means nothing in a log
        let bar = bar.trim_start_matches(|c: char| !c.is_ascii()).trim();
        if state.printed.is_none_or(|t| t.elapsed() >= self.every) {
            writeln!(err, "[{stamp}] {bar}")?;
            state.written.push(bar.to_string());
            state.printed = Some(Instant::now());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn draw(log: &LogLines, line: &str) {
        log.write_str(line).unwrap();
        log.flush().unwrap();
    }

    #[test]
    fn a_log_gets_the_lines_above_the_bar_and_the_bar_when_it_is_due() {
        let log = LogLines::new(Duration::from_secs(3600));
        draw(&log, "⠁ step 1/8 dataset [=>   ] 10% | 2/20 scenes");
        assert!(log.written().is_empty(), "the bar waits its interval");
        // a line printed above the bar always comes out, on a line of its own, also when it
        // comes padded to the width, as indicatif writes it, before a bar line of any length
        let bar = format!("⠂ step 2/8 learning [=>   ] 5% | {}", "x".repeat(300));
        log.write_str(&format!("{:<1000}{bar}", "step 2/8 learning: 1088640 image-epochs"))
            .unwrap();
        log.flush().unwrap();
        assert_eq!(log.written(), ["step 2/8 learning: 1088640 image-epochs"]);
        // bar lines come when due, without the spinner's frame
        let every = LogLines::new(Duration::ZERO);
        draw(&every, "⠁ step 1/8 dataset [=>   ] 10%");
        draw(&every, "⠂ step 1/8 dataset [==>  ] 15%");
        assert_eq!(
            every.written(),
            ["step 1/8 dataset [=>   ] 10%", "step 1/8 dataset [==>  ] 15%"]
        );
    }
}
