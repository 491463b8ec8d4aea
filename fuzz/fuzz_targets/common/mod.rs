//! What the decoder targets (`model`, `basis`, `dataset`) share: how their input becomes a file.

use camloc_store::{FileKind, envelope};

/// The file bytes a decoder target decodes, or `None` for an empty input. The first byte of
/// `data` picks what the rest is: even, a whole file (so the header, kind, version, length
/// and checksum checks are exercised); odd, a payload wrapped in a valid envelope of `kind`
/// (so that mutations reach the bincode decoder and the validation behind the checksum).
pub fn decoder_input(data: &[u8], kind: FileKind) -> Option<Vec<u8>> {
    let (&selector, rest) = data.split_first()?;
    Some(if selector % 2 == 0 {
        rest.to_vec()
    } else {
        envelope(kind, rest)
    })
}
