"""Tests of what a notebook user passes and gets back (a simulated user's trial): arguments
refused with their names, inputs people have (an empty list, a table of one pose a row,
pandas' missing values, joints NaN in every channel), the warnings' class, the rate a
sequence was solved at."""

import warnings

import numpy as np
import pytest

import camloc
from helpers import example_points


def test_arguments_of_the_wrong_type_are_named():
    points = example_points()
    cases = [
        (dict(sequence=1), "sequence: expected True or False, got int"),
        (dict(lifter=0), "lifter: expected True, False or a lifter file's path, got int"),
        (dict(sequence_max_rows=1e5), "sequence_max_rows: expected a whole number"),
    ]
    for kwargs, message in cases:
        with pytest.raises(TypeError, match=message):
            camloc.reconstruct(points, **kwargs)
    with pytest.raises(TypeError, match="sequence: expected True or False"):
        camloc.Localizer().localize(points, sequence="yes")
    with pytest.raises(ValueError, match="sequence_max_rows: expected a whole number >= 0"):
        camloc.reconstruct(points, sequence_max_rows=-1)
    with pytest.raises(TypeError, match="recursive: expected True or False"):
        camloc.read_keypoints(".", recursive=None)
    # None where a default is meant: the default.
    default = camloc.reconstruct(points)
    unset = camloc.reconstruct(points, lifter=None, layout=None)
    np.testing.assert_array_equal(default["points3d"], unset["points3d"])
    np.testing.assert_array_equal(
        camloc.Localizer().localize(points, layout=None)["label"],
        camloc.Localizer().localize(points)["label"],
    )
    # NumPy's bools are bools.
    assert camloc.reconstruct(points, sequence=np.bool_(False))["points3d"].shape == (3, 15, 3)


def test_an_empty_list_is_no_poses():
    got = camloc.Localizer().localize([])
    assert got["label"].shape == (0,) and got["probabilities"].shape == (0, 12)
    assert camloc.reconstruct([])["points3d"].shape == (0, 15, 3)


def test_shape_mistakes_say_what_to_give():
    points = example_points()
    # A table of one pose a row: x, y of the 15 joints flattened.
    with pytest.raises(ValueError, match=r"reshape\(-1, 15, 2\)"):
        camloc.Localizer().localize(points.reshape(3, 30))
    # 17 joints without a layout: the layouts of 17 joints are named.
    seventeen = np.zeros((2, 17, 2))
    with pytest.raises(ValueError, match='layout="coco17" or layout="h36m17"'):
        camloc.Localizer().localize(seventeen)


def test_pandas_missing_values_are_named():
    class NAType:
        """What pandas' pd.NA is to NumPy: an object that is no float."""

    points = example_points().astype(object)
    points[0, 3, 0] = NAType()
    with pytest.raises(TypeError, match=r"pd.NA is not a number.*na_value=np.nan"):
        camloc.Localizer().localize(points)


def test_a_joint_nan_in_every_channel_is_missing():
    points = example_points()
    scored = np.concatenate([points, np.full(points.shape[:2] + (1,), 0.8)], axis=-1)
    scored[1, 11] = np.nan
    got = camloc.Localizer().localize(scored)
    assert got["error"][1] is None
    zero = scored.copy()
    zero[1, 11, 2] = 0.0
    np.testing.assert_array_equal(got["probabilities"], camloc.Localizer().localize(zero)["probabilities"])
    # A present joint's NaN score stays an error.
    scored[1, 11] = [1.0, 2.0, np.nan]
    assert "joint 11's score: NaN" in camloc.Localizer().localize(scored)["error"][1]
    # The same with the scores given apart.
    error = camloc.Localizer().localize(scored[..., :2], scores=scored[..., 2])["error"][1]
    assert "joint 11's score: NaN" in error


def test_warnings_are_camloc_warnings():
    flipped = example_points() * [1.0, -1.0]
    with pytest.warns(camloc.CamlocWarning, match="head below both ankles"):
        camloc.Localizer().localize(flipped)
    assert issubclass(camloc.CamlocWarning, UserWarning)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.simplefilter("ignore", camloc.CamlocWarning)
        camloc.reconstruct(flipped)


def test_a_sequence_returns_the_rate_it_was_solved_at():
    points = example_points()
    assert camloc.reconstruct(points)["fps"] == 30.0
    seq = camloc.reconstruct(points, sequence=True, fps=120)
    assert seq["fps"] == 120.0
    bvh = camloc.to_bvh(seq["world_points3d"], seq["fps"], seq["person_bone_lengths"])
    assert "Frame Time: 0.00833333" in bvh


def test_missing_and_derived_landmarks_are_the_command_line_s(cli, tmp_path):
    """``missing`` and ``derived`` as ``camloc localize --npz`` writes them, for Human3.6M
    poses with scores, one joint scored 0 and one row that cannot be read (a half-NaN joint)."""
    from helpers import SAMPLES

    points = np.load(SAMPLES / "h36m17_scores.npy")
    points[0, 14, 2] = 0.0
    points[1, 5, 0] = np.nan
    path = tmp_path / "h36m.npy"
    np.save(path, points)
    cli("localize", "--input", path, "--layout", "h36m17", "--npz", tmp_path / "o.npz", "-q")
    with np.load(tmp_path / "o.npz") as npz:
        want = {name: npz[name] for name in ("missing", "derived")}
    got = camloc.Localizer().localize(points, layout="h36m17")
    for name in ("missing", "derived"):
        assert got[name].shape == (len(points), 15) and got[name].dtype == np.bool_
        np.testing.assert_array_equal(got[name], want[name], err_msg=name)
    assert got["missing"][0].sum() == 1 and got["missing"][1].all()


def test_mediapipe_landmarks_are_a_layout():
    """MediaPipe Pose's 33 landmarks in pixels (layout ``mediapipe33``; its unused joints NaN)
    give what COCO-17 arrays of the same joints give: the same 12 limb joints, the head from
    the same face points."""
    points = example_points()
    names = ["left_shoulder", "right_shoulder", "left_elbow", "right_elbow", "left_wrist",
             "right_wrist", "left_hip", "right_hip", "left_knee", "right_knee", "left_ankle",
             "right_ankle"]
    head = points[:, [camloc.LANDMARKS.index("head")]]
    limbs = points[:, [camloc.LANDMARKS.index(n) for n in names]]
    coco17 = np.concatenate([np.repeat(head, 5, axis=1), limbs], axis=1)
    mediapipe = np.full((len(points), 33, 2), np.nan)
    mediapipe[:, [0, 2, 5, 7, 8]] = head
    mediapipe[:, [11, 12, 13, 14, 15, 16, 23, 24, 25, 26, 27, 28]] = limbs
    assert "mediapipe33" in camloc.LAYOUTS
    alone = camloc.Localizer(camera_height="any")
    expected = alone.localize(coco17, layout="coco17")
    got = alone.localize(mediapipe, layout="mediapipe33")
    np.testing.assert_array_equal(got["label"], expected["label"])
    np.testing.assert_allclose(got["probabilities"], expected["probabilities"], atol=1e-12)
    # MediaPipe's own four numbers a landmark are refused with the way to give them, and that
    # way gives what the three channels give.
    with pytest.raises(ValueError, match=r"points\[\.\.\., :2\] with scores=points\[\.\.\., 3\]"):
        alone.localize(np.zeros((2, 33, 4)), layout="mediapipe33")
    four = np.concatenate([mediapipe, np.zeros((len(points), 33, 1)), np.ones((len(points), 33, 1))],
                          axis=2)
    hinted = alone.localize(four[..., :2], layout="mediapipe33", scores=four[..., 3])
    np.testing.assert_array_equal(hinted["label"], expected["label"])
    rebuilt = camloc.reconstruct(four[..., :2], layout="mediapipe33", scores=four[..., 3])
    assert all(e is None for e in rebuilt["error"])
