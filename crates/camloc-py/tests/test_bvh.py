"""BVH export from Python: `camloc.to_bvh` files read back, by camloc's own reader
(`camloc.read_bvh`) and by a third-party parser (bvhio, with its own forward kinematics), to
the reconstructed landmarks within 1 mm: the fixture poses, and 200 frames of a CMU walk of a
held-out subject taken from 2D keypoints, through Python and through `camloc reconstruct
--sequence --bvh` (skipped, with the reason, without the data); with root motion, the
command line's file animates Python's `world_points3d`.
"""

import json
from pathlib import Path

import numpy as np
import pytest

import camloc
from helpers import DATA, walk_trials

ROOT = Path(__file__).resolve().parents[3]
EXAMPLE = ROOT / "fixtures" / "keypoints" / "example.json"

# The subjects the project's evaluations hold out (xtask/src/generalise.rs, TEST_SUBJECTS).
HELD_OUT = ["06", "09", "16", "17", "35", "47", "113", "127", "141"]

# camloc's landmark of each joint camloc's BVH files name (LANDMARKS order).
JOINTS = [
    "Hips", "LeftUpLeg", "LeftLeg", "LeftFoot", "RightUpLeg", "RightLeg", "RightFoot",
    "Neck", "Head", "LeftArm", "LeftForeArm", "LeftHand", "RightArm", "RightForeArm", "RightHand",
]

# The 14 limbs as (parent, child) landmark indices, parents first (docs/conventions.md section 3).
LIMBS = [(0, 1), (1, 2), (2, 3), (0, 4), (4, 5), (5, 6), (0, 7), (7, 8), (7, 9), (9, 10),
         (10, 11), (7, 12), (12, 13), (13, 14)]


def with_lengths(points3d, lengths):
    """Each pose of (N, 15, 3) with every limb brought to its length along its own direction."""
    out = points3d.copy()
    for k, (a, b) in enumerate(LIMBS):
        d = points3d[:, b] - points3d[:, a]
        out[:, b] = out[:, a] + d * (lengths[k] / np.linalg.norm(d, axis=1))[:, None]
    return out


def mean_lengths(points3d):
    return np.array([np.linalg.norm(points3d[:, b] - points3d[:, a], axis=1).mean()
                     for a, b in LIMBS])


def bvhio_landmarks(path, unit_m):
    """The 15 landmarks of every frame as bvhio computes them, metres, z up (N, 15, 3)."""
    bvhio = pytest.importorskip("bvhio", reason="the third-party BVH parser bvhio is not installed")
    root = bvhio.readAsHierarchy(str(path))
    joints = {joint.Name: joint for joint, _, _ in root.layout()}
    frames = []
    for frame in range(len(root.Keyframes)):
        root.loadPose(frame)
        # File frame y up: (x, y, z) -> (x, -z, y) in camloc's z-up world.
        frames.append([[p.x, -p.z, p.y] for p in (joints[j].PositionWorld for j in JOINTS)])
    return np.array(frames) * unit_m


def assert_both_readers_give(path, expected, fps):
    """camloc's reader and bvhio give `expected` (N, 15, 3) within 1 mm; returns the errors."""
    ours = camloc.read_bvh(path, unit_m=0.01)
    assert ours["points3d"].shape == expected.shape
    assert abs(ours["frame_time_s"] - 1 / fps) < 1e-9
    theirs = bvhio_landmarks(path, 0.01)
    errors = []
    for read in (ours["points3d"], theirs):
        error = np.linalg.norm(read - expected, axis=2).max()
        assert error < 1e-3, f"largest landmark error {error} m"
        errors.append(error)
    return errors


def test_fixture_poses_read_back_by_both_readers(tmp_path):
    points = camloc.read_keypoints(EXAMPLE)["points"]
    rec = camloc.reconstruct(points)
    for n, pose in enumerate(rec["points3d"]):
        path = tmp_path / f"pose{n}.bvh"
        path.write_text(camloc.to_bvh(pose, fps=25))
        assert_both_readers_give(path, pose[None], 25)


def test_bad_input_raises_value_error():
    pose = camloc.reconstruct(camloc.read_keypoints(EXAMPLE)["points"])["points3d"][0]
    with pytest.raises(ValueError, match="shape"):
        camloc.to_bvh(np.zeros((3, 14, 3)))
    with pytest.raises(ValueError, match="fps"):
        camloc.to_bvh(pose, fps=0)
    with pytest.raises(ValueError, match="limb_lengths: 13 numbers, expected 14"):
        camloc.to_bvh(pose, limb_lengths=[0.3] * 13)
    with pytest.raises(ValueError, match="no frame"):
        camloc.to_bvh(np.full((2, 15, 3), np.nan))
    half = pose.copy()
    half[3, 1] = np.nan
    with pytest.raises(ValueError, match=r"points3d\[0\]"):
        camloc.to_bvh(half)
    with pytest.raises(OSError):
        camloc.read_bvh(ROOT / "no-such-file.bvh")


def held_out_walk():
    """A walk of a held-out subject, chosen by its description in the CMU index ("walk")."""
    folder, walks = DATA / "cmu" / "bvh", walk_trials()
    if walks is None or not folder.is_dir():
        pytest.skip(f"SKIPPED: the CMU walk test: {DATA / 'cmu'} not found (set CAMLOC_DATA)")
    for path in sorted(folder.glob("*.bvh")):
        subject = path.stem.split("_")[0]
        if path.stem in walks and subject in HELD_OUT:
            return path
    pytest.skip("no walk of a held-out subject in the CMU folder")


@pytest.fixture(scope="module")
def walk_keypoints():
    """(clip name, (200, 15, 2) keypoints) of a held-out CMU walk seen by one fixed camera: 4 m
    from the mean pelvis, 10 degrees above it, at 200 degrees of azimuth in the clip's ground
    plane (the walker's facing is the clip's own), 1000 px focal length."""
    clip = held_out_walk()
    truth = camloc.read_bvh(clip)["points3d"][:200]
    assert truth.shape == (200, 15, 3)
    a, e = np.radians(200.0), np.radians(10.0)
    towards = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    z = -towards
    x = np.cross(z, [0, 0, 1.0])
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    centre = truth[:, 0].mean(axis=0) + 4.0 * towards
    local = (truth - centre) @ np.stack([x, y, z]).T
    return clip.name, 1000.0 * local[..., :2] / local[..., 2:] + [960.0, 540.0]


def assert_walk_reads_back(name, path, points3d, how):
    """The walk's BVH at `path` reads back (both readers) to each frame's limb directions with
    the mean limb lengths of the frames; prints the errors."""
    expected = with_lengths(points3d, mean_lengths(points3d))
    ours, theirs = assert_both_readers_give(path, expected, 120)
    moved = np.linalg.norm(expected - points3d, axis=2).max()
    print(f"{name} ({how}): read back within {ours * 1e3:.6f} mm (camloc), {theirs * 1e3:.6f} "
          f"mm (bvhio); the shared lengths move landmarks by up to {moved * 1e3:.1f} mm")


def test_a_held_out_cmu_walk_goes_from_2d_keypoints_to_a_bvh_both_readers_read_back(
    tmp_path, walk_keypoints
):
    name, points2d = walk_keypoints
    rec = camloc.reconstruct(points2d)
    assert all(error is None for error in rec["error"])
    path = tmp_path / "walk.bvh"
    path.write_text(camloc.to_bvh(rec["points3d"], fps=120))
    assert_walk_reads_back(name, path, rec["points3d"], "camloc.to_bvh")


def write_keypoints(path, points2d):
    """`points2d` (N, 15, 2) written as a camloc JSON keypoint file at `path`, one pose a frame."""
    poses = [
        {"id": f"frame-{t:04d}", "landmarks": dict(zip(camloc.LANDMARKS, pose.tolist()))}
        for t, pose in enumerate(points2d)
    ]
    path.write_text(json.dumps({"format": "camloc-keypoints", "version": 1, "poses": poses}))
    return path


def test_the_command_line_makes_the_walk_bvh_both_readers_read_back(
    tmp_path, walk_keypoints, cli
):
    name, points2d = walk_keypoints
    keypoints = write_keypoints(tmp_path / "walk.json", points2d)
    path = tmp_path / "walk.bvh"
    code, objects = cli("reconstruct", "--input", keypoints, "--sequence", "--fps", "120",
                        "--bvh", path, "--bvh-in-place")
    assert code == 0 and len(objects) == 200
    points3d = np.array([[o["landmarks_m"][n] for n in camloc.LANDMARKS] for o in objects])
    # In place, each pelvis is above the origin at the height root motion gives it.
    world = camloc.reconstruct(points2d, sequence=True, fps=120)["world_points3d"]
    points3d[..., 2] += world[:, :1, 2]
    assert_walk_reads_back(name, path, points3d, "camloc reconstruct --sequence --bvh")


def test_the_command_line_s_walk_moves_as_python_s_world_points3d(tmp_path, walk_keypoints, cli):
    """`camloc reconstruct --sequence --bvh` (root motion) animates the frames Python's
    `reconstruct(sequence=True)["world_points3d"]` places, both readers within 1 mm; the
    walker moves across the floor."""
    name, points2d = walk_keypoints
    keypoints = write_keypoints(tmp_path / "walk.json", points2d)
    path = tmp_path / "walk.bvh"
    code, _ = cli("reconstruct", "--input", keypoints, "--sequence", "--fps", "120", "--bvh", path)
    assert code == 0
    rec = camloc.reconstruct(points2d, sequence=True, fps=120)
    world = rec["world_points3d"]
    assert world.shape == (200, 15, 3) and not np.isnan(world).any()
    assert "world_points3d" not in camloc.reconstruct(points2d[:3])
    # The floor is under the planted feet: the lower ankle on it at the median, a tenth of
    # the planted ankles a little below it.
    ankles = [camloc.LANDMARKS.index(n) for n in ("left_ankle", "right_ankle")]
    lower = world[:, ankles, 2].min(axis=1)
    assert abs(np.median(lower)) < 0.03 and world[..., 2].min() > -0.05
    walked = np.linalg.norm(world[-1, 0, :2] - world[0, 0, :2])
    assert walked > 0.5, f"the pelvis moved {walked:.2f} m"
    ours, theirs = assert_both_readers_give(path, with_lengths(world, mean_lengths(world)), 120)
    print(f"{name}: the pelvis moved {walked:.2f} m across the floor; the command line's BVH is "
          f"Python's world_points3d within {ours * 1e3:.6f} mm (camloc), {theirs * 1e3:.6f} mm "
          "(bvhio)")


def test_to_bvh_takes_limb_lengths_as_reconstruct_takes_bone_lengths(tmp_path):
    """A mapping of BONE_KEYS, 14 numbers and a file give the same file; bad ones name the
    argument."""
    pose = camloc.reconstruct(camloc.read_keypoints(EXAMPLE)["points"])["points3d"][0]
    lengths = [0.1, 0.42, 0.41, 0.1, 0.42, 0.41, 0.5, 0.25, 0.17, 0.28, 0.26, 0.17, 0.28, 0.26]
    mapping = dict(zip(camloc.BONE_KEYS, lengths))
    path = tmp_path / "me.json"
    path.write_text(json.dumps({"format": "camloc-bone-lengths", "version": 1, "unit": "m",
                                "lengths": mapping}))
    as_list = camloc.to_bvh(pose, limb_lengths=lengths)
    assert camloc.to_bvh(pose, limb_lengths=mapping) == as_list
    assert camloc.to_bvh(pose, limb_lengths=str(path)) == as_list
    with pytest.raises(ValueError, match="limb_lengths: 13 numbers"):
        camloc.to_bvh(pose, limb_lengths=lengths[:13])
    with pytest.raises(ValueError, match="limb_lengths: unknown key"):
        camloc.to_bvh(pose, limb_lengths={**mapping, "tail": 0.3})
