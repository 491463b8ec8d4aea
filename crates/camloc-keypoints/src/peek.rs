//! The start of a text input, read before deciding how to read the rest: a byte-order mark and
//! the white space before the content are skipped and only counted (so that any amount of it
//! costs no memory), then up to [`STREAM_PEEK_BYTES`] of content are kept for format detection
//! and for refusing input that is not text at once.

use std::io::{self, Read};

use crate::error::KeypointError;

/// Text inputs longer than this many bytes (past their blank lead) are streamed when they are
/// JSON (format given, or detected from these first bytes of content) or LSP CSV; shorter ones
/// are read whole.
pub const STREAM_PEEK_BYTES: u64 = 1 << 16;

/// UTF-8's byte-order mark.
const BOM: &[u8] = b"\xEF\xBB\xBF";

/// The start of a text input (see the module documentation).
#[derive(Default)]
pub(crate) struct Start {
    /// The input starts with a byte-order mark.
    bom: bool,
    /// White-space bytes before the last newline of the lead, other than newlines.
    blanks: u64,
    /// Newlines in the lead.
    pub(crate) newlines: u64,
    /// White-space bytes after the last newline of the lead (the column of the content).
    column: u64,
    /// Up to [`STREAM_PEEK_BYTES`] of content after the lead.
    pub(crate) content: Vec<u8>,
    /// The input ended within `content`.
    pub(crate) ended: bool,
}

/// Reads the start of the input `reader` ([`Start::read_as`]) of `size` bytes when known, in
/// `format` when given: a live input (standard input, a pipe: no size) in a JSON format given
/// is peeked at what its first read brings, not 64 KiB, so that a detector writing to it
/// has its first poses answered as they come; otherwise [`STREAM_PEEK_BYTES`] are read for the
/// format's detection.
pub(crate) fn read_start(
    reader: &mut impl Read,
    limit: u64,
    size: Option<u64>,
    format: Option<crate::KeypointFormat>,
) -> io::Result<Start> {
    let eager = size.is_none() && format.is_some_and(|f| f.is_json());
    Start::read_as(reader, limit, eager)
}

impl Start {
    /// Reads the start of `reader`: its lead, then [`STREAM_PEEK_BYTES`] of content, or with
    /// `eager` the content that one read brings (its end known only when that read brings
    /// nothing); stops early (with [`Start::len`] over `limit`) when the lead alone is longer
    /// than `limit` bytes.
    fn read_as(reader: &mut impl Read, limit: u64, eager: bool) -> io::Result<Start> {
        let mut start = Start::default();
        let mut first = true;
        loop {
            let mut chunk = Vec::new();
            let ended = if eager {
                chunk.resize(STREAM_PEEK_BYTES as usize, 0);
                let n = loop {
                    match reader.read(&mut chunk) {
                        Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                        read => break read?,
                    }
                };
                chunk.truncate(n);
                n == 0
            } else {
                reader.take(STREAM_PEEK_BYTES).read_to_end(&mut chunk)?;
                (chunk.len() as u64) < STREAM_PEEK_BYTES
            };
            let mut rest = &chunk[..];
            if first {
                first = false;
                if let Some(after) = rest.strip_prefix(BOM) {
                    start.bom = true;
                    rest = after;
                }
            }
            let blank = rest
                .iter()
                .position(|b| !b" \t\r\n".contains(b))
                .unwrap_or(rest.len());
            start.count_lead(&rest[..blank]);
            if blank < rest.len() || ended {
                start.content = rest[blank..].to_vec();
                if eager {
                    start.ended = ended;
                    return Ok(start);
                }
                let missing = STREAM_PEEK_BYTES - start.content.len() as u64;
                if !ended {
                    reader.take(missing).read_to_end(&mut start.content)?;
                }
                start.ended = (start.content.len() as u64) < STREAM_PEEK_BYTES;
                return Ok(start);
            }
            if start.len() > limit {
                return Ok(start);
            }
        }
    }

    /// Counts the white space `blank` into the lead.
    fn count_lead(&mut self, blank: &[u8]) {
        for &b in blank {
            if b == b'\n' {
                self.blanks += self.column;
                self.column = 0;
                self.newlines += 1;
            } else {
                self.column += 1;
            }
        }
    }

    /// Bytes read so far.
    pub(crate) fn len(&self) -> u64 {
        self.lead_len() + 3 * u64::from(self.bom) + self.content.len() as u64
    }

    /// Bytes of white space before the content.
    pub(crate) fn lead_len(&self) -> u64 {
        self.blanks + self.newlines + self.column
    }

    /// The lead as bytes with the same lines, columns and length (`bom`: with the byte-order
    /// mark, if the input had one).
    pub(crate) fn lead(&self, bom: bool) -> impl Read + Send + 'static {
        let mark = if bom && self.bom { BOM } else { &[] };
        mark.chain(io::repeat(b' ').take(self.blanks))
            .chain(io::repeat(b'\n').take(self.newlines))
            .chain(io::repeat(b' ').take(self.column))
    }

    /// [`KeypointError::NotUtf8`] for an invalid byte in the content (a character cut by the
    /// end of the peek is not one, unless the input ends there).
    pub(crate) fn utf8_error(&self, file: &str) -> Option<KeypointError> {
        let e = std::str::from_utf8(&self.content).err()?;
        if e.error_len().is_none() && !self.ended {
            return None;
        }
        let valid = &self.content[..e.valid_up_to()];
        let newlines = valid.iter().filter(|&&b| b == b'\n').count();
        let before = self.lead_len() as usize + 3 * usize::from(self.bom);
        Some(KeypointError::NotUtf8 {
            file: file.to_owned(),
            line: 1 + self.newlines as usize + newlines,
            offset: before + e.valid_up_to(),
        })
    }

    /// The content as text, up to a character cut by the end of the peek.
    pub(crate) fn text(&self) -> &str {
        match std::str::from_utf8(&self.content) {
            Ok(text) => text,
            Err(e) => std::str::from_utf8(&self.content[..e.valid_up_to()]).unwrap_or_default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lead_is_counted_and_given_back_with_the_same_shape() {
        let mut input = BOM.to_vec();
        input.extend_from_slice(b" \t\r\n\n  ");
        input.extend(vec![b' '; 3 * STREAM_PEEK_BYTES as usize]);
        input.extend_from_slice(b"{\"poses\": []}");
        let start = Start::read_as(&mut &input[..], u64::MAX, false).unwrap();
        assert_eq!(start.content, b"{\"poses\": []}");
        assert!(start.ended);
        assert_eq!(start.len(), input.len() as u64);
        let mut lead = Vec::new();
        start.lead(true).read_to_end(&mut lead).unwrap();
        let original = &input[..input.len() - start.content.len()];
        assert_eq!(lead.len(), original.len());
        let lines = |b: &[u8]| b.iter().filter(|&&c| c == b'\n').count();
        assert_eq!(lines(&lead), lines(original));
        assert_eq!(
            lead.iter().rev().position(|&c| c == b'\n'),
            original.iter().rev().position(|&c| c == b'\n')
        );
    }

    #[test]
    fn an_eager_start_is_what_one_read_brings() {
        // A reader that brings 5 bytes at a time (a pipe a detector writes to).
        struct Trickle<'a>(&'a [u8]);
        impl Read for Trickle<'_> {
            fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
                let n = self.0.len().min(5).min(buf.len());
                buf[..n].copy_from_slice(&self.0[..n]);
                self.0 = &self.0[n..];
                Ok(n)
            }
        }
        let input = b"\n\n   [{\"frame_id\": 0}]";
        let start = Start::read_as(&mut Trickle(input), u64::MAX, true).unwrap();
        // The first read is all lead; the second brings the content's first bytes.
        assert_eq!(start.newlines, 2);
        assert_eq!(start.content, b"[{\"fr");
        assert!(!start.ended);
        let whole = Start::read_as(&mut Trickle(input), u64::MAX, false).unwrap();
        assert_eq!(whole.content, b"[{\"frame_id\": 0}]");
        assert!(whole.ended);
        // Eager only for a live input in a JSON format given.
        let json = Some(crate::KeypointFormat::Camloc);
        let eager = |size, format| {
            read_start(&mut Trickle(input), u64::MAX, size, format)
                .unwrap()
                .content
                .len()
        };
        assert_eq!(eager(None, json), 5);
        assert_eq!(eager(Some(22), json), 17);
        assert_eq!(eager(None, None), 17);
        assert_eq!(eager(None, Some(crate::KeypointFormat::Lsp)), 17);
    }

    #[test]
    fn an_endless_lead_stops_past_the_limit() {
        let start = Start::read_as(&mut io::repeat(b'\n'), 1 << 20, false).unwrap();
        assert!(start.len() > 1 << 20 && start.len() <= (1 << 20) + STREAM_PEEK_BYTES);
    }
}
