//! CMU ASF (Acclaim skeleton file) reader and the forward kinematics of its bones.

use std::ops::Range;
use std::path::Path;

use super::error::MocapError;
use super::read_file;
use super::rotation::{Axis, Rot3, add, y_up_to_z_up};
use super::text::{Lines, Source, decode};
use camloc_skeleton::{NUM_LANDMARKS, Pose3};

mod parse;

use parse::RawSkeleton;

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

/// A skeleton read from an ASF file: bones, their rest geometry, motion channels and units.
#[derive(Clone, Debug)]
pub struct AsfSkeleton {
    source: String,
    metres_per_unit: f64,
    radians_per_angle_unit: f64,
    root: Root,
    /// Bones, parents before children.
    bones: Vec<Bone>,
    /// The bone whose end point is each landmark; `None` for the pelvis (the root position).
    landmarks: [Option<usize>; NUM_LANDMARKS],
    /// Number of motion values per frame (root and every bone).
    value_count: usize,
}

/// The root: AMC value order, pre-set position and orientation frame.
#[derive(Clone, Debug)]
struct Root {
    order: Vec<RootDof>,
    position: [f64; 3],
    axis: Rot3,
    axis_inverse: Rot3,
}

/// One root motion value: a translation or a rotation along an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RootDof {
    Translation(Axis),
    Rotation(Axis),
}

/// A bone in its rest pose, with its motion channels.
#[derive(Clone, Debug)]
struct Bone {
    name: String,
    /// Parent bone (an index into `AsfSkeleton::bones`), `None` for a child of the root.
    parent: Option<usize>,
    /// `direction * length`, file units.
    vector: [f64; 3],
    axis: Rot3,
    axis_inverse: Rot3,
    dofs: Vec<Axis>,
    /// Index of this bone's first value in a frame's value vector.
    first_value: usize,
}

impl AsfSkeleton {
    /// The file name or path the skeleton was read from.
    pub fn source_name(&self) -> &str {
        &self.source
    }

    /// Metres per length unit of the file (`0.0254 / L` for `:units length L`).
    pub fn metres_per_unit(&self) -> f64 {
        self.metres_per_unit
    }

    /// Bone names, parents before children.
    pub fn bone_names(&self) -> impl Iterator<Item = &str> {
        self.bones.iter().map(|b| b.name.as_str())
    }

    /// The landmarks with every motion value zero (root at `position`), in metres, z up.
    pub fn rest_pose(&self) -> Pose3 {
        self.pose(
            &vec![0.0; self.value_count],
            self.radians_per_angle_unit,
            &mut Vec::new(),
        )
    }

    /// Radians per angle unit declared by `:units angle`.
    pub(crate) fn radians_per_angle_unit(&self) -> f64 {
        self.radians_per_angle_unit
    }

    /// Number of motion values per frame.
    pub(crate) fn value_count(&self) -> usize {
        self.value_count
    }

    /// The AMC line names (`root` first, then the bones) and the range of each line's values
    /// in a frame's value vector.
    pub(crate) fn motion_slots(&self) -> impl Iterator<Item = (&str, Range<usize>)> {
        let root = std::iter::once(("root", 0..self.root.order.len()));
        root.chain(
            self.bones
                .iter()
                .map(|b| (b.name.as_str(), b.first_value..b.first_value + b.dofs.len())),
        )
    }

    /// Forward kinematics of one frame: `values` laid out as [`Self::motion_slots`], angles in
    /// units of `radians_per_unit`; `scratch` is reused between calls.
    pub(crate) fn pose(
        &self,
        values: &[f64],
        radians_per_unit: f64,
        scratch: &mut Vec<(Rot3, [f64; 3])>,
    ) -> Pose3 {
        let root_values = values.get(..self.root.order.len()).unwrap_or_default();
        let mut root_position = self.root.position;
        let mut motion = Rot3::IDENTITY;
        for (dof, &v) in self.root.order.iter().zip(root_values) {
            match *dof {
                RootDof::Translation(axis) => root_position[axis.index()] += v,
                RootDof::Rotation(axis) => {
                    motion = Rot3::about(axis, v * radians_per_unit).mul(&motion);
                }
            }
        }
        let root_rotation = self.root.axis.mul(&motion).mul(&self.root.axis_inverse);
        scratch.clear();
        for bone in &self.bones {
            let (parent_rotation, start) = match bone.parent {
                Some(p) => scratch
                    .get(p)
                    .copied()
                    .unwrap_or((Rot3::IDENTITY, [0.0; 3])),
                None => (root_rotation, root_position),
            };
            let bone_values = values.get(bone.first_value..).unwrap_or_default();
            let rotation = if bone.dofs.is_empty() {
                parent_rotation
            } else {
                let motion = bone
                    .dofs
                    .iter()
                    .zip(bone_values)
                    .fold(Rot3::IDENTITY, |m, (&axis, &v)| {
                        Rot3::about(axis, v * radians_per_unit).mul(&m)
                    });
                parent_rotation
                    .mul(&bone.axis)
                    .mul(&motion)
                    .mul(&bone.axis_inverse)
            };
            scratch.push((rotation, add(start, rotation.apply(bone.vector))));
        }
        Pose3::new(self.landmarks.map(|bone| {
            let point = bone
                .and_then(|b| scratch.get(b))
                .map_or(root_position, |&(_, end)| end);
            y_up_to_z_up(point, self.metres_per_unit)
        }))
    }
}

/// The bone whose end point is each landmark (`None`: the root position), landmark order.
const LANDMARK_BONES: [Option<&str>; NUM_LANDMARKS] = [
    None,
    Some("lhipjoint"),
    Some("lfemur"),
    Some("ltibia"),
    Some("rhipjoint"),
    Some("rfemur"),
    Some("rtibia"),
    Some("thorax"),
    Some("upperneck"),
    Some("lclavicle"),
    Some("lhumerus"),
    Some("lradius"),
    Some("rclavicle"),
    Some("rhumerus"),
    Some("rradius"),
];
