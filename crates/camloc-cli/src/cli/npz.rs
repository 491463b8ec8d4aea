//! NumPy `.npz` archives written as their rows come, in memory that does not grow with the
//! number of rows.
//!
//! An archive is a zip of `.npy` files, stored uncompressed (as `numpy.savez` writes them),
//! with ZIP64 records only where a size or offset needs them. Each entry's local header holds
//! its size and CRC-32 before its data, and the data of one array must be contiguous, while the
//! rows of all arrays come interleaved and their number is known only at the end of the input
//! (a folder or a JSON stream has no count up front). So each array's values go to its own
//! anonymous scratch file beside the target ([`Column`], through a [`COLUMN_BUFFER`] buffer,
//! counted and checksummed on the way), and [`stage_npz`] writes the archive once every length
//! is known: headers computed from the counts, bodies copied from the scratch files (in the
//! kernel where it can, `copy_file_range` on Linux). Memory: one buffer per array; disk: the
//! arrays twice until the run ends, when the scratch files go.

use std::fs::File;
use std::io::{self, BufReader, BufWriter, Seek, Write};
use std::path::Path;

use camloc::store::{StagedFiles, StoreError, scratch_beside};

/// Bytes buffered per column before they go to its scratch file.
const COLUMN_BUFFER: usize = 1 << 16;

/// A sizes or offset from this value on needs a ZIP64 record (the 32-bit field holds
/// `0xFFFF_FFFF` then).
const ZIP64_FROM: u64 = 0xFFFF_FFFF;

/// The zip version needed to read an entry: 2.0 (stored files), 4.5 with ZIP64 records.
const VERSION_PLAIN: u16 = 20;
const VERSION_ZIP64: u16 = 45;

/// DOS date 1980-01-01 (day 1, month 1, year 0 from 1980), the time stamp of every entry: the
/// archive's content does not depend on when it was written.
const DOS_DATE: u16 = (1 << 5) | 1;

/// An element type of a column, with its NumPy type string (`descr`).
pub trait Element: Copy {
    /// NumPy's name of the type, little-endian (`<f8`, `|u1`, ...).
    const DESCR: &'static str;
    /// Appends the value's little-endian bytes to `out`.
    fn put(self, out: &mut impl Write) -> io::Result<()>;
}

macro_rules! element {
    ($t:ty, $descr:literal) => {
        impl Element for $t {
            const DESCR: &'static str = $descr;
            fn put(self, out: &mut impl Write) -> io::Result<()> {
                out.write_all(&self.to_le_bytes())
            }
        }
    };
}

element!(u8, "|u1");
element!(u16, "<u2");
element!(u64, "<u8");
element!(i64, "<i8");
element!(f64, "<f8");

impl Element for bool {
    const DESCR: &'static str = "|b1";
    fn put(self, out: &mut impl Write) -> io::Result<()> {
        out.write_all(&[u8::from(self)])
    }
}

/// One array of an archive, filled value by value: a 1-D array, or a 2-D array of rows of
/// `width` values (`(N, width)`).
pub struct Column<T: Element> {
    name: &'static str,
    width: Option<usize>,
    values: u64,
    scratch: BufWriter<Checksummed<File>>,
    _element: std::marker::PhantomData<fn(T)>,
}

impl<T: Element> Column<T> {
    /// An empty array `name` (without `.npy`) of the archive `target`; `width`: `None` for a 1-D
    /// array, `Some(w)` for one of rows of `w` values.
    ///
    /// # Errors
    /// [`StoreError::Io`] when the scratch file cannot be made beside `target`.
    pub fn new(
        target: &Path,
        name: &'static str,
        width: Option<usize>,
    ) -> Result<Column<T>, StoreError> {
        let file = scratch_beside(target)?;
        Ok(Column {
            name,
            width,
            values: 0,
            scratch: BufWriter::with_capacity(COLUMN_BUFFER, Checksummed::new(file)),
            _element: std::marker::PhantomData,
        })
    }

    /// Appends one value.
    ///
    /// # Errors
    /// An I/O error of the scratch file.
    pub fn push(&mut self, value: T) -> io::Result<()> {
        self.values += 1;
        value.put(&mut self.scratch)
    }

    /// The number of values appended.
    pub fn len(&self) -> u64 {
        self.values
    }

    /// Appends values.
    ///
    /// # Errors
    /// An I/O error of the scratch file.
    pub fn extend(&mut self, values: impl IntoIterator<Item = T>) -> io::Result<()> {
        values.into_iter().try_for_each(|v| self.push(v))
    }

    /// The array as an entry of the archive (its `.npy` header and its body).
    ///
    /// # Errors
    /// An I/O error of the scratch file.
    pub fn entry(self) -> io::Result<Entry> {
        let shape = match self.width {
            None => format!("({},)", self.values),
            Some(w) => format!("({}, {w})", self.values / w.max(1) as u64),
        };
        let header = npy_header(T::DESCR, &shape);
        let mut body = self.scratch.into_inner().map_err(|e| e.into_error())?;
        body.file.rewind()?;
        let mut crc = crc32fast::Hasher::new();
        crc.update(&header);
        crc.combine(&body.crc);
        Ok(Entry {
            name: format!("{}.npy", self.name),
            size: header.len() as u64 + body.bytes,
            crc: crc.finalize(),
            header,
            body: body.file,
        })
    }
}

impl Column<u8> {
    /// Appends bytes.
    ///
    /// # Errors
    /// An I/O error of the scratch file.
    pub fn extend_bytes(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.values += bytes.len() as u64;
        self.scratch.write_all(bytes)
    }
}

/// A writer that checksums (CRC-32) and counts what goes through it.
struct Checksummed<W> {
    file: W,
    crc: crc32fast::Hasher,
    bytes: u64,
}

impl<W> Checksummed<W> {
    fn new(file: W) -> Checksummed<W> {
        Checksummed {
            file,
            crc: crc32fast::Hasher::new(),
            bytes: 0,
        }
    }
}

impl<W: Write> Write for Checksummed<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.file.write(buf)?;
        self.crc.update(&buf[..n]);
        self.bytes += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

/// The `.npy` (version 1.0) header of a C-order array of `descr` values of `shape` (Python's
/// tuple syntax), padded with spaces so that the data starts at a multiple of 64 bytes.
fn npy_header(descr: &str, shape: &str) -> Vec<u8> {
    let dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    // Magic (6), version (2), header length (2), the dictionary, at least one space, newline.
    let unpadded = 10 + dict.len() + 1;
    let padded = unpadded.div_ceil(64) * 64;
    let len = padded - 10;
    let mut header = Vec::with_capacity(padded);
    header.extend_from_slice(b"\x93NUMPY\x01\x00");
    // The dictionary of a few arrays' types and shapes is far below 64 KiB.
    header.extend_from_slice(&u16::try_from(len).unwrap_or(u16::MAX).to_le_bytes());
    header.extend_from_slice(dict.as_bytes());
    header.resize(padded - 1, b' ');
    header.push(b'\n');
    header
}

/// One `.npy` file of an archive: its name, size and CRC-32, its header, and the scratch
/// file (rewound) that holds its body.
pub struct Entry {
    name: String,
    size: u64,
    crc: u32,
    header: Vec<u8>,
    body: File,
}

/// Stages the archive of `entries` (in this order) in `staged` as the content of `target`.
///
/// # Errors
/// An I/O error reading a scratch file or writing the staged file.
pub fn stage_npz(
    staged: &mut StagedFiles,
    target: &Path,
    entries: Vec<Entry>,
) -> Result<(), StoreError> {
    staged.add_with(target, |out| write_zip(out, entries, ZIP64_FROM))?;
    Ok(())
}

/// Where an entry went in the archive.
struct Placed {
    name: String,
    size: u64,
    crc: u32,
    offset: u64,
}

impl Placed {
    /// `true` when its size or offset needs ZIP64 records (from `zip64_from` on).
    fn zip64(&self, zip64_from: u64) -> bool {
        self.size >= zip64_from || self.offset >= zip64_from
    }
}

/// Writes `entries` as a zip archive of stored files; sizes and offsets from `zip64_from` on are
/// written in ZIP64 records ([`ZIP64_FROM`] outside tests, which lower it to test them).
fn write_zip(out: &mut impl Write, entries: Vec<Entry>, zip64_from: u64) -> io::Result<()> {
    let mut offset = 0u64;
    let mut placed = Vec::with_capacity(entries.len());
    for entry in entries {
        let at = Placed {
            name: entry.name,
            size: entry.size,
            crc: entry.crc,
            offset,
        };
        let local = local_header(&at, zip64_from);
        out.write_all(&local)?;
        out.write_all(&entry.header)?;
        let copied = io::copy(
            &mut BufReader::with_capacity(COLUMN_BUFFER, entry.body),
            out,
        )?;
        if entry.header.len() as u64 + copied != at.size {
            return Err(io::Error::other(format!(
                "scratch data of {} changed while the archive was written",
                at.name
            )));
        }
        offset += local.len() as u64 + at.size;
        placed.push(at);
    }
    let directory_offset = offset;
    let mut directory = Vec::new();
    for at in &placed {
        central_header(&mut directory, at, zip64_from);
    }
    out.write_all(&directory)?;
    let directory_size = directory.len() as u64;
    let count = placed.len() as u64;
    let zip64 = placed.iter().any(|p| p.zip64(zip64_from))
        || directory_offset >= zip64_from
        || directory_size >= zip64_from
        || count >= 0xFFFF;
    let mut end = Vec::new();
    if zip64 {
        let record_offset = directory_offset + directory_size;
        // ZIP64 end of central directory record (its size field counts what follows it).
        put32(&mut end, 0x0606_4b50);
        put64(&mut end, 44);
        put16(&mut end, VERSION_ZIP64);
        put16(&mut end, VERSION_ZIP64);
        put32(&mut end, 0);
        put32(&mut end, 0);
        put64(&mut end, count);
        put64(&mut end, count);
        put64(&mut end, directory_size);
        put64(&mut end, directory_offset);
        // Its locator: on disk 0, at `record_offset`, one disk in all.
        put32(&mut end, 0x0706_4b50);
        put32(&mut end, 0);
        put64(&mut end, record_offset);
        put32(&mut end, 1);
    }
    // End of central directory record.
    put32(&mut end, 0x0605_4b50);
    put16(&mut end, 0);
    put16(&mut end, 0);
    let count16 = if zip64 { 0xFFFF } else { count as u16 };
    put16(&mut end, count16);
    put16(&mut end, count16);
    put32(&mut end, narrow(directory_size, zip64));
    put32(&mut end, narrow(directory_offset, zip64));
    put16(&mut end, 0);
    out.write_all(&end)
}

/// The local file header of `at`.
fn local_header(at: &Placed, zip64_from: u64) -> Vec<u8> {
    let zip64 = at.zip64(zip64_from);
    let mut h = Vec::with_capacity(30 + at.name.len() + 20);
    put32(&mut h, 0x0403_4b50);
    common_fields(&mut h, at, zip64);
    put16(&mut h, if zip64 { 20 } else { 0 });
    h.extend_from_slice(at.name.as_bytes());
    if zip64 {
        // ZIP64 extra field: original and compressed size.
        put16(&mut h, 0x0001);
        put16(&mut h, 16);
        put64(&mut h, at.size);
        put64(&mut h, at.size);
    }
    h
}

/// Appends the central directory header of `at` to `out`.
fn central_header(out: &mut Vec<u8>, at: &Placed, zip64_from: u64) {
    let zip64 = at.zip64(zip64_from);
    put32(out, 0x0201_4b50);
    // Made by: the version (MS-DOS attributes, none set).
    put16(out, if zip64 { VERSION_ZIP64 } else { VERSION_PLAIN });
    common_fields(out, at, zip64);
    put16(out, if zip64 { 28 } else { 0 });
    // Comment length, disk number, internal and external attributes.
    put16(out, 0);
    put16(out, 0);
    put16(out, 0);
    put32(out, 0);
    put32(out, narrow(at.offset, zip64));
    out.extend_from_slice(at.name.as_bytes());
    if zip64 {
        // ZIP64 extra field: original size, compressed size, local header offset.
        put16(out, 0x0001);
        put16(out, 24);
        put64(out, at.size);
        put64(out, at.size);
        put64(out, at.offset);
    }
}

/// The fields that local and central headers share, from "version needed" to the name length.
fn common_fields(out: &mut Vec<u8>, at: &Placed, zip64: bool) {
    put16(out, if zip64 { VERSION_ZIP64 } else { VERSION_PLAIN });
    // Flags none, method 0 (stored), time 00:00:00, date.
    put16(out, 0);
    put16(out, 0);
    put16(out, 0);
    put16(out, DOS_DATE);
    put32(out, at.crc);
    put32(out, narrow(at.size, zip64));
    put32(out, narrow(at.size, zip64));
    // Entry names are a few ASCII characters.
    put16(out, at.name.len() as u16);
}

/// `value` in a 32-bit field: itself, or `0xFFFF_FFFF` where a ZIP64 record holds it.
fn narrow(value: u64, zip64: bool) -> u32 {
    if zip64 { u32::MAX } else { value as u32 }
}

fn put16(out: &mut Vec<u8>, v: u16) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn put32(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn put64(out: &mut Vec<u8>, v: u64) {
    out.extend_from_slice(&v.to_le_bytes());
}

#[cfg(test)]
mod tests;
