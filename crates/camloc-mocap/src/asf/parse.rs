//! The ASF text parser: sections, bone blocks and the hierarchy, read into a [`RawSkeleton`]
//! and resolved into an [`AsfSkeleton`].

use std::collections::HashMap;

use super::skeleton::{AsfSkeleton, Bone, LANDMARK_BONES, Root, RootDof};
use crate::error::{MocapError, ParseProblem};
use crate::rotation::{Axis, Rot3};
use crate::text::Source;
use camloc_skeleton::{Landmark, NUM_LANDMARKS};

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
pub(super) struct RawSkeleton<'a> {
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
    pub(super) fn start_section(
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
    pub(super) fn line(
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
    pub(super) fn finish(
        self,
        last_line: usize,
        source: Source<'_>,
    ) -> Result<AsfSkeleton, MocapError> {
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
