//! Writing a command's output without panicking when the reader goes away (`println!` panics on a
//! closed pipe). Every line goes through [`text::shown`] here, at the edge, so control or bidi
//! characters in a name, path or reply never reach the terminal. (JSON lines are left as they are:
//! serde_json escapes C0 itself and no output holds DEL, C1 or bidi.)

use std::io::{self, Write};

use crate::text;

/// What became of a write to stdout.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Printed {
    /// Everything was written.
    All,
    /// The reader went away (a closed pipe): stop printing, this is not an error.
    ReaderGone,
}

/// Writes escaped `lines` and flushes; a broken pipe is [`Printed::ReaderGone`].
pub fn write_lines<W: Write>(out: &mut W, lines: &[String]) -> io::Result<Printed> {
    let written = lines
        .iter()
        .try_for_each(|line| writeln!(out, "{}", text::shown(line)))
        .and_then(|()| out.flush());
    match written {
        Ok(()) => Ok(Printed::All),
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(Printed::ReaderGone),
        Err(e) => Err(e),
    }
}

/// Prints `lines` on stdout; see [`write_lines`].
pub fn print_lines(lines: &[String]) -> io::Result<Printed> {
    write_lines(&mut io::stdout().lock(), lines)
}

/// Prints one line on stdout; see [`write_lines`].
pub fn print_line(line: impl Into<String>) -> io::Result<Printed> {
    print_lines(&[line.into()])
}

/// Prints `armjog: ...` on stderr, escaped to one line; a failure is only logged.
pub fn print_error(reason: &str) {
    let mut err = io::stderr().lock();
    let shown = text::shown(reason);
    if let Err(e) = writeln!(err, "armjog: {shown}").and_then(|()| err.flush()) {
        tracing::warn!("cannot write to stderr ({e}): {}", text::logged(reason));
    }
}

/// Prints `armjog: reason` on stderr ([`print_error`]) and returns the exit status `code`.
pub fn fail(reason: impl std::fmt::Display, code: i32) -> i32 {
    print_error(&reason.to_string());
    code
}

/// Prints several lines (clap's message) on stderr, each escaped; a failure is only logged.
pub fn print_error_lines(message: &str) {
    let mut err = io::stderr().lock();
    let written = message
        .lines()
        .try_for_each(|line| writeln!(err, "{}", text::shown(line)))
        .and_then(|()| err.flush());
    if let Err(e) = written {
        tracing::warn!("cannot write to stderr ({e}): {}", text::logged(message));
    }
}

/// Prints a command's output and reason; its own status if the reader left, 1 if stdout failed.
pub fn report(stdout: &[String], stderr: Option<&str>, exit_code: i32) -> i32 {
    let code = match print_lines(stdout) {
        Ok(Printed::All) => exit_code,
        Ok(Printed::ReaderGone) => {
            tracing::info!("stdout closed by its reader; output cut short");
            exit_code
        }
        Err(e) => {
            print_error(&format!("cannot write the output: {e}"));
            if exit_code == 0 { 1 } else { exit_code }
        }
    };
    if let Some(reason) = stderr {
        print_error(reason);
    }
    code
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer whose reader has gone after `room` bytes.
    struct ClosedAfter {
        room: usize,
        kind: io::ErrorKind,
    }

    impl Write for ClosedAfter {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            if self.room == 0 {
                return Err(io::Error::from(self.kind));
            }
            let n = buf.len().min(self.room);
            self.room -= n;
            Ok(n)
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    fn lines() -> Vec<String> {
        vec!["robot state   ready".into(), "faults        none".into()]
    }

    #[test]
    fn a_broken_pipe_means_the_reader_is_gone() {
        let mut out = ClosedAfter {
            room: 10,
            kind: io::ErrorKind::BrokenPipe,
        };
        assert_eq!(
            write_lines(&mut out, &lines()).ok(),
            Some(Printed::ReaderGone)
        );
    }

    #[test]
    fn other_write_failures_are_errors() {
        let mut out = ClosedAfter {
            room: 0,
            kind: io::ErrorKind::StorageFull,
        };
        let err = write_lines(&mut out, &lines()).expect_err("a full disk is an error");
        assert_eq!(err.kind(), io::ErrorKind::StorageFull);
    }

    #[test]
    fn control_and_bidi_characters_are_written_escaped() {
        let mut out = Vec::new();
        let lines = vec![
            "evil\u{1b}]0;PWNED\u{7}\u{1b}[31m\u{202e}  talos \u{1b}[2J".to_string(),
            "two\nlines \u{9b}1m".to_string(),
        ];
        assert_eq!(write_lines(&mut out, &lines).ok(), Some(Printed::All));
        assert_eq!(
            String::from_utf8_lossy(&out),
            "evil\\u{1b}]0;PWNED\\u{7}\\u{1b}[31m\\u{202e}  talos \\u{1b}[2J\n\
             two\\nlines \\u{9b}1m\n"
        );
    }

    #[test]
    fn all_lines_are_written_when_there_is_room() {
        let mut out = Vec::new();
        assert_eq!(write_lines(&mut out, &lines()).ok(), Some(Printed::All));
        assert_eq!(
            String::from_utf8_lossy(&out),
            "robot state   ready\nfaults        none\n"
        );
    }
}
