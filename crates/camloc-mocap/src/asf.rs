//! CMU ASF (Acclaim skeleton file) reader and the forward kinematics of its bones.

use std::path::Path;

use super::error::MocapError;
use super::read_file;
use super::text::{Lines, Source, decode};

mod parse;
mod skeleton;

use parse::RawSkeleton;
pub use skeleton::AsfSkeleton;

/// Reads an ASF skeleton; see [`parse_asf`] for the conventions.
///
/// # Errors
///
/// [`MocapError::Io`] when the file cannot be read, otherwise as [`parse_asf`].
pub fn read_asf(path: impl AsRef<Path>) -> Result<AsfSkeleton, MocapError> {
    let path = path.as_ref();
    parse_asf(&read_file(path)?, &path.display().to_string())
}

/// Parses ASF text (as `&str` or raw bytes) into a skeleton whose motions
/// [`parse_amc`](super::parse_amc) can read.
///
/// # Format
///
/// Sections start with a `:keyword` line; `#` starts a comment; `(`, `)` and `,` count as
/// whitespace; unknown sections and keys (`:version`, `:documentation`, `id`, `limits`, ...)
/// are skipped.
///
/// * `:units`: `length L` (one unit is `1 / L` inch, the CMU convention; default 1) and
///   `angle deg|rad` (default `deg`).
/// * `:root`: `order` (the AMC root values, e.g. `TX TY TZ RX RY RZ`; required), `axis` (order
///   of the `orientation` angles), `position`, `orientation` (both default to zero).
/// * `:bonedata`: `begin` .. `end` blocks with `name`, `direction` (the rest-pose direction in
///   the file frame), `length`, `axis ax ay az ORDER` (the bone frame: angles about x, y and z
///   applied in the order `ORDER`, e.g. `XYZ` is `C = Rz * Ry * Rx`) and `dof` (any of
///   `rx ry rz`, in the order the AMC lists the values).
/// * `:hierarchy`: `begin`, lines `parent child ...` (the parent may be `root`), `end`. Every
///   bone must be attached to the root.
///
/// # Kinematics
///
/// The standard CMU way: a motion rotation `M` applies the listed rotations in order about
/// fixed axes (`dof rx ry rz` gives `M = Rz * Ry * Rx`; the same for the root `order`); a
/// bone's world rotation is `W = W_parent * C * M * C^-1` (the root's `W = C * M * C^-1` with
/// `C` from `orientation`), and its end point is `start + W * direction * length`, `start` being
/// the parent's end point or the root position (`position` plus the AMC translation).
///
/// # Landmarks
///
/// Each landmark is the end point of a bone (names compared ignoring ASCII case): hip
/// `lhipjoint`, knee `lfemur`, ankle `ltibia`, neck `thorax`, head `upperneck`, shoulder
/// `lclavicle`, elbow `lhumerus`, wrist `lradius` (right side `r...`); the pelvis is the root
/// position.
///
/// # Errors
///
/// [`MocapError::Parse`] with the line of the first problem (invalid UTF-8, empty file,
/// malformed or non-finite numbers, unknown units or dofs, unsupported translation dofs,
/// repeated bones, unknown names in `:hierarchy`, unattached bones, missing `:root`/`order` or
/// `:hierarchy`); [`MocapError::MissingLandmark`] when a landmark bone is absent.
pub fn parse_asf<B: AsRef<[u8]> + ?Sized>(
    input: &B,
    source_name: &str,
) -> Result<AsfSkeleton, MocapError> {
    let source = Source { name: source_name };
    let text = decode(input.as_ref(), source)?;
    let mut raw = RawSkeleton::default();
    let mut lines = Lines::new(text);
    for (number, line) in lines.by_ref() {
        let content = line.split('#').next().unwrap_or_default();
        let mut tokens = content
            .split(|c: char| c.is_whitespace() || matches!(c, '(' | ')' | ','))
            .filter(|t| !t.is_empty());
        let Some(key) = tokens.next() else { continue };
        match key.strip_prefix(':') {
            Some(keyword) => raw.start_section(keyword, number, source)?,
            None => raw.line(key, &mut tokens, number, source)?,
        }
    }
    raw.finish(lines.number(), source)
}
