use super::*;
use proptest::prelude::*;
use std::io::Write;

const KIND: FileKind = FileKind {
    magic: *b"CAMLOCTS",
    version: 3,
    what: "test",
    max_payload: 4096,
};

#[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
struct Thing {
    name: String,
    values: Vec<f64>,
}

#[derive(Debug, thiserror::Error)]
#[error("value {0} is not finite")]
struct NotFinite(f64);

impl Validate for Thing {
    type Invalid = NotFinite;
    fn validate(&self) -> Result<(), NotFinite> {
        match self.values.iter().find(|v| !v.is_finite()) {
            Some(&v) => Err(NotFinite(v)),
            None => Ok(()),
        }
    }
}

impl Persist for Thing {
    const KIND: FileKind = KIND;
}

fn thing() -> Thing {
    Thing {
        name: "abc".into(),
        values: vec![1.5, -2.0, 3.25, 1e300],
    }
}

proptest! {
    #[test]
    fn round_trip_is_exact(name in ".{0,20}", values in proptest::collection::vec(proptest::num::f64::ANY, 0..50)) {
        let t = Thing { name, values };
        let bytes = encode(KIND, &t).unwrap();
        let back: Thing = decode(KIND, &bytes, MEMORY_ORIGIN).unwrap();
        prop_assert_eq!(encode(KIND, &back).unwrap(), bytes);
    }

    #[test]
    fn any_flipped_byte_is_refused(pos in 0usize..200, bit in 0u8..8) {
        let mut bytes = encode(KIND, &thing()).unwrap();
        let pos = pos % bytes.len();
        bytes[pos] ^= 1 << bit;
        prop_assert!(Thing::from_bytes(&bytes).is_err());
    }
}

#[test]
fn kind_version_and_truncation_errors() {
    let bytes = encode(KIND, &vec![1u32, 2, 3]).unwrap();
    let other = FileKind { version: 4, ..KIND };
    assert!(matches!(
        decode::<Vec<u32>>(other, &bytes, "f.bin"),
        Err(StoreError::Version {
            found: 3,
            expected: 4,
            ..
        })
    ));
    let wrong = FileKind {
        magic: *b"CAMLOCXX",
        ..KIND
    };
    assert!(matches!(
        decode::<Vec<u32>>(wrong, &bytes, "f.bin"),
        Err(StoreError::WrongKind { other: None, .. })
    ));
    for len in [bytes.len() - 1, 10] {
        assert!(matches!(
            decode::<Vec<u32>>(KIND, &bytes[..len], "f.bin"),
            Err(StoreError::Corrupt { .. })
        ));
    }
    let mut padded = bytes.clone();
    padded.push(0);
    assert!(matches!(
        decode::<Vec<u32>>(KIND, &padded, "f.bin"),
        Err(StoreError::Corrupt { .. })
    ));
    assert!(matches!(
        decode::<Vec<u32>>(KIND, b"", "f.bin"),
        Err(StoreError::WrongKind { .. })
    ));
}

#[test]
fn wrong_kind_names_the_file_and_what_it_is() {
    let dataset = envelope(DATASET_KIND, b"");
    let err = decode::<Vec<u32>>(MODEL_KIND, &dataset, "model.bin").unwrap_err();
    assert_eq!(
        err.to_string(),
        "model.bin: not a camloc model file (magic bytes \"CAMLOCDS\": this is a dataset)"
    );
    let err = decode::<Vec<u32>>(MODEL_KIND, b"\0\x01PK", "x.bin").unwrap_err();
    assert_eq!(
        err.to_string(),
        "x.bin: not a camloc model file (magic bytes \"\\x00\\x01PK\")"
    );
}

#[test]
fn validation_runs_after_every_decode_and_names_the_origin() {
    let bad = Thing {
        name: "x".into(),
        values: vec![1.0, f64::INFINITY],
    };
    let bytes = bad.to_bytes().unwrap();
    let err = Thing::from_bytes_named(&bytes, "t.bin").unwrap_err();
    assert!(matches!(err, StoreError::Invalid { .. }), "{err:?}");
    assert_eq!(
        err.to_string(),
        "t.bin: invalid camloc test file: value inf is not finite"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.bin");
    fs::write(&path, &bytes).unwrap();
    assert!(matches!(
        Thing::load(&path),
        Err(StoreError::Invalid { .. })
    ));
}

/// A header that declares `len` payload bytes (with the checksum of nothing).
fn forged_header(kind: FileKind, len: u64) -> Vec<u8> {
    let mut h = envelope(kind, b"");
    h[12..20].copy_from_slice(&len.to_le_bytes());
    h
}

#[test]
fn a_forged_length_is_capped_by_the_kind_and_by_the_file() {
    let huge = forged_header(KIND, u64::MAX);
    assert!(matches!(
        Thing::from_bytes(&huge),
        Err(StoreError::TooLarge {
            declared: u64::MAX,
            max: 4096,
            ..
        })
    ));
    // Within the cap but longer than the file: refused before reading the payload.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("forged.bin");
    fs::write(&path, forged_header(KIND, 4000)).unwrap();
    let err = Thing::load(&path).unwrap_err();
    assert!(matches!(err, StoreError::Corrupt { .. }), "{err:?}");
    assert!(err.to_string().starts_with(&path.display().to_string()));
    // The real kinds: a dataset header claiming 16 EiB.
    let err = decode::<Vec<u8>>(DATASET_KIND, &forged_header(DATASET_KIND, 1 << 60), "d.bin")
        .unwrap_err();
    assert!(matches!(err, StoreError::TooLarge { .. }), "{err:?}");
}

#[test]
fn a_stream_is_read_only_as_far_as_the_header_allows() {
    // A source that never ends (like /dev/zero or a pipe), with a valid header in front.
    let header = forged_header(KIND, 16);
    let mut endless = header.as_slice().chain(std::io::repeat(7));
    let err = read_envelope::<Thing>(KIND, &mut endless, None, "pipe").unwrap_err();
    assert!(matches!(err, StoreError::Corrupt { .. }), "{err:?}");
    let mut zeros = std::io::repeat(0);
    assert!(matches!(
        read_envelope::<Thing>(KIND, &mut zeros, None, "zeros"),
        Err(StoreError::WrongKind { .. })
    ));
}

#[cfg(unix)]
#[test]
fn dev_zero_fails_fast() {
    let zero = Path::new("/dev/zero");
    if !zero.exists() {
        eprintln!("SKIPPED dev_zero_fails_fast: /dev/zero does not exist here");
        return;
    }
    let err = Thing::load(zero).unwrap_err();
    assert!(matches!(err, StoreError::WrongKind { .. }), "{err:?}");
    assert!(err.to_string().starts_with("/dev/zero: "), "{err}");
}

#[test]
fn write_new_refuses_to_overwrite_and_leaves_no_temporary() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.bin");
    write_new(&path, b"first", false).unwrap();
    assert!(matches!(
        write_new(&path, b"second", false),
        Err(StoreError::Exists { .. })
    ));
    assert_eq!(fs::read(&path).unwrap(), b"first");
    write_new(&path, b"third", true).unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"third");
    let names: Vec<_> = fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["out.bin"]);
    #[cfg(unix)]
    {
        // Same mode as a file made by `File::create` (0666 less the umask), not 0600.
        use std::os::unix::fs::PermissionsExt;
        let plain = dir.path().join("plain.bin");
        fs::File::create(&plain).unwrap();
        let mode = |p: &Path| fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&path), mode(&plain));
    }
    assert!(matches!(
        write_new(&dir.path().join("missing-dir").join("x.bin"), b"x", false),
        Err(StoreError::Io { .. })
    ));
    assert!(matches!(
        write_new(dir.path(), b"x", true),
        Err(StoreError::NotRegular {
            kind: "directory",
            ..
        })
    ));
}

#[cfg(unix)]
#[test]
fn symlinks_are_never_followed_and_replaced_only_with_force() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("target.txt");
    fs::write(&target, b"precious").unwrap();
    let link = dir.path().join("link.txt");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let err = write_new(&link, b"new", false).unwrap_err();
    assert!(matches!(err, StoreError::Symlink { .. }), "{err:?}");
    assert_eq!(fs::read(&target).unwrap(), b"precious");
    // A dangling link is refused too (writing would create its target).
    let dangling = dir.path().join("dangling.txt");
    std::os::unix::fs::symlink(dir.path().join("nowhere"), &dangling).unwrap();
    assert!(matches!(
        write_new(&dangling, b"new", false),
        Err(StoreError::Symlink { .. })
    ));
    assert!(!dir.path().join("nowhere").exists());
    // With force the link itself is replaced by a regular file; the target is untouched.
    write_new(&link, b"new", true).unwrap();
    assert!(fs::symlink_metadata(&link).unwrap().file_type().is_file());
    assert_eq!(fs::read(&link).unwrap(), b"new");
    assert_eq!(fs::read(&target).unwrap(), b"precious");
}

#[cfg(unix)]
#[test]
fn special_files_are_refused_even_with_force() {
    use std::os::unix::fs::FileTypeExt;
    let null = Path::new("/dev/null");
    if null.exists() {
        for force in [false, true] {
            let err = write_new(null, b"x", force).unwrap_err();
            assert!(
                matches!(
                    err,
                    StoreError::NotRegular {
                        kind: "character device",
                        ..
                    }
                ),
                "{err:?}"
            );
        }
        assert!(
            fs::symlink_metadata(null)
                .unwrap()
                .file_type()
                .is_char_device()
        );
    } else {
        eprintln!("SKIPPED /dev/null part: it does not exist here");
    }
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !matches!(made, Ok(s) if s.success()) {
        eprintln!("SKIPPED FIFO part: mkfifo is not available");
        return;
    }
    let err = write_new(&fifo, b"x", true).unwrap_err();
    assert!(
        matches!(err, StoreError::NotRegular { kind: "FIFO", .. }),
        "{err:?}"
    );
    assert!(fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo());
}

/// Names in `dir`, sorted.
fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<_> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn staged_files_are_all_or_nothing_and_never_clobber() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.txt"), dir.path().join("b.txt"));
    // Two files for one target: the second no-clobber rename finds the first in place, fails,
    // and the first is taken back.
    let mut staged = StagedFiles::new(false);
    staged.add(&a, b"one").unwrap();
    staged.add(&a, b"two").unwrap();
    assert!(matches!(staged.commit(), Err(StoreError::Exists { .. })));
    assert!(
        names_in(dir.path()).is_empty(),
        "{:?}",
        names_in(dir.path())
    );
    // A file that appears at a target after staging is not replaced.
    let mut staged = StagedFiles::new(false);
    staged.add(&a, b"staged").unwrap();
    staged.add(&b, b"staged").unwrap();
    fs::write(&b, b"theirs").unwrap();
    assert!(matches!(staged.commit(), Err(StoreError::Exists { .. })));
    assert_eq!(names_in(dir.path()), ["b.txt"]);
    assert_eq!(fs::read(&b).unwrap(), b"theirs");
    // With overwrite, a failure at the second file puts the replaced first file back.
    fs::write(&a, b"old a").unwrap();
    let mut staged = StagedFiles::new(true);
    staged.add(&a, b"new a").unwrap();
    let at = staged.add(&b, b"new b").unwrap();
    staged.retarget(at, &dir.path().join("missing-dir").join("b.txt"));
    assert!(matches!(staged.commit(), Err(StoreError::Io { .. })));
    assert_eq!(names_in(dir.path()), ["a.txt", "b.txt"]);
    assert_eq!(fs::read(&a).unwrap(), b"old a");
    // And a successful commit replaces both, leaving no temporary or backup.
    let mut staged = StagedFiles::new(true);
    staged.add(&a, b"new a").unwrap();
    staged
        .add_with(&b, |w| {
            w.write_all(b"new ").and_then(|()| w.write_all(b"b"))
        })
        .unwrap();
    assert_eq!(staged.commit().unwrap(), [a.clone(), b.clone()]);
    assert_eq!(names_in(dir.path()), ["a.txt", "b.txt"]);
    assert_eq!(fs::read(&a).unwrap(), b"new a");
    assert_eq!(fs::read(&b).unwrap(), b"new b");
}

#[test]
fn staged_files_dropped_without_commit_leave_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut staged = StagedFiles::new(false);
    staged.add(&dir.path().join("a.txt"), b"a").unwrap();
    staged.add(&dir.path().join("b.txt"), b"b").unwrap();
    assert_eq!(
        names_in(dir.path()).len(),
        2,
        "two temporaries while staged"
    );
    drop(staged);
    assert!(names_in(dir.path()).is_empty());
    // Refused targets are refused before anything moves.
    fs::write(dir.path().join("b.txt"), b"mine").unwrap();
    let mut staged = StagedFiles::new(false);
    staged.add(&dir.path().join("a.txt"), b"a").unwrap();
    staged.add(&dir.path().join("b.txt"), b"b").unwrap();
    assert!(matches!(staged.commit(), Err(StoreError::Exists { .. })));
    assert_eq!(names_in(dir.path()), ["b.txt"]);
    let mut staged = StagedFiles::new(true);
    staged.add(dir.path(), b"x").unwrap();
    assert!(matches!(
        staged.commit(),
        Err(StoreError::NotRegular {
            kind: "directory",
            ..
        })
    ));
    assert_eq!(names_in(dir.path()), ["b.txt"]);
}

#[test]
fn scratch_files_leave_nothing_behind() {
    use std::io::{Read, Seek};
    let dir = tempfile::tempdir().unwrap();
    let mut scratch = scratch_beside(&dir.path().join("out.npy")).unwrap();
    scratch.write_all(b"body").unwrap();
    scratch.rewind().unwrap();
    let mut back = String::new();
    scratch.read_to_string(&mut back).unwrap();
    assert_eq!(back, "body");
    drop(scratch);
    assert!(names_in(dir.path()).is_empty());
}

#[test]
fn undecodable_payloads_are_named_in_words() {
    use bincode::error::DecodeError;
    let early = decode_problem(&DecodeError::UnexpectedEnd { additional: 59936 });
    assert_eq!(early, "it ends 59936 bytes too early");
    for e in [
        DecodeError::LimitExceeded,
        DecodeError::InvalidBooleanValue(7),
    ] {
        let words = decode_problem(&e);
        assert!(
            !words.contains('{') && !words.contains("Invalid"),
            "{words}"
        );
    }
}

/// An output whose name is as long as a file system allows (250 bytes, non-ASCII at the cut)
/// is written and replaced: its temporary and backup names repeat at most 200 bytes of it.
#[test]
fn an_output_of_a_long_name_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let name = format!("{}é{}.json", "n".repeat(199), "m".repeat(44));
    assert_eq!(name.len(), 250);
    let path = dir.path().join(&name);
    write_new(&path, b"one", false).unwrap();
    write_new(&path, b"two", true).unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"two");
    let mut staged = StagedFiles::new(true);
    staged.add(&path, b"three").unwrap();
    staged.commit().unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"three");
    assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
}

/// A temporary file that cannot be made is reported on the output, with the system's reason
/// alone: `tempfile` adds the temporary file's whole path (trial118: a 614-character line).
#[cfg(target_os = "linux")]
#[test]
fn a_failed_temporary_file_is_said_without_its_path() {
    let err = write_new(Path::new("/proc/camloc-output.bin"), b"x", false).unwrap_err();
    let message = err.to_string();
    assert!(
        message.starts_with("/proc/camloc-output.bin: "),
        "{message}"
    );
    assert!(
        !message.contains("at path") && !message.contains(".tmp"),
        "{message}"
    );
}
