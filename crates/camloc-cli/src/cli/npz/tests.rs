use super::*;

// The archive reader of the command-line tests, which checks every offset, size and CRC.
#[path = "../../../tests/common/npz.rs"]
#[allow(dead_code)]
mod reader;

/// A scratch target in the system's temporary folder (scratch files are made beside it).
fn target() -> std::path::PathBuf {
    std::env::temp_dir().join("camloc-npz-unit.npz")
}

/// Columns of every element type and both shapes, `rows` rows.
fn entries(rows: usize) -> Vec<Entry> {
    let t = target();
    let mut probabilities = Column::<f64>::new(&t, "probabilities", Some(3)).unwrap();
    let mut label = Column::<u16>::new(&t, "label", None).unwrap();
    let mut failed = Column::<bool>::new(&t, "failed", None).unwrap();
    let mut frame = Column::<i64>::new(&t, "frame", None).unwrap();
    let mut end = Column::<u64>::new(&t, "id_end", None).unwrap();
    let mut text = Column::<u8>::new(&t, "id_utf8", None).unwrap();
    for r in 0..rows {
        probabilities.extend([r as f64, 0.5, f64::NAN]).unwrap();
        label.push(r as u16 + 1).unwrap();
        failed.push(r % 2 == 1).unwrap();
        frame.push(r as i64 - 1).unwrap();
        text.extend(format!("é{r}").bytes()).unwrap();
        end.push(text.values).unwrap();
    }
    [
        probabilities.entry(),
        label.entry(),
        failed.entry(),
        frame.entry(),
        end.entry(),
        text.entry(),
    ]
    .into_iter()
    .collect::<io::Result<_>>()
    .unwrap()
}

fn archive(rows: usize, zip64_from: u64) -> Vec<u8> {
    let mut bytes = Vec::new();
    write_zip(&mut bytes, entries(rows), zip64_from).unwrap();
    bytes
}

#[test]
fn arrays_read_back_with_their_types_and_shapes_with_and_without_zip64() {
    let plain = archive(5, ZIP64_FROM);
    // 0: every record in ZIP64 form; 700: the first entries plain, the later ones ZIP64.
    for zip64_from in [ZIP64_FROM, 0, 700] {
        let bytes = archive(5, zip64_from);
        assert_eq!(
            bytes.len() > plain.len(),
            zip64_from < ZIP64_FROM,
            "ZIP64 records were written where they had to be"
        );
        let npz = reader::Npz::parse(&bytes);
        let names = [
            "failed",
            "frame",
            "id_end",
            "id_utf8",
            "label",
            "probabilities",
        ];
        assert_eq!(npz.names(), names);
        let (shape, p) = npz.array::<f64>("probabilities");
        assert_eq!(shape, [5, 3]);
        assert_eq!(p[6..8], [2.0, 0.5]);
        assert!(p[8].is_nan());
        assert_eq!(npz.array::<u16>("label"), (vec![5], vec![1, 2, 3, 4, 5]));
        assert_eq!(
            npz.array::<bool>("failed").1,
            [false, true, false, true, false]
        );
        assert_eq!(npz.array::<i64>("frame").1, [-1, 0, 1, 2, 3]);
        let (_, utf8) = npz.array::<u8>("id_utf8");
        let (_, end) = npz.array::<u64>("id_end");
        assert_eq!(end, [3, 6, 9, 12, 15]);
        assert_eq!(std::str::from_utf8(&utf8[6..9]).unwrap(), "é2");
        let descrs = ["'|b1'", "'<i8'", "'<u8'", "'|u1'", "'<u2'", "'<f8'"];
        for (name, descr) in names.iter().zip(descrs) {
            assert_eq!(npz.descr(name), descr, "{name}");
        }
    }
}

#[test]
fn empty_arrays_have_zero_rows() {
    let npz = reader::Npz::parse(&archive(0, ZIP64_FROM));
    assert_eq!(npz.array::<f64>("probabilities"), (vec![0, 3], vec![]));
    assert_eq!(npz.array::<u16>("label"), (vec![0], vec![]));
}

#[test]
fn npy_headers_end_on_a_64_byte_boundary() {
    for shape in ["(0,)", "(7, 12)", "(18446744073709551615, 255)"] {
        let header = npy_header("<f8", shape);
        assert_eq!(header.len() % 64, 0, "{shape}");
        assert_eq!(header.last(), Some(&b'\n'));
        let len = u16::from_le_bytes([header[8], header[9]]) as usize;
        assert_eq!(len + 10, header.len());
    }
}

/// Python's own zip reader (the one `numpy.load` uses) accepts both forms and finds every
/// entry's size and CRC; skipped visibly without `python3`.
#[test]
fn python_zipfile_reads_both_forms() {
    let dir = std::env::temp_dir().join(format!("camloc-npz-py-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for zip64_from in [ZIP64_FROM, 0] {
        let path = dir.join(format!("a{zip64_from}.npz"));
        let bytes = archive(4, zip64_from);
        std::fs::write(&path, &bytes).unwrap();
        let script = "import sys, zipfile\n\
                      z = zipfile.ZipFile(sys.argv[1])\n\
                      assert z.testzip() is None\n\
                      for i in z.infolist(): print(i.filename, i.file_size, i.CRC)";
        let run = std::process::Command::new("python3")
            .args(["-c", script])
            .arg(&path)
            .output();
        let Ok(run) = run else {
            stderr_line!("SKIPPED: python3 not found, zip archive not checked by Python");
            break;
        };
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let expected: Vec<String> = reader::entries(&bytes)
            .iter()
            .map(|(name, data)| format!("{name} {} {}", data.len(), crc32fast::hash(data)))
            .collect();
        let printed = String::from_utf8(run.stdout).unwrap();
        assert_eq!(printed.lines().collect::<Vec<_>>(), expected);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
