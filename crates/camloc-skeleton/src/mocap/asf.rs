//! CMU ASF (Acclaim skeleton file) reader and the forward kinematics of its bones.

use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;

use super::error::{MocapError, ParseProblem};
use super::read_file;
use super::rotation::{Axis, Rot3, add, y_up_to_z_up};
use super::text::{Lines, Source, decode};
use crate::{Landmark, NUM_LANDMARKS, Pose3};

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

/// The section being read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
enum Section {
    /// Before the first keyword.
    #[default]
    Start,
    Units,
    Root,
    Bonedata,
    Hierarchy,
    /// `:documentation`, `:version`, `:name` and unknown keywords: content skipped.
    Skipped,
}

/// A complete bone block, before the hierarchy is resolved.
#[derive(Debug)]
struct ParsedBone<'a> {
    /// Line of `begin`.
    line: usize,
    name: &'a str,
    /// Unit direction, file frame.
    direction: [f64; 3],
    length: f64,
    axis: ([f64; 3], [Axis; 3]),
    dofs: Vec<Axis>,
}

/// A bone block being read.
#[derive(Debug)]
struct RawBone<'a> {
    /// Line of `begin`.
    line: usize,
    name: Option<&'a str>,
    direction: Option<[f64; 3]>,
    length: Option<f64>,
    axis: ([f64; 3], [Axis; 3]),
    dofs: Vec<Axis>,
}

/// Everything read so far, in file units and angles.
#[derive(Debug, Default)]
struct RawSkeleton<'a> {
    section: Section,
    seen: Vec<&'static str>,
    length_unit: Option<f64>,
    radians_per_angle_unit: Option<f64>,
    order: Option<Vec<RootDof>>,
    root_axis: Option<[Axis; 3]>,
    position: [f64; 3],
    orientation: [f64; 3],
    bones: Vec<ParsedBone<'a>>,
    open_bone: Option<RawBone<'a>>,
    /// `(line, parent, children)` of each `:hierarchy` line.
    hierarchy: Vec<(usize, &'a str, Vec<&'a str>)>,
    /// `None` before `begin`, `Some(true)` inside the block, `Some(false)` after `end`.
    hierarchy_open: Option<bool>,
}

/// Parses a rotation order such as `XYZ` (a permutation of x, y, z, either case).
fn rotation_order(token: &str, line: usize, source: Source<'_>) -> Result<[Axis; 3], MocapError> {
    let err = || source.expected(line, "a rotation order such as XYZ", token);
    let mut axes = [Axis::X; 3];
    let mut letters = token.chars();
    for a in axes.iter_mut() {
        *a = letters.next().and_then(Axis::from_letter).ok_or_else(err)?;
    }
    let distinct = axes[0] != axes[1] && axes[1] != axes[2] && axes[0] != axes[2];
    if letters.next().is_some() || !distinct {
        return Err(err());
    }
    Ok(axes)
}

/// Rotation applying the angles `angles` (about x, y, z, radians) in the sequence `order`.
fn euler(order: [Axis; 3], angles: [f64; 3]) -> Rot3 {
    order.iter().fold(Rot3::IDENTITY, |r, &axis| {
        Rot3::about(axis, angles[axis.index()]).mul(&r)
    })
}

impl<'a> RawSkeleton<'a> {
    fn start_section(
        &mut self,
        keyword: &str,
        line: usize,
        source: Source<'_>,
    ) -> Result<(), MocapError> {
        self.close_checks(line, source)?;
        let (section, name) = match keyword {
            "units" => (Section::Units, ":units"),
            "root" => (Section::Root, ":root"),
            "bonedata" => (Section::Bonedata, ":bonedata"),
            "hierarchy" => (Section::Hierarchy, ":hierarchy"),
            _ => {
                self.section = Section::Skipped;
                return Ok(());
            }
        };
        if self.seen.contains(&name) {
            return Err(source.error(
                line,
                ParseProblem::Duplicate {
                    what: format!("section {name}"),
                },
            ));
        }
        self.seen.push(name);
        self.section = section;
        Ok(())
    }

    /// Checks that the section being left is complete.
    fn close_checks(&self, line: usize, source: Source<'_>) -> Result<(), MocapError> {
        if self.open_bone.is_some() {
            return Err(source.expected(line, "`end` of the bone block", "a new section"));
        }
        if self.hierarchy_open == Some(true) {
            return Err(source.expected(line, "`end` of :hierarchy", "a new section"));
        }
        Ok(())
    }

    /// One non-keyword line: `key` and the rest of its tokens.
    fn line(
        &mut self,
        key: &'a str,
        tokens: &mut impl Iterator<Item = &'a str>,
        line: usize,
        source: Source<'_>,
    ) -> Result<(), MocapError> {
        match self.section {
            Section::Start => Err(source.expected(line, "a :keyword", key)),
            Section::Skipped => Ok(()),
            Section::Units => self.units_line(key, tokens, line, source),
            Section::Root => self.root_line(key, tokens, line, source),
            Section::Bonedata => self.bone_line(key, tokens, line, source),
            Section::Hierarchy => self.hierarchy_line(key, tokens, line, source),
        }
    }

    fn units_line(
        &mut self,
        key: &str,
        tokens: &mut impl Iterator<Item = &'a str>,
        line: usize,
        source: Source<'_>,
    ) -> Result<(), MocapError> {
        match key {
            "length" => {
                let token = source.token(tokens, line, "the length unit")?;
                let length = source.number(token, line, || "`:units length`".to_owned())?;
                if length <= 0.0 {
                    return Err(source.invalid(
                        line,
                        "`:units length`".to_owned(),
                        "must be positive",
                    ));
                }
                self.length_unit = Some(length);
            }
            "angle" => {
                let token = source.token(tokens, line, "the angle unit")?;
                self.radians_per_angle_unit = Some(match token.to_ascii_lowercase().as_str() {
                    "deg" | "degree" | "degrees" => 1f64.to_radians(),
                    "rad" | "radian" | "radians" => 1.0,
                    _ => return Err(source.expected(line, "`deg` or `rad`", token)),
                });
            }
            _ => {}
        }
        Ok(())
    }

    fn root_line(
        &mut self,
        key: &str,
        tokens: &mut impl Iterator<Item = &'a str>,
        line: usize,
        source: Source<'_>,
    ) -> Result<(), MocapError> {
        match key {
            "order" => {
                let mut order = Vec::new();
                for token in tokens {
                    let dof = token
                        .split_at_checked(1)
                        .and_then(|(kind, axis)| {
                            let axis = Axis::from_letter(axis.chars().next()?)
                                .filter(|_| axis.len() == 1)?;
                            match kind {
                                "T" | "t" => Some(RootDof::Translation(axis)),
                                "R" | "r" => Some(RootDof::Rotation(axis)),
                                _ => None,
                            }
                        })
                        .ok_or_else(|| {
                            source.error(
                                line,
                                ParseProblem::Unknown {
                                    what: format!("root channel '{token}'"),
                                },
                            )
                        })?;
                    if order.contains(&dof) {
                        return Err(source.error(
                            line,
                            ParseProblem::Duplicate {
                                what: format!("root channel '{token}'"),
                            },
                        ));
                    }
                    order.push(dof);
                }
                self.order = Some(order);
            }
            "axis" => {
                let token = source.token(tokens, line, "the root axis order")?;
                self.root_axis = Some(rotation_order(token, line, source)?);
            }
            "position" => {
                self.position = source.vector3(tokens, line, || "root position".to_owned())?;
            }
            "orientation" => {
                self.orientation =
                    source.vector3(tokens, line, || "root orientation".to_owned())?;
            }
            _ => {}
        }
        Ok(())
    }

    fn bone_line(
        &mut self,
        key: &'a str,
        tokens: &mut impl Iterator<Item = &'a str>,
        line: usize,
        source: Source<'_>,
    ) -> Result<(), MocapError> {
        if key == "begin" {
            if self.open_bone.is_some() {
                return Err(source.expected(line, "`end` of the bone block", key));
            }
            self.open_bone = Some(RawBone {
                line,
                name: None,
                direction: None,
                length: None,
                axis: ([0.0; 3], [Axis::X, Axis::Y, Axis::Z]),
                dofs: Vec::new(),
            });
            return Ok(());
        }
        let Some(bone) = self.open_bone.as_mut() else {
            return Err(source.expected(line, "`begin` of a bone block", key));
        };
        let label = |bone: &RawBone<'_>| format!("bone '{}'", bone.name.unwrap_or("?"));
        match key {
            "end" => {
                let bone = self.open_bone.take();
                if let Some(bone) = bone {
                    let missing = |field: &str| {
                        source.expected(line, &format!("`{field}` in {}", label(&bone)), "end")
                    };
                    let parsed = ParsedBone {
                        line: bone.line,
                        name: bone.name.ok_or_else(|| missing("name"))?,
                        direction: bone.direction.ok_or_else(|| missing("direction"))?,
                        length: bone.length.ok_or_else(|| missing("length"))?,
                        axis: bone.axis,
                        dofs: bone.dofs,
                    };
                    self.bones.push(parsed);
                }
            }
            "name" => {
                let name = source.token(tokens, line, "a bone name")?;
                if name.eq_ignore_ascii_case("root") {
                    return Err(source.invalid(
                        line,
                        "bone name 'root'".to_owned(),
                        "reserved for the root",
                    ));
                }
                bone.name = Some(name);
            }
            "direction" => {
                let d = source.vector3(tokens, line, || format!("direction of {}", label(bone)))?;
                let norm = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                if norm == 0.0 {
                    return Err(source.invalid(
                        line,
                        format!("direction of {}", label(bone)),
                        "must not be zero",
                    ));
                }
                bone.direction = Some(d.map(|c| c / norm));
            }
            "length" => {
                let token = source.token(tokens, line, "the bone length")?;
                let length = source.number(token, line, || format!("length of {}", label(bone)))?;
                if length < 0.0 {
                    return Err(source.invalid(
                        line,
                        format!("length of {}", label(bone)),
                        "must not be negative",
                    ));
                }
                bone.length = Some(length);
            }
            "axis" => {
                let angles = source.vector3(tokens, line, || format!("axis of {}", label(bone)))?;
                let order = match tokens.next() {
                    Some(token) => rotation_order(token, line, source)?,
                    None => [Axis::X, Axis::Y, Axis::Z],
                };
                bone.axis = (angles, order);
            }
            "dof" => {
                for token in tokens {
                    let axis = match token.to_ascii_lowercase().as_str() {
                        "rx" => Axis::X,
                        "ry" => Axis::Y,
                        "rz" => Axis::Z,
                        "tx" | "ty" | "tz" | "l" => {
                            return Err(source.invalid(
                                line,
                                format!("dof '{token}' of {}", label(bone)),
                                "only rotation dofs (rx ry rz) are supported",
                            ));
                        }
                        _ => {
                            return Err(source.error(
                                line,
                                ParseProblem::Unknown {
                                    what: format!("dof '{token}' of {}", label(bone)),
                                },
                            ));
                        }
                    };
                    if bone.dofs.contains(&axis) {
                        return Err(source.error(
                            line,
                            ParseProblem::Duplicate {
                                what: format!("dof '{token}' of {}", label(bone)),
                            },
                        ));
                    }
                    bone.dofs.push(axis);
                }
            }
            _ => {}
        }
        Ok(())
    }

    fn hierarchy_line(
        &mut self,
        key: &'a str,
        tokens: &mut impl Iterator<Item = &'a str>,
        line: usize,
        source: Source<'_>,
    ) -> Result<(), MocapError> {
        match (self.hierarchy_open, key) {
            (None, "begin") => self.hierarchy_open = Some(true),
            (None, _) => return Err(source.expected(line, "`begin`", key)),
            (Some(true), "end") => self.hierarchy_open = Some(false),
            (Some(true), parent) => {
                let children: Vec<&str> = tokens.collect();
                if children.is_empty() {
                    return Err(source.error(
                        line,
                        ParseProblem::Missing {
                            expected: format!("the child bones of '{parent}'"),
                        },
                    ));
                }
                self.hierarchy.push((line, parent, children));
            }
            (Some(false), _) => {
                return Err(source.expected(line, "a :keyword after :hierarchy", key));
            }
        }
        Ok(())
    }

    /// Resolves the hierarchy and builds the skeleton.
    fn finish(self, last_line: usize, source: Source<'_>) -> Result<AsfSkeleton, MocapError> {
        self.close_checks(last_line, source)?;
        let order = self.order.ok_or_else(|| {
            source.unexpected_end(last_line, "a :root section with an `order` line")
        })?;
        if self.hierarchy_open.is_none() {
            return Err(source.unexpected_end(last_line, "a :hierarchy section"));
        }
        let topo = order_bones(&self.bones, &self.hierarchy, source)?;
        let radians = self.radians_per_angle_unit.unwrap_or(1f64.to_radians());
        let root_axis = euler(
            self.root_axis.unwrap_or([Axis::X, Axis::Y, Axis::Z]),
            self.orientation.map(|a| a * radians),
        );
        let mut value_count = order.len();
        let mut bones = Vec::with_capacity(topo.len());
        for &(raw_index, parent) in &topo {
            let Some(raw) = self.bones.get(raw_index) else {
                continue;
            };
            let (angles, axis_order) = raw.axis;
            let axis = euler(axis_order, angles.map(|a| a * radians));
            bones.push(Bone {
                name: raw.name.to_owned(),
                parent,
                vector: raw.direction.map(|c| c * raw.length),
                axis,
                axis_inverse: axis.transpose(),
                dofs: raw.dofs.clone(),
                first_value: value_count,
            });
            value_count += raw.dofs.len();
        }
        let mut landmarks = [None; NUM_LANDMARKS];
        for ((slot, bone_name), landmark) in
            landmarks.iter_mut().zip(LANDMARK_BONES).zip(Landmark::ALL)
        {
            if let Some(name) = bone_name {
                let found = bones.iter().position(|b| b.name.eq_ignore_ascii_case(name));
                *slot = Some(found.ok_or_else(|| MocapError::MissingLandmark {
                    file: source.name.to_owned(),
                    landmark,
                    expected: format!("bone '{name}'"),
                })?);
            }
        }
        Ok(AsfSkeleton {
            source: source.name.to_owned(),
            metres_per_unit: 0.0254 / self.length_unit.unwrap_or(1.0),
            radians_per_angle_unit: radians,
            root: Root {
                order,
                position: self.position,
                axis: root_axis,
                axis_inverse: root_axis.transpose(),
            },
            bones,
            landmarks,
            value_count,
        })
    }
}

/// The bones in breadth-first order from the root (parents first), each with the position of
/// its parent in that order (`None`: the root), as `:hierarchy` connects them.
fn order_bones(
    bones: &[ParsedBone<'_>],
    hierarchy: &[(usize, &str, Vec<&str>)],
    source: Source<'_>,
) -> Result<Vec<(usize, Option<usize>)>, MocapError> {
    let mut index: HashMap<&str, usize> = HashMap::with_capacity(bones.len());
    for (i, bone) in bones.iter().enumerate() {
        if index.insert(bone.name, i).is_some() {
            return Err(source.error(
                bone.line,
                ParseProblem::Duplicate {
                    what: format!("bone '{}'", bone.name),
                },
            ));
        }
    }
    // children[0] lists the root's children, children[i + 1] those of bone i.
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); bones.len() + 1];
    let mut has_parent = vec![false; bones.len()];
    for (line, parent, kids) in hierarchy {
        let unknown = |name: &str| {
            source.error(
                *line,
                ParseProblem::Unknown {
                    what: format!("bone '{name}' in :hierarchy"),
                },
            )
        };
        let p = if parent.eq_ignore_ascii_case("root") {
            0
        } else {
            index.get(parent).ok_or_else(|| unknown(parent))? + 1
        };
        for kid in kids {
            let k = *index.get(kid).ok_or_else(|| unknown(kid))?;
            let taken = has_parent.get_mut(k).map(|h| std::mem::replace(h, true));
            if taken == Some(true) {
                return Err(source.error(
                    *line,
                    ParseProblem::Duplicate {
                        what: format!("bone '{kid}' as a child in :hierarchy"),
                    },
                ));
            }
            if let Some(list) = children.get_mut(p) {
                list.push(k);
            }
        }
    }
    // Each bone has at most one parent, so each is queued at most once.
    let mut order: Vec<(usize, Option<usize>)> = children
        .first()
        .map(|c| c.iter().map(|&k| (k, None)).collect())
        .unwrap_or_default();
    let mut head = 0;
    while let Some(&(bone, _)) = order.get(head) {
        if let Some(kids) = children.get(bone + 1) {
            order.extend(kids.iter().map(|&k| (k, Some(head))));
        }
        head += 1;
    }
    if order.len() < bones.len() {
        let mut attached = vec![false; bones.len()];
        for &(bone, _) in &order {
            if let Some(a) = attached.get_mut(bone) {
                *a = true;
            }
        }
        if let Some((bone, _)) = bones.iter().zip(&attached).find(|(_, a)| !**a) {
            return Err(source.invalid(
                bone.line,
                format!("bone '{}'", bone.name),
                "not attached to the root by :hierarchy",
            ));
        }
    }
    Ok(order)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_orders_are_permutations() {
        let s = Source { name: "t.asf" };
        assert_eq!(
            rotation_order("XYZ", 1, s).unwrap(),
            [Axis::X, Axis::Y, Axis::Z]
        );
        assert_eq!(
            rotation_order("zxy", 1, s).unwrap(),
            [Axis::Z, Axis::X, Axis::Y]
        );
        for bad in ["XXY", "XY", "XYZW", "ABC", ""] {
            assert!(rotation_order(bad, 1, s).is_err(), "{bad}");
        }
    }

    #[test]
    fn euler_applies_the_first_axis_first() {
        let q = 90f64.to_radians();
        // XYZ with x = y = 90 deg: x first takes +y to +z, then y takes +z to +x.
        let r = euler([Axis::X, Axis::Y, Axis::Z], [q, q, 0.0]);
        let v = r.apply([0.0, 1.0, 0.0]);
        assert!((v[0] - 1.0).abs() < 1e-12 && v[1].abs() < 1e-12 && v[2].abs() < 1e-12);
    }
}
