//! A reader of the `.npz` archives `localize --npz` writes (zip, stored entries, ZIP64 records
//! where present), for tests: every offset, size and CRC-32 is checked, and the `.npy` entries
//! are read by npyz.

use std::collections::BTreeMap;

/// The `.npy` entries of an archive by name (without `.npy`).
pub struct Npz(pub BTreeMap<String, Vec<u8>>);

impl Npz {
    /// Reads the archive in `bytes`, panicking on anything malformed.
    pub fn parse(bytes: &[u8]) -> Npz {
        let mut arrays = BTreeMap::new();
        for (name, data) in entries(bytes) {
            let name = name.strip_suffix(".npy").expect("entries are .npy files");
            assert!(
                arrays.insert(name.to_owned(), data).is_none(),
                "{name} twice"
            );
        }
        Npz(arrays)
    }

    /// The names of the arrays, sorted.
    pub fn names(&self) -> Vec<&str> {
        self.0.keys().map(String::as_str).collect()
    }

    fn npy(&self, name: &str) -> npyz::NpyFile<&[u8]> {
        let bytes = self
            .0
            .get(name)
            .unwrap_or_else(|| panic!("no array {name}"));
        npyz::NpyFile::new(&bytes[..]).expect("a .npy entry")
    }

    /// Array `name`'s shape and values (C order).
    pub fn array<T: npyz::Deserialize>(&self, name: &str) -> (Vec<u64>, Vec<T>) {
        let npy = self.npy(name);
        assert_eq!(npy.order(), npyz::Order::C);
        let shape = npy.shape().to_vec();
        (shape, npy.into_vec::<T>().unwrap())
    }

    /// Array `name`'s NumPy type string, quoted (`'<f8'`, ...).
    pub fn descr(&self, name: &str) -> String {
        self.npy(name).dtype().descr()
    }
}

fn u16_at(b: &[u8], at: usize) -> u64 {
    u16::from_le_bytes(b[at..at + 2].try_into().unwrap()).into()
}

fn u32_at(b: &[u8], at: usize) -> u64 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap()).into()
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(b[at..at + 8].try_into().unwrap())
}

/// The (name, content) of every entry of a zip archive without comment, in directory order.
pub fn entries(bytes: &[u8]) -> Vec<(String, Vec<u8>)> {
    let end = bytes.len() - 22;
    assert_eq!(u32_at(bytes, end), 0x0605_4b50, "end of central directory");
    let (mut count, mut dir_size, mut dir_offset) = (
        u16_at(bytes, end + 10),
        u32_at(bytes, end + 12),
        u32_at(bytes, end + 16),
    );
    if count == 0xFFFF || dir_size == 0xFFFF_FFFF || dir_offset == 0xFFFF_FFFF {
        let locator = end - 20;
        assert_eq!(u32_at(bytes, locator), 0x0706_4b50, "ZIP64 locator");
        let record = u64_at(bytes, locator + 8) as usize;
        assert_eq!(record, locator - 56, "ZIP64 record just before its locator");
        assert_eq!(u32_at(bytes, record), 0x0606_4b50, "ZIP64 record");
        count = u64_at(bytes, record + 32);
        dir_size = u64_at(bytes, record + 40);
        dir_offset = u64_at(bytes, record + 48);
        assert_eq!(dir_offset + dir_size, record as u64);
    } else {
        assert_eq!(dir_offset + dir_size, end as u64);
    }
    let mut at = dir_offset as usize;
    let mut out = Vec::new();
    let mut next_local = 0u64;
    for _ in 0..count {
        assert_eq!(u32_at(bytes, at), 0x0201_4b50, "central header");
        assert_eq!(u16_at(bytes, at + 10), 0, "stored");
        let crc = u32_at(bytes, at + 16);
        let (mut size, mut original) = (u32_at(bytes, at + 20), u32_at(bytes, at + 24));
        let (name_len, extra_len) = (u16_at(bytes, at + 28), u16_at(bytes, at + 30));
        let mut offset = u32_at(bytes, at + 42);
        let name_at = at + 46;
        let name = std::str::from_utf8(&bytes[name_at..name_at + name_len as usize]).unwrap();
        let mut extra = &bytes[name_at + name_len as usize..][..extra_len as usize];
        while !extra.is_empty() {
            let (id, len) = (u16_at(extra, 0), u16_at(extra, 2) as usize);
            let mut field = &extra[4..4 + len];
            if id == 1 {
                for value in [&mut original, &mut size, &mut offset] {
                    if *value == 0xFFFF_FFFF {
                        *value = u64_at(field, 0);
                        field = &field[8..];
                    }
                }
                assert!(
                    field.is_empty(),
                    "ZIP64 field of {name} holds what it replaces"
                );
            }
            extra = &extra[4 + len..];
        }
        assert_eq!(size, original, "{name} stored");
        assert_eq!(offset, next_local, "{name} follows the previous entry");
        let local = offset as usize;
        assert_eq!(u32_at(bytes, local), 0x0403_4b50, "local header of {name}");
        assert_eq!(
            u32_at(bytes, local + 14),
            crc,
            "{name}: local and central CRC"
        );
        let (local_name, local_extra) = (u16_at(bytes, local + 26), u16_at(bytes, local + 28));
        assert_eq!(
            &bytes[local + 30..local + 30 + local_name as usize],
            name.as_bytes()
        );
        let data_at = local + 30 + (local_name + local_extra) as usize;
        let data = bytes[data_at..data_at + size as usize].to_vec();
        assert_eq!(u64::from(crc32fast::hash(&data)), crc, "{name}: CRC-32");
        next_local = (data_at as u64) + size;
        out.push((name.to_owned(), data));
        at = name_at + (name_len + extra_len) as usize + u16_at(bytes, at + 32) as usize;
    }
    assert_eq!(
        next_local, dir_offset,
        "the directory follows the last entry"
    );
    out
}
