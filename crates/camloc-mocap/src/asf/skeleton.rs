//! [`AsfSkeleton`]: the bones of an ASF file in their rest pose, and the forward kinematics
//! that turn a frame of motion values into the 15 landmarks.

use std::ops::Range;

use crate::rotation::{Axis, Rot3, add, y_up_to_z_up};
use camloc_skeleton::{NUM_LANDMARKS, Pose3};

/// A skeleton read from an ASF file: bones, their rest geometry, motion channels and units.
#[derive(Clone, Debug)]
pub struct AsfSkeleton {
    pub(super) source: String,
    pub(super) metres_per_unit: f64,
    pub(super) radians_per_angle_unit: f64,
    pub(super) root: Root,
    /// Bones, parents before children.
    pub(super) bones: Vec<Bone>,
    /// The bone whose end point is each landmark; `None` for the pelvis (the root position).
    pub(super) landmarks: [Option<usize>; NUM_LANDMARKS],
    /// Number of motion values per frame (root and every bone).
    pub(super) value_count: usize,
}

/// The root: AMC value order, pre-set position and orientation frame.
#[derive(Clone, Debug)]
pub(super) struct Root {
    pub(super) order: Vec<RootDof>,
    pub(super) position: [f64; 3],
    pub(super) axis: Rot3,
    pub(super) axis_inverse: Rot3,
}

/// One root motion value: a translation or a rotation along an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum RootDof {
    Translation(Axis),
    Rotation(Axis),
}

/// A bone in its rest pose, with its motion channels.
#[derive(Clone, Debug)]
pub(super) struct Bone {
    pub(super) name: String,
    /// Parent bone (an index into `AsfSkeleton::bones`), `None` for a child of the root.
    pub(super) parent: Option<usize>,
    /// `direction * length`, file units.
    pub(super) vector: [f64; 3],
    pub(super) axis: Rot3,
    pub(super) axis_inverse: Rot3,
    pub(super) dofs: Vec<Axis>,
    /// Index of this bone's first value in a frame's value vector.
    pub(super) first_value: usize,
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
pub(super) const LANDMARK_BONES: [Option<&str>; NUM_LANDMARKS] = [
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
