//! Where the command line's text goes: one [`Output`] holds standard output and standard
//! error, and every write returns an `io::Result` instead of panicking as `print!` does.
//!
//! Commands write with `writeln!(o.out(), ...)?` or `o.diagnostics(...)?` and return
//! `Result<_, Stop>`; [`finish`] maps the outcome to the exit code in one place: a closed
//! pipe (`mbfx check big.adm | head -1`) ends the program quietly with exit 0, as `rg`
//! and other Unix filters do, and any other write failure (a full disk) is one line on
//! stderr and exit 1. Each stream tags its errors with its name, so that line says which
//! stream failed; [`Named`] does the same for a file a command writes (a CSV of results).

use crate::diag::{render, Diagnostic, SourceFile};
use std::fmt;
use std::io::{self, Write};

/// Why a command stopped before finishing normally.
#[derive(Debug)]
pub enum Stop {
    /// The command failed and has written its diagnostics: exit 1.
    Failed,
    /// Writing failed (the error names the stream or file).
    Io(io::Error),
}

impl From<io::Error> for Stop {
    fn from(e: io::Error) -> Stop {
        Stop::Io(e)
    }
}

/// The exit code of a command's outcome; reports a write failure on stderr (if stderr can
/// still be written).
pub fn finish(outcome: Result<i32, Stop>, o: &mut Output<'_>) -> i32 {
    let outcome = outcome.and_then(|code| o.flush().map(|()| code).map_err(Stop::Io));
    match outcome {
        Ok(code) => code,
        Err(Stop::Failed) => 1,
        Err(Stop::Io(e)) if e.kind() == io::ErrorKind::BrokenPipe => 0,
        Err(Stop::Io(e)) => {
            // stderr may be the stream that failed: nothing more can be said then.
            let _ = writeln!(o.err, "mbfx: {e}");
            let _ = o.err.flush();
            1
        }
    }
}

/// A writer whose errors say what was being written (`cannot write to stdout: ...`),
/// keeping the error's kind so a closed pipe is still recognised.
pub struct Named<W> {
    inner: W,
    name: String,
}

impl<W: Write> Named<W> {
    /// `inner`, whose errors will name `name`.
    pub fn new(inner: W, name: impl Into<String>) -> Named<W> {
        Named {
            inner,
            name: name.into(),
        }
    }

    fn tag(&self, e: io::Error) -> io::Error {
        io::Error::new(
            e.kind(),
            WriteError(format!("cannot write to {}: {e}", self.name)),
        )
    }
}

/// The message of a tagged write error.
#[derive(Debug)]
struct WriteError(String);

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for WriteError {}

impl<W: Write> Write for Named<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.inner.write(buf).map_err(|e| self.tag(e))
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush().map_err(|e| self.tag(e))
    }
}

/// Standard output and standard error of a command, and whether diagnostics are coloured.
pub struct Output<'a> {
    out: Named<Box<dyn Write + 'a>>,
    err: Named<Box<dyn Write + 'a>>,
    /// Whether diagnostics are coloured.
    pub color: bool,
}

impl Output<'static> {
    /// The process's standard output and standard error.
    pub fn stdio(color: bool) -> Output<'static> {
        Output::new(
            Box::new(io::stdout().lock()),
            Box::new(io::stderr().lock()),
            color,
        )
    }
}

impl<'a> Output<'a> {
    /// An output to any two writers (tests capture into buffers).
    pub fn new(out: Box<dyn Write + 'a>, err: Box<dyn Write + 'a>, color: bool) -> Output<'a> {
        Output {
            out: Named::new(out, "stdout"),
            err: Named::new(err, "stderr"),
            color,
        }
    }

    /// Standard output: results and reports.
    pub fn out(&mut self) -> &mut dyn Write {
        &mut self.out
    }

    /// Standard error: diagnostics and summaries.
    pub fn err(&mut self) -> &mut dyn Write {
        &mut self.err
    }

    /// Standard output and standard error at once (a run writes its CSV to one and its
    /// step table to the other).
    pub fn both(&mut self) -> (&mut dyn Write, &mut dyn Write) {
        (&mut self.out, &mut self.err)
    }

    /// Renders diagnostics about `source` to standard error.
    pub fn diagnostics(&mut self, diags: &[Diagnostic], source: &SourceFile) -> io::Result<()> {
        if diags.is_empty() {
            return Ok(());
        }
        let text = render(diags, source, self.color);
        self.err.write_all(text.as_bytes())
    }

    /// Flushes both streams.
    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()?;
        self.err.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer that fails every write with `kind`.
    struct Failing(io::ErrorKind);

    impl Write for Failing {
        fn write(&mut self, _: &[u8]) -> io::Result<usize> {
            Err(io::Error::from(self.0))
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    /// The exit code and stderr text of a command that writes one line to a stdout whose
    /// writes fail with `kind`.
    fn write_failing(kind: io::ErrorKind) -> (i32, String) {
        let mut err = Vec::new();
        let mut o = Output::new(Box::new(Failing(kind)), Box::new(&mut err), false);
        let outcome = writeln!(o.out(), "1.0").map(|()| 0).map_err(Stop::from);
        let code = finish(outcome, &mut o);
        drop(o);
        (code, String::from_utf8_lossy(&err).into_owned())
    }

    #[test]
    fn a_closed_pipe_exits_quietly_and_a_full_disk_is_one_message() {
        assert_eq!(write_failing(io::ErrorKind::BrokenPipe), (0, String::new()));
        let (code, text) = write_failing(io::ErrorKind::StorageFull);
        assert_eq!(code, 1);
        assert!(text.starts_with("mbfx: cannot write to stdout: "), "{text}");
        assert_eq!(text.lines().count(), 1, "{text}");
    }
}
