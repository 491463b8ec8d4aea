//! NumPy `.npy` keypoint arrays, read pose by pose (memory does not grow with N), and writers
//! for camloc's own arrays: (N, 15, 2) 2D landmarks and (N, 15, 3) 3D poses.
//!
//! The array is read and written by the `npyz` crate. Before `npyz` sees a header, this module
//! checks its size ([`NPY_MAX_HEADER_BYTES`]), its nesting, and that it is a plain
//! `{'descr': str, 'fortran_order': bool, 'shape': (ints)}` dict whose shape has no overflowing
//! product, so that no file can make it allocate without bound or overflow.

use std::io::{self, Read, Write};

use camloc_skeleton::{NUM_LANDMARKS, PartialPose2, Pose3};
use npyz::WriterBuilder;

use crate::ReadOptions;
use crate::array_pose::{ArrayPoseError, pose_from_array};
use crate::error::{KeypointError, Location, PosePlace};
use crate::format::NPY_MAGIC;
use crate::layout::{Layout, resolve_layout};
use crate::record::KeypointRecord;

/// The longest `.npy` header accepted, in bytes: NumPy's own default limit (`max_header_size`).
pub const NPY_MAX_HEADER_BYTES: usize = 10_000;

/// The deepest bracket nesting accepted in a `.npy` header (a plain header has 2).
const MAX_HEADER_DEPTH: usize = 8;

/// The input after its header: the header bytes read ahead, then the rest, buffered.
type Buffered<R> = io::BufReader<io::Chain<io::Cursor<Vec<u8>>, R>>;

/// Bytes read from the input at a time.
const READ_BUFFER: usize = 1 << 16;

/// The numbers of an array after its header, `float64` or `float32` in the file's byte order,
/// read a pose at a time: one copy of the pose's bytes, then decoded as `npyz` decodes them
/// (`<` little-endian, `>` big-endian; `npyz` refuses `|` for floats, the machine's order here).
struct Values<R: Read> {
    reader: R,
    /// 8 for `float64`, 4 for `float32`.
    size: usize,
    order: npyz::Endianness,
    /// The bytes of the last pose read.
    bytes: Vec<u8>,
}

impl<R: Read> Values<R> {
    /// The numbers of `npy`'s array, `None` when its dtype is neither `float64` nor `float32`
    /// (any byte order), the dtypes `npyz` reads as `f64` or `f32`.
    fn new(npy: npyz::NpyFile<R>) -> Option<Values<R>> {
        let dtype = npy.dtype();
        let size = if <f64 as npyz::Deserialize>::reader(&dtype).is_ok() {
            8
        } else if <f32 as npyz::Deserialize>::reader(&dtype).is_ok() {
            4
        } else {
            return None;
        };
        let npyz::DType::Plain(type_str) = dtype else {
            return None;
        };
        Some(Values {
            reader: npy.into_inner(),
            size,
            order: type_str.endianness(),
            bytes: Vec::new(),
        })
    }

    /// Reads the next `count` numbers into `row` (replacing what it held).
    fn read_into(&mut self, count: usize, row: &mut Vec<f64>) -> io::Result<()> {
        self.bytes.resize(count * self.size, 0);
        self.reader.read_exact(&mut self.bytes)?;
        let order = self.order;
        row.clear();
        if self.size == 8 {
            row.extend(self.bytes.chunks_exact(8).map(|b| {
                let mut bytes = [0; 8];
                bytes.copy_from_slice(b);
                match order {
                    npyz::Endianness::Little => f64::from_le_bytes(bytes),
                    npyz::Endianness::Big => f64::from_be_bytes(bytes),
                    npyz::Endianness::Irrelevant => f64::from_ne_bytes(bytes),
                }
            }));
        } else {
            row.extend(self.bytes.chunks_exact(4).map(|b| {
                let mut bytes = [0; 4];
                bytes.copy_from_slice(b);
                f64::from(match order {
                    npyz::Endianness::Little => f32::from_le_bytes(bytes),
                    npyz::Endianness::Big => f32::from_be_bytes(bytes),
                    npyz::Endianness::Irrelevant => f32::from_ne_bytes(bytes),
                })
            }));
        }
        Ok(())
    }
}

/// A `.npy` keypoint array of shape (N, J, 2) or (N, J, 3) (`x, y` or `x, y, score`, `float64`
/// or `float32`, C order), read one pose at a time as [`KeypointRecord`]s.
///
/// Each pose is mapped by its [`Layout`] ([`pose_from_array`]): both coordinates NaN mark a
/// missing joint, scores must lie in [0, 1] and below [`ReadOptions::min_score`] mark it missing.
/// Record ids are the row numbers (`"0"`, `"1"`, ...), which are also the records' `frame`.
/// Iteration stops after the first error, but for a pose whose joints contradict its layout
/// ([`KeypointError::LayoutMismatch`]) or a row with an infinity, a NaN score, one NaN
/// coordinate or a score outside [0, 1] ([`KeypointError::BadRow`]): those are that pose's
/// error (a score outside [0, 1] had ended the array, and a detector's one stray score lost
/// every frame of a `--sequence` run; a 3D pose array read as keypoints now fails row by
/// row, each with the hint).
pub struct NpyPoses<R: Read> {
    file: String,
    /// Buffered here (whatever `R` is) so that reading one pose is a copy from the buffer.
    values: Option<Values<Buffered<R>>>,
    count: u64,
    channels: usize,
    layout: Layout,
    options: ReadOptions,
    next: u64,
    row: Vec<f64>,
}

impl<R: Read> NpyPoses<R> {
    /// Reads the header from `reader`. `file` names the input in records and errors; `size`, the
    /// input's length in bytes when known (a regular file), lets a truncated file or one with
    /// bytes after the array be refused at once; without it (a pipe), a truncated array is
    /// reported at the pose where the data end, and bytes after the last pose are not read.
    /// The layout is [`ReadOptions::layout`], or the one layout with J joints (J = 17 needs it
    /// named: COCO-17 or Human3.6M).
    pub fn new(
        mut reader: R,
        file: &str,
        size: Option<u64>,
        options: &ReadOptions,
    ) -> Result<NpyPoses<R>, KeypointError> {
        let problem = |problem: String| KeypointError::Npy {
            file: file.to_owned(),
            problem,
        };
        let (head, head_len) = read_head(&mut reader).map_err(problem)?;
        let buffered =
            io::BufReader::with_capacity(READ_BUFFER, io::Cursor::new(head).chain(reader));
        let npy = npyz::NpyFile::new(buffered)
            .map_err(|e| problem(format!("not a readable .npy header: {e}")))?;
        let shape = npy.shape().to_vec();
        if npy.order() != npyz::Order::C {
            return Err(problem(
                "the array is in Fortran order; save it in C order (np.ascontiguousarray)".into(),
            ));
        }
        let dtype = crate::error::clip(npy.dtype().descr().trim_matches('\''));
        let Some(values) = Values::new(npy) else {
            return Err(problem(format!("dtype {dtype} is not float64 or float32")));
        };
        let item_bytes = values.size as u64;
        let (count, joints, channels) = match shape[..] {
            [n, j, c @ (2 | 3)] => (n, j, c as usize),
            _ => {
                // MediaPipe's landmarks as arrays are (x, y, z, visibility).
                let hint = match shape[..] {
                    [_, 33, 4] => {
                        ": MediaPipe's (x, y, z, visibility)? save x, y and visibility \
                                   (array[..., [0, 1, 3]])"
                    }
                    _ => "",
                };
                return Err(problem(format!(
                    "shape {} is not (N, J, 2) or (N, J, 3){hint}",
                    shape_text(&shape)
                )));
            }
        };
        let layout = usize::try_from(joints)
            .map_err(|_| "no layout has that many".to_owned())
            .and_then(|j| resolve_layout(options.layout, j, None))
            .map_err(|what| KeypointError::JointCount {
                file: file.to_owned(),
                at: Location::Array(Box::new([])),
                found: joints,
                what,
            })?;
        if let Some(size) = size {
            let data = joints
                .checked_mul(channels as u64 * item_bytes)
                .and_then(|pose| count.checked_mul(pose))
                .and_then(|d| d.checked_add(head_len));
            if data != Some(size) {
                return Err(problem(format!(
                    "the file has {size} bytes, but a {dtype} array of shape {} needs {}{}",
                    shape_text(&shape),
                    data.map_or_else(|| "more".to_owned(), |d| d.to_string()),
                    if data.is_some_and(|d| d > size) {
                        " (truncated?)"
                    } else {
                        ""
                    }
                )));
            }
        }
        Ok(NpyPoses {
            file: file.to_owned(),
            values: Some(values),
            count,
            channels,
            layout,
            options: *options,
            next: 0,
            row: Vec::with_capacity(layout.joint_count() * channels),
        })
    }

    /// N, the number of poses in the array.
    pub fn len(&self) -> u64 {
        self.count
    }

    /// `true` when the array holds no pose.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The layout the poses are read in.
    pub fn layout(&self) -> Layout {
        self.layout
    }

    /// C: 2 for `x, y`, 3 for `x, y, score`.
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// The next pose, or `None` after the last.
    fn read_next(&mut self) -> Option<Result<KeypointRecord, KeypointError>> {
        let n = self.next;
        let values = self.values.as_mut()?;
        let problem = |problem: String| KeypointError::Npy {
            file: self.file.clone(),
            problem,
        };
        if n == self.count {
            return None;
        }
        if let Err(e) = values.read_into(self.layout.joint_count() * self.channels, &mut self.row) {
            let what = if e.kind() == io::ErrorKind::UnexpectedEof {
                format!(
                    "the data end inside pose {n} of {} (truncated?)",
                    self.count
                )
            } else {
                format!("cannot read: {e}")
            };
            return Some(Err(problem(format!("[{n}]: {what}"))));
        }
        self.next += 1;
        let mapped = pose_from_array(self.layout, &self.row, self.channels, &self.options)
            .map_err(|e| pose_error(&self.file, n, e));
        Some(mapped.map(|mapped| {
            let place = row_place(&self.file, n);
            KeypointRecord {
                id: place.id,
                pose: mapped.pose,
                derived: mapped.derived,
                source: place.source,
                frame: place.frame,
                person: place.person,
                person_is_position: false,
            }
        }))
    }
}

impl<R: Read> Iterator for NpyPoses<R> {
    type Item = Result<KeypointRecord, KeypointError>;

    fn next(&mut self) -> Option<Self::Item> {
        let item = self.read_next();
        // A pose whose joints contradict its layout is that pose's problem (its row was read
        // whole); any other error ends the array.
        if matches!(item, Some(Err(ref e)) if !e.is_pose_error()) {
            self.values = None;
        }
        item
    }
}

/// A pose error as a [`KeypointError`] naming the file and the element; a value no pose holds
/// is that row's own ([`KeypointError::BadRow`]).
fn pose_error(file: &str, pose: u64, error: ArrayPoseError) -> KeypointError {
    if matches!(
        error,
        ArrayPoseError::NonFinite { .. }
            | ArrayPoseError::HalfMissing { .. }
            | ArrayPoseError::ScoreOutOfRange { .. }
    ) {
        return KeypointError::BadRow {
            why: error.to_string(),
            place: Box::new(row_place(file, pose)),
            error: Box::new(element_error(file, pose, error)),
        };
    }
    element_error(file, pose, error)
}

/// [`pose_error`]'s error naming the file and the element.
fn element_error(file: &str, pose: u64, error: ArrayPoseError) -> KeypointError {
    let file = file.to_owned();
    match error {
        ArrayPoseError::NonFinite {
            joint,
            channel,
            value,
        } => KeypointError::NonFinite {
            file,
            at: Location::Array(Box::new([pose, joint as u64, channel as u64])),
            field: if channel == 2 { "score" } else { "coordinate" },
            text: value.to_string(),
        },
        ArrayPoseError::HalfMissing { joint } => KeypointError::HalfMissing {
            file,
            at: Location::Array(Box::new([pose, joint as u64])),
        },
        ArrayPoseError::ScoreOutOfRange {
            joint,
            score,
            separate,
        } => KeypointError::ScoreOutOfRange {
            file,
            at: Location::Array(Box::new([pose, joint as u64, 2])),
            what: "score",
            score,
            hint: crate::array_pose::score_hint(score, separate),
        },
        mismatch @ ArrayPoseError::LayoutMismatch { .. } => KeypointError::LayoutMismatch {
            place: Box::new(row_place(&file, pose)),
            file,
            at: Location::Array(Box::new([pose])),
            source: mismatch,
        },
        shape @ ArrayPoseError::Shape { .. } => KeypointError::Npy {
            file,
            problem: format!("[{pose}]: {shape}"),
        },
    }
}

/// The place of row `n` of the array `file`: its number is its id and its frame.
fn row_place(file: &str, n: u64) -> PosePlace {
    PosePlace {
        id: n.to_string(),
        // As `Location::Array([n])` displays, without its allocations.
        source: format!("{file}: [{n}]"),
        frame: Some(n),
        person: None,
    }
}

/// `(4, 15, 2)`.
fn shape_text(shape: &[u64]) -> String {
    let dims: Vec<String> = shape.iter().map(u64::to_string).collect();
    crate::error::clip(&format!("({})", dims.join(", ")))
}

/// Reads the magic, version, header length and header, checks them (see the module
/// documentation) and returns these bytes for `npyz` to parse again.
fn read_head(reader: &mut impl Read) -> Result<(Vec<u8>, u64), String> {
    let eof = |e: io::Error| match e.kind() {
        io::ErrorKind::UnexpectedEof => "the file ends inside the .npy header".to_owned(),
        _ => format!("cannot read: {e}"),
    };
    let mut head = vec![0u8; 8];
    reader.read_exact(&mut head).map_err(eof)?;
    if !head.starts_with(NPY_MAGIC) {
        return Err("not a .npy file (no \\x93NUMPY magic)".into());
    }
    let len_bytes = match (head[6], head[7]) {
        (1, 0) => 2,
        (2 | 3, 0) => 4,
        (major, minor) => return Err(format!("unsupported .npy version {major}.{minor}")),
    };
    let mut len = [0u8; 4];
    reader.read_exact(&mut len[..len_bytes]).map_err(eof)?;
    head.extend_from_slice(&len[..len_bytes]);
    let len = u32::from_le_bytes(len) as usize;
    if len > NPY_MAX_HEADER_BYTES {
        return Err(format!(
            "the header claims {len} bytes, more than {NPY_MAX_HEADER_BYTES}"
        ));
    }
    let start = head.len();
    head.resize(start + len, 0);
    reader.read_exact(&mut head[start..]).map_err(eof)?;
    let descr = check_header(&head[start..])?;
    let read = head.len() as u64;
    // NumPy reads a descr without a byte order, or with `=` or `|`, in this machine's; the
    // header reader only takes `<` and `>`.
    let native = if cfg!(target_endian = "little") {
        '<'
    } else {
        '>'
    };
    let Some(explicit) = ["f8", "f4"]
        .into_iter()
        .find(|t| descr == *t || descr.strip_prefix(['=', '|']) == Some(*t))
        .map(|t| format!("{native}{t}"))
    else {
        return Ok((head, read));
    };
    let text = String::from_utf8_lossy(&head[start..]).into_owned();
    let quoted = ['\'', '"']
        .into_iter()
        .map(|q| format!("{q}{descr}{q}"))
        .find(|quoted| text.contains(quoted.as_str()));
    let text = match quoted {
        Some(quoted) => text.replacen(&quoted, &format!("'{explicit}'"), 1),
        None => text,
    };
    if len_bytes == 2 && text.len() > usize::from(u16::MAX) {
        return Err("the header is too long for a version 1.0 .npy file".into());
    }
    head.truncate(start - len_bytes);
    head.extend_from_slice(&(text.len() as u32).to_le_bytes()[..len_bytes]);
    head.extend_from_slice(text.as_bytes());
    Ok((head, read))
}

/// Checks the header dict: plain, shallow, and a shape whose element count fits a `u64`;
/// returns its descr.
fn check_header(text: &[u8]) -> Result<String, String> {
    let text = std::str::from_utf8(text).map_err(|_| "the header is not text".to_owned())?;
    let mut depth = 0usize;
    for c in text.chars() {
        match c {
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => depth = depth.saturating_sub(1),
            _ => {}
        }
        if depth > MAX_HEADER_DEPTH {
            return Err("the header is nested too deeply".into());
        }
    }
    let bad = || "the header is not a dict of 'descr', 'fortran_order' and 'shape'".to_owned();
    let value: py_literal::Value = text.trim_end().parse().map_err(|_| bad())?;
    let dict = value.as_dict().ok_or_else(bad)?;
    let get = |key: &str| {
        dict.iter()
            .find(|(k, _)| k.as_string().is_some_and(|k| k == key))
            .map(|(_, v)| v)
    };
    let known = |k: &py_literal::Value| {
        k.as_string()
            .is_some_and(|k| ["descr", "fortran_order", "shape"].contains(&k.as_str()))
    };
    if dict.len() != 3 || !dict.iter().all(|(k, _)| known(k)) {
        return Err(format!("{} (and no other key)", bad()));
    }
    let descr = get("descr").and_then(py_literal::Value::as_string);
    let (Some(descr), Some(py_literal::Value::Boolean(_))) = (descr, get("fortran_order")) else {
        return Err(format!("{} (with a plain dtype string)", bad()));
    };
    let dims = get("shape")
        .and_then(py_literal::Value::as_tuple)
        .ok_or_else(bad)?;
    dims.iter()
        .try_fold(1u64, |product, dim| {
            let dim: u64 = dim.as_integer()?.to_string().parse().ok()?;
            product.checked_mul(dim)
        })
        .map(|_| descr.clone())
        .ok_or_else(|| {
            "the header's shape is not a tuple of sizes with a product below 2^64".to_owned()
        })
}

/// A pose that [`NpyPoseWriter`] can write as one row of a (N, 15, C) `float64` array.
pub trait NpyPose {
    /// C, the numbers per landmark.
    const CHANNELS: usize;
    /// Calls `push` with the pose's 15 × C numbers, landmark by landmark.
    fn values(&self, push: impl FnMut(f64));
}

/// 2D landmarks in the `camloc15` layout: `x, y` (C = 2), NaN, NaN for a missing landmark.
impl NpyPose for PartialPose2 {
    const CHANNELS: usize = 2;
    fn values(&self, mut push: impl FnMut(f64)) {
        for point in &self.points {
            let [x, y] = point.unwrap_or([f64::NAN; 2]);
            push(x);
            push(y);
        }
    }
}

/// 3D landmarks (C = 3), in the pose's own units and frame (metres for reconstructions).
impl NpyPose for Pose3 {
    const CHANNELS: usize = 3;
    fn values(&self, mut push: impl FnMut(f64)) {
        self.points.iter().flatten().for_each(|&v| push(v));
    }
}

/// Writes poses as a little-endian `float64` `.npy` array of shape (N, 15, C), N declared up
/// front, one pose at a time (memory does not grow with N). [`NpyPoseWriter::finish`] fails
/// when fewer or more than N poses were written.
pub struct NpyPoseWriter<W: Write, P: NpyPose> {
    inner: npyz::NpyWriter<f64, W>,
    _pose: std::marker::PhantomData<fn(&P)>,
}

impl<W: Write, P: NpyPose> NpyPoseWriter<W, P> {
    /// Writes the header of an array of `count` poses.
    pub fn new(writer: W, count: u64) -> io::Result<Self> {
        let inner = npyz::WriteOptions::new()
            .default_dtype()
            .shape(&[count, NUM_LANDMARKS as u64, P::CHANNELS as u64])
            .writer(writer)
            .begin_nd()?;
        Ok(NpyPoseWriter {
            inner,
            _pose: std::marker::PhantomData,
        })
    }

    /// Writes one pose.
    pub fn push(&mut self, pose: &P) -> io::Result<()> {
        let mut result = Ok(());
        pose.values(|v| {
            if result.is_ok() {
                result = self.inner.push(&v);
            }
        });
        result
    }

    /// Checks that N poses were written and flushes.
    pub fn finish(self) -> io::Result<()> {
        self.inner.finish()
    }
}

/// Writes `poses` as one `.npy` array (N, 15, C); see [`NpyPoseWriter`].
pub fn write_npy<W: Write, P: NpyPose>(writer: W, poses: &[P]) -> io::Result<()> {
    let mut out = NpyPoseWriter::<W, P>::new(writer, poses.len() as u64)?;
    for pose in poses {
        out.push(pose)?;
    }
    out.finish()
}

/// Reads an (N, 15, 3) `camloc15` array of 3D poses, as written by [`write_npy`] for
/// [`Pose3`]; every value must be finite. `file` names the input in errors.
pub fn read_npy_poses3(reader: impl Read, file: &str) -> Result<Vec<Pose3>, KeypointError> {
    let options = ReadOptions {
        layout: Some(Layout::Camloc15),
        ..ReadOptions::default()
    };
    let mut poses = NpyPoses::new(reader, file, None, &options)?;
    let problem = |problem: String| KeypointError::Npy {
        file: file.to_owned(),
        problem,
    };
    if poses.channels != 3 {
        return Err(problem("3D poses need shape (N, 15, 3)".to_owned()));
    }
    let Some(mut values) = poses.values.take() else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    let mut row = Vec::with_capacity(NUM_LANDMARKS * 3);
    for n in 0..poses.count {
        values
            .read_into(NUM_LANDMARKS * 3, &mut row)
            .map_err(|e| problem(format!("[{n}]: cannot read: {e}")))?;
        let mut pose = Pose3::new([[0.0; 3]; NUM_LANDMARKS]);
        for (k, (v, &read)) in pose.points.iter_mut().flatten().zip(&row).enumerate() {
            if !read.is_finite() {
                return Err(KeypointError::NonFinite {
                    file: file.to_owned(),
                    at: Location::Array(Box::new([n, k as u64 / 3, k as u64 % 3])),
                    field: "coordinate",
                    text: read.to_string(),
                });
            }
            *v = read;
        }
        out.push(pose);
    }
    Ok(out)
}
