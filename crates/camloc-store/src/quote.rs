//! How messages quote text that came from the user (pose ids, image names, keys, file names,
//! array shapes): control and bidirectional formatting characters escaped, so that nothing
//! reaches a terminal or a drawing raw, and cut to a bounded length, so that a message stays
//! one short line whatever the input.

use std::borrow::Cow;
use std::fmt::Write;
use std::path::Path;

/// The most characters of one piece of input (a key, a field, a header, an id) that a message
/// quotes; longer text is cut there and ends with `…`.
pub const MAX_QUOTED_CHARS: usize = 80;

/// The most characters of a file name a message quotes; a longer one keeps its start and its
/// end (the file's own name) around a `…`.
pub const MAX_QUOTED_PATH_CHARS: usize = 100;

/// Whether `c` is escaped where user text is shown: a control character, a bidirectional
/// formatting character (U+061C, U+200E, U+200F, U+202A to U+202E, U+2066 to U+2069), which would
/// turn the rest of a line around, numbers included ("p = 0.57" read "75.0 = p"), or
/// U+FFFE and U+FFFF, which XML cannot hold (a drawing's caption with one is not read).
fn escapes(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{061c}'
                | '\u{200e}'
                | '\u{200f}'
                | '\u{202a}'..='\u{202e}'
                | '\u{2066}'..='\u{2069}'
                | '\u{fffe}'
                | '\u{ffff}'
        )
}

/// `text` as the text of an SVG or HTML element: [`escaped`], then `&`, `<` and `>` as
/// references (XML cannot hold most control characters, even as references).
pub fn markup_escaped(text: &str) -> String {
    escaped(text)
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// `text` with its control and bidirectional formatting characters escaped (`\n`,
/// `\u{1b}`, `\u{202e}`, ...), nothing cut: for output that shows user text whole (ids in
/// text output, drawing captions).
pub fn escaped(text: &str) -> Cow<'_, str> {
    if text.chars().any(escapes) {
        Cow::Owned(cut(text, usize::MAX, 0))
    } else {
        Cow::Borrowed(text)
    }
}

/// `text` as a message quotes it: control characters escaped, at most [`MAX_QUOTED_CHARS`]
/// characters of it (then `…`).
pub fn quoted(text: &str) -> String {
    cut(text, MAX_QUOTED_CHARS, 0)
}

/// A file name as a message quotes it: control characters escaped, at most
/// [`MAX_QUOTED_PATH_CHARS`] characters (the start and the end of a longer one, around `…`).
pub fn quoted_path(path: &Path) -> String {
    let text = path.to_string_lossy();
    let tail = MAX_QUOTED_PATH_CHARS / 2;
    cut(&text, MAX_QUOTED_PATH_CHARS - tail, tail)
}

/// Escapes `text` and keeps at most its first `head` and last `tail` characters of a longer
/// text, counted as shown (an escaped character takes its escape's length: a run of control
/// characters is cut as short as plain text), with `…` between (or at the end when `tail` is
/// 0).
fn cut(text: &str, head: usize, tail: usize) -> String {
    let width = |c: char| {
        if escapes(c) {
            c.escape_default().count()
        } else {
            1
        }
    };
    let mut out = String::new();
    if text.chars().map(width).sum::<usize>() <= head.saturating_add(tail) {
        text.chars().for_each(|c| push_shown(&mut out, c));
        return out;
    }
    let mut used = 0usize;
    for c in text.chars() {
        used += width(c);
        if used > head {
            break;
        }
        push_shown(&mut out, c);
    }
    out.push('…');
    // The last characters that `tail` shows.
    let (mut used, mut start) = (0usize, text.len());
    for (i, c) in text.char_indices().rev() {
        used += width(c);
        if used > tail {
            break;
        }
        start = i;
    }
    text[start..].chars().for_each(|c| push_shown(&mut out, c));
    out
}

/// Appends `c` to `out` as messages show it: escaped when [`escapes`] says so.
fn push_shown(out: &mut String, c: char) {
    if escapes(c) {
        let _ = write!(out, "{}", c.escape_default());
    } else {
        out.push(c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_escaped_and_long_text_cut() {
        assert_eq!(escaped("a\u{1b}[31mb\n"), "a\\u{1b}[31mb\\n");
        assert_eq!(escaped("id\u{202e}p = 0.57"), "id\\u{202e}p = 0.57");
        assert_eq!(quoted("\u{2067}x\u{200f}"), "\\u{2067}x\\u{200f}");
        assert!(matches!(escaped("plain"), Cow::Borrowed("plain")));
        let long = "x".repeat(100_000);
        let q = quoted(&long);
        assert_eq!(q.chars().count(), MAX_QUOTED_CHARS + 1);
        assert!(q.ends_with('…'));
        assert_eq!(quoted("short"), "short");
        let path = format!("/{}/frame_7.json", "d".repeat(5_000));
        let q = quoted_path(Path::new(&path));
        assert_eq!(q.chars().count(), MAX_QUOTED_PATH_CHARS + 1);
        assert!(
            q.starts_with("/ddd") && q.ends_with("d/frame_7.json"),
            "{q}"
        );
        assert_eq!(quoted_path(Path::new("a\nb.json")), "a\\nb.json");
        // Escapes count as shown: 100 ESC characters are cut at 80 shown characters, not
        // 80 escapes of 6 (trial118: 480-character pieces).
        let q = quoted(&"\u{1b}".repeat(100));
        assert!(q.chars().count() <= MAX_QUOTED_CHARS + 1, "{q}");
        assert!(q.starts_with("\\u{1b}") && q.ends_with('…'), "{q}");
        let q = quoted_path(Path::new(&"a\u{202e}b".repeat(60)));
        assert!(q.chars().count() <= MAX_QUOTED_PATH_CHARS + 1, "{q}");
        assert_eq!(escaped(&"\u{1b}".repeat(3)), "\\u{1b}".repeat(3));
        assert_eq!(markup_escaped("a\u{fffe}<&>"), "a\\u{fffe}&lt;&amp;&gt;");
    }
}
