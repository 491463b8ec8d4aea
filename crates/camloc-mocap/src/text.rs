//! Text handling shared by the BVH, ASF and AMC readers: UTF-8 decoding, line iteration with
//! 1-based line numbers (LF or CRLF), number parsing with located errors.

use std::str::Split;

use super::error::{MocapError, ParseProblem};
use camloc_skeleton::Pose3;

/// The file being parsed, for building located errors.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Source<'a> {
    /// The file name or path used in error messages.
    pub(crate) name: &'a str,
}

impl Source<'_> {
    /// A [`MocapError::Parse`] at `line` of this file.
    pub(crate) fn error(&self, line: usize, problem: ParseProblem) -> MocapError {
        MocapError::Parse {
            file: self.name.to_owned(),
            line,
            problem,
        }
    }

    /// "expected `expected`, found `found`" at `line`.
    pub(crate) fn expected(&self, line: usize, expected: &str, found: &str) -> MocapError {
        self.error(
            line,
            ParseProblem::Expected {
                expected: expected.to_owned(),
                found: found.to_owned(),
            },
        )
    }

    /// "expected `expected`, found the end of the file" at `line`.
    pub(crate) fn unexpected_end(&self, line: usize, expected: &str) -> MocapError {
        self.error(
            line,
            ParseProblem::UnexpectedEnd {
                expected: expected.to_owned(),
            },
        )
    }

    /// The next token of a line, or a [`ParseProblem::Missing`] error saying `expected`.
    pub(crate) fn token<'t>(
        &self,
        tokens: &mut impl Iterator<Item = &'t str>,
        line: usize,
        expected: &str,
    ) -> Result<&'t str, MocapError> {
        tokens.next().ok_or_else(|| {
            self.error(
                line,
                ParseProblem::Missing {
                    expected: expected.to_owned(),
                },
            )
        })
    }

    /// "invalid `what`: `reason`" at `line`.
    pub(crate) fn invalid(&self, line: usize, what: String, reason: &str) -> MocapError {
        self.error(
            line,
            ParseProblem::Invalid {
                what,
                reason: reason.to_owned(),
            },
        )
    }

    /// `pose`, or an error at `line` when huge values made a coordinate of frame `frame`
    /// overflow to infinity.
    pub(crate) fn finite_pose(
        &self,
        pose: Pose3,
        line: usize,
        frame: usize,
    ) -> Result<Pose3, MocapError> {
        if pose.is_finite() {
            Ok(pose)
        } else {
            Err(self.invalid(
                line,
                format!("frame {frame}"),
                "joint positions overflow (values too large)",
            ))
        }
    }

    /// Parses a finite `f64`; `what` describes the quantity and is only built on error.
    pub(crate) fn number(
        &self,
        token: &str,
        line: usize,
        what: impl FnOnce() -> String,
    ) -> Result<f64, MocapError> {
        match token.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(self.error(
                line,
                ParseProblem::NotFinite {
                    what: what(),
                    found: token.to_owned(),
                },
            )),
            Err(_) => Err(self.error(
                line,
                ParseProblem::NotANumber {
                    what: what(),
                    found: token.to_owned(),
                },
            )),
        }
    }

    /// Parses a non-negative integer; `what` describes the quantity and is only built on error.
    pub(crate) fn count(
        &self,
        token: &str,
        line: usize,
        what: impl FnOnce() -> String,
    ) -> Result<usize, MocapError> {
        token.parse::<usize>().map_err(|_| {
            self.error(
                line,
                ParseProblem::NotANumber {
                    what: what(),
                    found: token.to_owned(),
                },
            )
        })
    }

    /// Parses three finite numbers from `tokens` (further tokens are left to the caller);
    /// `what` names the vector, e.g. `OFFSET of joint LeftKnee`, and is only built on error.
    pub(crate) fn vector3<'t>(
        &self,
        tokens: &mut impl Iterator<Item = &'t str>,
        line: usize,
        what: impl Fn() -> String,
    ) -> Result<[f64; 3], MocapError> {
        let mut v = [0.0; 3];
        for (i, c) in v.iter_mut().enumerate() {
            let Some(token) = tokens.next() else {
                return Err(self.error(
                    line,
                    ParseProblem::ValueCount {
                        what: what(),
                        expected: 3,
                        found: i,
                    },
                ));
            };
            *c = self.number(token, line, || format!("{} (value {})", what(), i + 1))?;
        }
        Ok(v)
    }
}

/// Decodes `bytes` as UTF-8 (dropping a leading byte-order mark).
///
/// Errors: [`ParseProblem::NotUtf8`] at the line of the first invalid byte,
/// [`ParseProblem::Empty`] when there is nothing but whitespace.
pub(crate) fn decode<'a>(bytes: &'a [u8], source: Source<'_>) -> Result<&'a str, MocapError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let valid = bytes.get(..e.valid_up_to()).unwrap_or_default();
        let line = 1 + valid.iter().filter(|&&b| b == b'\n').count();
        source.error(line, ParseProblem::NotUtf8)
    })?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(source.error(1, ParseProblem::Empty));
    }
    Ok(text)
}

/// The lines of a text with their 1-based numbers, without the `\n` or `\r\n` terminator.
#[derive(Clone, Debug)]
pub(crate) struct Lines<'a> {
    split: Split<'a, char>,
    number: usize,
}

impl<'a> Lines<'a> {
    /// The lines of `text`.
    pub(crate) fn new(text: &'a str) -> Self {
        Lines {
            split: text.split('\n'),
            number: 0,
        }
    }

    /// Number of the line most recently returned (0 before the first); after the iterator is
    /// exhausted this is the last line, which is where "unexpected end of file" is reported.
    pub(crate) fn number(&self) -> usize {
        self.number.max(1)
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a str);

    fn next(&mut self) -> Option<Self::Item> {
        let line = self.split.next()?;
        self.number += 1;
        Some((self.number, line.strip_suffix('\r').unwrap_or(line)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_strip_crlf_and_count_from_one() {
        let lines: Vec<_> = Lines::new("a\r\nb\nc").collect();
        assert_eq!(lines, vec![(1, "a"), (2, "b"), (3, "c")]);
    }

    #[test]
    fn decode_reports_the_line_of_invalid_utf8() {
        let source = Source { name: "x.bvh" };
        let err = decode(b"ok\nstill ok\nbad \xff here", source).unwrap_err();
        assert_eq!(err.line(), Some(3));
        assert_eq!(err.problem(), Some(&ParseProblem::NotUtf8));
        let err = decode(b" \r\n\t", source).unwrap_err();
        assert_eq!(err.problem(), Some(&ParseProblem::Empty));
        assert_eq!(
            decode("\u{feff}HIERARCHY".as_bytes(), source).unwrap(),
            "HIERARCHY"
        );
    }

    #[test]
    fn numbers_must_be_finite() {
        let source = Source { name: "x" };
        assert_eq!(source.number(".5", 1, String::new).unwrap(), 0.5);
        assert_eq!(source.number("-1e2", 1, String::new).unwrap(), -100.0);
        for bad in ["inf", "NaN", "-infinity"] {
            let err = source.number(bad, 4, || "q".into()).unwrap_err();
            assert!(matches!(
                err.problem(),
                Some(ParseProblem::NotFinite { .. })
            ));
            assert_eq!(err.line(), Some(4));
        }
        let err = source.number("abc", 2, || "q".into()).unwrap_err();
        assert_eq!(err.to_string(), "x:2: expected a number for q, found 'abc'");
    }
}
