//! Captions and titles of the drawings broken into lines that fit them.

/// Distance between the lines of a caption (pixels, at the documents' font size 12).
pub(super) const CAPTION_LINE_PX: f64 = 15.0;

/// `caption` broken at spaces into lines that fit `width` pixels (at most one character per
/// 7 pixels, wider than the average sans-serif character at font size 12); a word longer than
/// a line (a path) is broken after its last `/`, `_` or `-` that fits, else where the line
/// ends. At least one line.
pub(super) fn caption_lines(caption: &str, width: f64) -> Vec<String> {
    let max_chars = ((width / 7.0) as usize).max(1);
    let mut lines = vec![String::new()];
    for word in caption.split(' ') {
        let mut rest: Vec<char> = word.chars().collect();
        loop {
            let line = lines.last_mut().expect("lines starts with one line");
            let used = line.chars().count();
            let room = if used == 0 {
                max_chars
            } else {
                max_chars.saturating_sub(used + 1)
            };
            if rest.len() <= room {
                if used > 0 {
                    line.push(' ');
                }
                line.extend(&rest);
                break;
            }
            if used > 0 {
                lines.push(String::new());
                continue;
            }
            let cut = rest[..max_chars]
                .iter()
                .rposition(|c| matches!(c, '/' | '_' | '-'))
                .map_or(max_chars, |k| k + 1);
            line.extend(&rest[..cut]);
            rest.drain(..cut);
            lines.push(String::new());
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::caption_lines;

    #[test]
    fn lines_fit_and_keep_every_word() {
        let missing = "pelvis, right_hip, neck, right_shoulder, right_elbow, right_wrist";
        let caption = format!("im00011: camera 08 (middle right), p = 0.95; missing: {missing}");
        let lines = caption_lines(&caption, 300.0);
        assert!(lines.len() > 1, "{lines:?}");
        assert!(
            lines.iter().all(|l| l.chars().count() <= 300 / 7),
            "{lines:?}"
        );
        assert_eq!(lines.join(" "), caption);
        let path = "/tmp/a-very-long-folder/of-frames/poses.json: person 0";
        let broken = caption_lines(path, 140.0);
        assert!(broken.iter().all(|l| l.chars().count() <= 20), "{broken:?}");
        assert_eq!(broken.concat().replace(' ', ""), path.replace(' ', ""));
        assert_eq!(caption_lines("a/long/path", 35.0), ["a/", "long/", "path"]);
        assert_eq!(caption_lines("abcdefgh", 21.0), ["abc", "def", "gh"]);
        assert_eq!(caption_lines("ab cd ef", 35.0), ["ab cd", "ef"]);
        assert_eq!(caption_lines("", 100.0), [""]);
    }
}
