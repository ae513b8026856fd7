//! Progress where no one watches a terminal (a Slurm log, `2> run.log`): indicatif draws nothing
//! when stderr is not a terminal, so a long run would print nothing for hours. This target takes
//! indicatif's rendered line and prints it as a plain log line when the step changes and at
//! most every [`LOG_EVERY`] in between.

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
    /// What names the step of the last printed line (the text before the bar).
    step: String,
    printed: Option<Instant>,
    /// Lines written (for tests: the sink is stderr).
    written: Vec<String>,
}

impl LogLines {
    pub fn new(every: Duration) -> Self {
        Self {
            state: Mutex::new(LogState::default()),
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

/// What names a line's step: the text before its bar (`[`), without the spinner's frame.
fn step_of(line: &str) -> String {
    let head = line.split('[').next().unwrap_or("");
    head.trim_start_matches(|c: char| !c.is_alphanumeric())
        .trim()
        .to_string()
}

impl TermLike for LogLines {
    fn width(&self) -> u16 {
        160
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
        let lines: Vec<&str> = text.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
        let stamp = chrono::Utc::now().format("%H:%M:%S");
        let mut err = io::stderr().lock();
        // the last line is the bar; those above it were printed above the bar (`println`)
        let Some((bar, above)) = lines.split_last() else {
            return Ok(());
        };
        for line in above {
            writeln!(err, "[{stamp}] {line}")?;
            state.written.push(line.to_string());
        }
        // the spinner's frame means nothing in a log
        let bar = bar.trim_start_matches(|c: char| !c.is_ascii()).trim();
        let step = step_of(bar);
        let due = state.printed.is_none_or(|t| t.elapsed() >= self.every);
        if step != state.step || due {
            writeln!(err, "[{stamp}] {bar}")?;
            state.written.push(bar.to_string());
            state.step = step;
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
    fn a_log_gets_a_line_per_step_and_none_in_between_until_it_is_due() {
        let log = LogLines::new(Duration::from_secs(3600));
        draw(&log, "⠁ step 1/8 dataset [=>   ] 10% | 2/20 scenes");
        draw(&log, "⠂ step 1/8 dataset [==>  ] 15% | 3/20 scenes");
        draw(&log, "⠄ step 2/8 learning [>    ] 0% | base S");
        draw(&log, "");
        assert_eq!(log.written().len(), 2, "{:?}", log.written());
        assert_eq!(log.written()[1], "step 2/8 learning [>    ] 0% | base S");
        // a line printed above the bar always comes out, on a line of its own
        log.write_line("learning: S done in 21.1 s").unwrap();
        draw(&log, "⠂ step 2/8 learning [=>   ] 5% | base C");
        assert_eq!(log.written()[2], "learning: S done in 21.1 s");
        assert_eq!(log.written().len(), 3);
        // a line is due at once when the interval is zero
        let every = LogLines::new(Duration::ZERO);
        draw(&every, "⠁ step 1/8 dataset [=>   ] 10%");
        draw(&every, "⠂ step 1/8 dataset [==>  ] 15%");
        assert_eq!(every.written().len(), 2);
    }
}
