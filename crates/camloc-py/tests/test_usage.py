"""Tests of the camloc Python package as users call it: sequences and their warnings,
arguments written as people write them, help texts, hostile sizes, masked and complex input,
known cameras, pickling and forked processes, the camera-height estimate.

The command-line comparisons run the `camloc` binary of the `cli` fixture (conftest.py).
"""

import json
import threading
import warnings

import numpy as np
import pytest

import camloc
from helpers import KEYPOINTS, LENGTHS, ROOT, example_points


def test_opt_makes_no_estimate_of_the_camera_heights():
    """``camera="opt"`` localizes no complete pose (it fills in missing joints with the
    localized camera): like ``camloc reconstruct --camera opt`` it makes no estimate. The 400
    LSP photos (skipped visibly without the data) have enough poses for one, and joints to
    fill in; an estimate changed 19 of their opt poses by up to 0.78 m."""
    lsp = ROOT.parent / "shared" / "data" / "lsp" / "lsp400_joints.csv"
    if not lsp.is_file():
        pytest.skip(f"SKIPPED: {lsp} not found")
    many = camloc.read_keypoints(lsp)["points"]
    default = camloc.reconstruct(many, camera="opt")["points3d"]
    alone = camloc.reconstruct(many, camera="opt", camera_height="any")["points3d"]
    np.testing.assert_array_equal(default, alone)


def test_a_sequence_that_jumps_between_people_warns_and_nothing_detected_says_so():
    # One person standing still, then another 600 px to the right: the rows of two people.
    pose = example_points()[0]
    rows = np.stack([pose + [2.0 * t, 0.0] for t in range(6)])
    other = rows + [600.0, 0.0]
    with pytest.warns(UserWarning, match="jumps across the image"):
        camloc.reconstruct(np.concatenate([rows, other]), sequence=True)
    # One row of the other person among one person's rows (two tracked ids swapped for a
    # frame).
    swapped = rows.copy()
    swapped[2] = other[2]
    with pytest.warns(UserWarning, match="lie apart from the rows before and after them"):
        got = camloc.reconstruct(swapped, sequence=True, camera_height="any")
    # That row is reconstructed on its own, as the command line does, and not placed in the
    # world; the others are.
    alone = camloc.reconstruct(swapped[2], camera_height="any")
    np.testing.assert_allclose(got["points3d"][2], alone["points3d"], atol=1e-9)
    assert np.isnan(got["world_points3d"][2]).all()
    assert np.isfinite(np.delete(got["world_points3d"], 2, axis=0)).all()
    assert got["left_out_of_sequence"].tolist() == [False, False, True, False, False, False]
    with pytest.warns(UserWarning, match="left out of the smoothing"):
        smoothed = camloc.Localizer().localize(swapped, sequence=True)
    assert smoothed["left_out_of_sequence"].tolist() == [False, False, True, False, False, False]
    assert "left_out_of_sequence" not in camloc.Localizer().localize(rows)
    assert np.isnan(smoothed["smoothed_azimuth_deg"][2])
    assert np.isfinite(np.delete(smoothed["smoothed_azimuth_deg"], 2)).all()
    # Legs a detector read with the sides swapped for two rows: swapped back, as the command
    # line does.
    walking = np.stack([pose + [2.0 * t, 0.0] for t in range(12)])
    legs = [camloc.LANDMARKS.index(f"{side}_{joint}") for joint in ("hip", "knee", "ankle")
            for side in ("left", "right")]
    crossed = walking.copy()
    crossed[4:6, legs] = walking[4:6][:, [legs[i ^ 1] for i in range(6)]]
    with pytest.warns(UserWarning, match=r"left and right legs of 2 row\(s\) are swapped"):
        repaired = camloc.reconstruct(crossed, sequence=True)
    # The call's camera heights come from its rows as given (two of them swapped), so the
    # middle cameras' elevation, hence the 3D, may differ a little (0.4 mm here).
    np.testing.assert_allclose(
        repaired["points3d"], camloc.reconstruct(walking, sequence=True)["points3d"], atol=2e-3
    )
    expected = np.zeros((12, 2), bool)
    expected[4:6, 0] = True
    np.testing.assert_array_equal(repaired["swapped_sides"], expected)
    with pytest.warns(UserWarning, match=r"left and right legs of 2 row\(s\) are swapped"):
        located = camloc.Localizer().localize(crossed, sequence=True)
    clean = camloc.Localizer().localize(walking, sequence=True)
    np.testing.assert_array_equal(located["swapped_sides"], expected)
    # The call's camera heights are estimated from its rows as given (two of them swapped):
    # the probabilities may differ a little, the answers not.
    for key in ("label", "smoothed_label"):
        np.testing.assert_array_equal(located[key], clean[key])
    np.testing.assert_allclose(located["probabilities"], clean["probabilities"], atol=1e-3)
    np.testing.assert_allclose(located["azimuth_deg"], clean["azimuth_deg"], atol=0.1)
    np.testing.assert_allclose(located["elevation_deg"], clean["elevation_deg"], atol=0.2)
    # The other person's rows at the end of a sequence (ids swapped for its last 3 frames):
    # left out too, as the rows are consecutive frames.
    long_rows = np.stack([pose + [2.0 * t, 0.0] for t in range(12)])
    long_rows[9:] += [600.0, 0.0]
    with pytest.warns(UserWarning, match=r"3 row\(s\) lie apart .*first at row 9"):
        got = camloc.reconstruct(long_rows, sequence=True, camera_height="any")
    assert np.isnan(got["world_points3d"][9:]).all()
    assert np.isfinite(got["world_points3d"][:9]).all()
    # One person, with a row of NaN where nothing was detected: no warning, and that row's
    # error says what happened.
    rows[3] = np.nan
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = camloc.reconstruct(rows, sequence=True)
    assert got["error"][3] == "the pose has no landmarks (nothing detected)"
    assert np.isnan(got["points3d"][3]).all()
    assert all(e is None for k, e in enumerate(got["error"]) if k != 3)


def test_smooth_viewpoints_equals_the_command_line(cli, localizer):
    path = KEYPOINTS / "example.json"
    _, rows = cli("localize", "--input", path, "--sequence")
    azimuth = np.array([r["azimuth_deg"] for r in rows])
    elevation = np.array([r["elevation_deg"] for r in rows])
    frames = np.array([r["frame"] if r.get("frame") is not None else i for i, r in enumerate(rows)])
    got = camloc.smooth_viewpoints(azimuth, elevation, frames)
    np.testing.assert_allclose(got[0], [r["smoothed_azimuth_deg"] for r in rows], atol=1e-4)
    np.testing.assert_allclose(got[1], [r["smoothed_elevation_deg"] for r in rows], atol=1e-4)
    # A frame without a viewpoint has none smoothed; frames far apart are not averaged.
    az, el = camloc.smooth_viewpoints([10.0, np.nan, 200.0], [0.0, np.nan, 5.0], [0, 1, 50])
    assert np.isnan(az[1]) and np.isnan(el[1])
    np.testing.assert_allclose([az[0], az[2], el[2]], [10.0, 200.0, 5.0], atol=1e-9)
    with pytest.raises(ValueError, match="same length"):
        camloc.smooth_viewpoints([1.0, 2.0], [1.0])
    with pytest.raises(ValueError, match="whole numbers"):
        camloc.smooth_viewpoints([1.0, 2.0], [1.0, 2.0], [-1, 3])
    with pytest.raises(ValueError, match="one-dimensional"):
        camloc.smooth_viewpoints([[1.0]], [[1.0]])
    with pytest.raises(ValueError, match=r"\[-90, 90\]"):
        camloc.smooth_viewpoints([1.0], [120.0])
    # At 120 frames a second the window is as long in time: 12 numbers on each side, as
    # `localize --sequence --fps 120` smooths.
    az, _ = camloc.smooth_viewpoints([10.0, 20.0, 30.0], [0.0, 0.0, 0.0], [0, 5, 10])
    np.testing.assert_allclose(az, [10.0, 20.0, 30.0], atol=1e-9)
    az, _ = camloc.smooth_viewpoints([10.0, 20.0, 30.0], [0.0, 0.0, 0.0], [0, 5, 10], fps=120)
    np.testing.assert_allclose(az, [20.0, 20.0, 20.0], atol=1e-9)
    _, fast = cli("localize", "--input", path, "--sequence", "--fps", "120")
    got = camloc.smooth_viewpoints(azimuth, elevation, frames, fps=120)
    np.testing.assert_allclose(got[0], [r["smoothed_azimuth_deg"] for r in fast], atol=1e-4)
    with pytest.raises(ValueError, match="fps"):
        camloc.smooth_viewpoints([1.0], [1.0], fps=0)
    # A threshold without scores is refused (it had been ignored without a word).
    with pytest.raises(ValueError, match="min_score 0.3 needs scores"):
        camloc.reconstruct(example_points(), min_score=0.3)
    # The command line's range: a rate a BVH file can hold (1e7 had been taken and solved at).
    with pytest.raises(ValueError, match="fps: not a frame rate.*got 10000000.0"):
        camloc.reconstruct(example_points(), sequence=True, fps=1e7)


def test_points_with_v_up_warn_as_the_command_line_does(localizer):
    points = example_points()
    flipped = points * [1.0, -1.0]
    with pytest.warns(UserWarning, match="head below both ankles"):
        localizer.localize(flipped)
    with pytest.warns(UserWarning, match="head below both ankles"):
        camloc.reconstruct(flipped)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        localizer.localize(points)


def test_a_sequence_is_smoothed_as_the_command_line_smooths_it(cli, localizer):
    path = KEYPOINTS / "example.json"
    _, rows = cli("localize", "--input", path, "--sequence")
    got = localizer.localize(example_points(), sequence=True)
    assert list(got["smoothed_label"]) == [r["smoothed_label"] for r in rows]
    np.testing.assert_allclose(
        got["smoothed_probability"], [r["smoothed_probability"] for r in rows], rtol=1e-9
    )
    for key in ["smoothed_azimuth_deg", "smoothed_elevation_deg"]:
        np.testing.assert_allclose(got[key], [r[key] for r in rows], atol=1e-4)
    # Without `sequence` there are no smoothed keys; a person never localized has none.
    assert "smoothed_label" not in localizer.localize(example_points())
    with pytest.warns(UserWarning, match="none of the 3 poses has a landmark"):
        empty = localizer.localize(np.full((3, 15, 2), np.nan), sequence=True)
    assert list(empty["smoothed_label"]) == [0, 0, 0]
    assert np.isnan(empty["smoothed_probability"]).all()


def test_a_localized_sequence_that_jumps_between_people_warns():
    pose = example_points()[0]
    rows = np.stack([pose + [2.0 * t, 0.0] for t in range(6)])
    with pytest.warns(UserWarning, match="jumps across the image"):
        camloc.Localizer().localize(np.concatenate([rows, rows + [600.0, 0.0]]), sequence=True)
    with pytest.raises(ValueError, match="frames must increase"):
        camloc.smooth_viewpoints([1.0, 2.0, 3.0], [0.0, 0.0, 0.0], [10, 0, 11])
    with pytest.raises(ValueError, match="layout"):
        camloc.read_keypoints(KEYPOINTS / "example.json", layout="h36m17")


def test_ctrl_c_stops_a_long_reconstruction():
    """A KeyboardInterrupt (Ctrl-C) during reconstruct comes within a block of poses, not at
    the end of the call."""
    import _thread
    import signal
    import time

    points = np.tile(example_points(), (40_000, 1, 1))
    # A runner started in the background (`cmd &` without job control) ignores SIGINT, and
    # Python then keeps it ignored: interrupt_main does nothing. Ctrl-C as a terminal has it.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, _thread.interrupt_main)
    started = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            camloc.reconstruct(points)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    # Not a speed goal: the whole call (120,000 poses) takes about a minute on two cores, a
    # block of 1024 poses about half a second; an interrupt only seen at the end fails this.
    assert time.perf_counter() - started < 30.0


def test_localizers_pickle_and_copy_to_the_same_answers(localizer):
    import copy
    import pickle

    points = example_points()
    want = localizer.localize(points)["probabilities"]
    for other in (pickle.loads(pickle.dumps(localizer)), copy.deepcopy(localizer)):
        assert other.camera_height == localizer.camera_height
        np.testing.assert_array_equal(other.localize(points)["probabilities"], want)
    eye = camloc.Localizer(camera_height="eye-level")
    assert pickle.loads(pickle.dumps(eye)).camera_height == "eye-level"


def h36m_standing_and_face():
    """Human3.6M's 17 joints of a standing person (pixels), and the same with the first five
    gathered as a face's: a pose refused for its layout."""
    standing = np.array(
        [[100, 130], [85, 130], [84, 185], [83, 240], [115, 130], [116, 185], [117, 240],
         [100, 90], [100, 50], [100, 20], [100, 5], [125, 50], [130, 90], [132, 125],
         [75, 50], [70, 90], [68, 125]],
        dtype=float,
    )
    face = standing.copy()
    face[:5] = [[100 + 2 * j, 20 - j] for j in range(5)]
    return standing, face


def test_a_sequence_row_refused_for_its_layout_is_a_failed_frame_in_its_place():
    # Human3.6M's 17 joints of a standing person, and the same with the first five gathered
    # as a face's: that row is refused for its layout (it had failed the whole sequence).
    standing, face = h36m_standing_and_face()
    rows = np.stack([standing + [4.0 * t, 0.0] for t in range(6)])
    rows[2] = face + [8.0, 0.0]
    got = camloc.reconstruct(rows, layout="h36m17", sequence=True)
    assert [e is not None for e in got["error"]] == [False, False, True, False, False, False]
    assert "likely coco17" in got["error"][2]
    assert np.isnan(got["points3d"][2]).all() and not np.isnan(got["points3d"][3]).any()


def test_a_pose_refused_for_its_layout_is_a_row_without_landmarks_in_its_place(tmp_path):
    """``read_keypoints`` reads on past a pose the reader refuses, as the command line does
    (a simulated user's 7,434-pose COCO file had been refused whole for one pose)."""
    standing, face = h36m_standing_and_face()
    folder = tmp_path / "take"
    folder.mkdir()
    np.save(folder / "a.npy", np.stack([standing, face, standing + [5.0, 0.0]]))
    np.save(folder / "b.npy", np.stack([standing]))
    with pytest.warns(UserWarning, match=r"1 pose\(s\) could not be read .*likely coco17"):
        got = camloc.read_keypoints(folder / "a.npy", layout="h36m17")
    assert len(got["points"]) == 3 and got["file_errors"] == []
    assert np.isnan(got["points"][1]).all() and not np.isnan(got["points"][[0, 2]]).any()
    [(source, message)] = got["pose_errors"]
    assert source == got["sources"][1] and "likely coco17" in message
    with pytest.warns(UserWarning, match=r"1 pose\(s\) could not be read"):
        both = camloc.read_keypoints(folder, layout="h36m17")
    assert len(both["points"]) == 4 and both["file_errors"] == [] and len(both["pose_errors"]) == 1
    clean = camloc.read_keypoints(folder / "b.npy", layout="h36m17")
    assert clean["pose_errors"] == []


def test_a_focal_length_alone_changes_no_localization_and_says_so(localizer):
    import warnings

    points = example_points()
    with pytest.warns(UserWarning, match="focal_px without principal_point"):
        alone = localizer.localize(points, focal_px=900.0)
    np.testing.assert_array_equal(alone["probabilities"], localizer.localize(points)["probabilities"])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        localizer.localize(points, focal_px=900.0, principal_point=(320, 240))


def test_points_that_are_no_array_say_so(localizer):
    for given in (None, 3.0):
        with pytest.raises(ValueError, match="got a single value, not an array of points"):
            localizer.localize(given)
    with pytest.raises(ValueError, match=r"got shape \[2\]"):
        localizer.localize(np.zeros(2))


def _localize_in_a_worker(points):
    return camloc.Localizer().localize(points)["label"]


def test_a_process_forked_after_parallel_work_localizes(localizer):
    # rayon's threads, started by the parent's batch, do not exist in a forked child: its work
    # had waited for them forever (a simulated user's multiprocessing pipeline hung).
    import multiprocessing

    points = np.repeat(example_points(), 5_000, axis=0)
    want = localizer.localize(points)["label"]
    pool = multiprocessing.get_context("fork").Pool(1)
    try:
        got = pool.apply_async(_localize_in_a_worker, (points,)).get(timeout=120)
    finally:
        pool.terminate()
    np.testing.assert_array_equal(got, want)


def test_input_mistakes_warn_where_every_pose_would_fail_quietly(localizer):
    import warnings

    points = example_points()
    # Scores on a scale of 0 to 100 fail every pose, one by one.
    with pytest.warns(UserWarning, match="every one of the 3 poses failed"):
        out = localizer.localize(points, scores=np.full(points.shape[:2], 95.0))
    assert all(e is not None for e in out["error"])
    # A minimum score above every score leaves no landmark: said, as the command line does.
    for call in (localizer.localize, camloc.reconstruct):
        with pytest.warns(UserWarning, match="none of the 3 poses has a landmark"):
            call(points, scores=np.full(points.shape[:2], 0.5), min_score=0.9)
    # Joints at (0, 0), where detectors put the ones they did not find.
    zeros = points.copy()
    zeros[:, [3, 6]] = 0.0
    with pytest.warns(UserWarning, match=r"landmarks at exactly \(0, 0\)"):
        localizer.localize(zeros)
    # The same joints given as NaN: no warning.
    nans = points.copy()
    nans[:, [3, 6]] = np.nan
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        localizer.localize(nans)


def test_arguments_as_users_write_them():
    points = example_points()
    by_case = camloc.reconstruct(points, camera="HYBRID")["points3d"]
    np.testing.assert_array_equal(by_case, camloc.reconstruct(points)["points3d"])
    as_list = camloc.reconstruct(points, focal_px=1500.0, principal_point=[320, 240])
    as_tuple = camloc.reconstruct(points, focal_px=1500.0, principal_point=(320.0, 240.0))
    np.testing.assert_array_equal(as_list["points3d"], as_tuple["points3d"])
    with pytest.raises(ValueError, match="principal_point: 2 numbers"):
        camloc.reconstruct(points, focal_px=1500.0, principal_point=[1, 2, 3])
    # The command line's "U,V" is not a Python pair: the error says what is.
    with pytest.raises(TypeError, match=r"two numbers \(u, v\) in pixels.*got a str"):
        camloc.reconstruct(points, focal_px=1500.0, principal_point="320,240")
    with pytest.raises(TypeError, match=r"got a list: \[960, '540'\]"):
        camloc.reconstruct(points, focal_px=1500.0, principal_point=[960, "540"])
    with pytest.raises(TypeError, match="focal_px: a number of pixels.*got a str"):
        camloc.reconstruct(points, focal_px="1000")
    with pytest.raises(TypeError, match="focal_px: .*got a bool"):
        camloc.Localizer().localize(points, focal_px=True)
    np.testing.assert_array_equal(
        camloc.reconstruct(points, focal_px=np.float32(1500.0), principal_point=[320, 240])[
            "points3d"
        ],
        as_list["points3d"],
    )
    with pytest.raises(TypeError, match="got a dict"):
        camloc.Localizer().localize(points, focal_px=1500.0, principal_point={"u": 1})
    np.testing.assert_array_equal(
        camloc.reconstruct(points, focal_px=1500.0, principal_point=np.array([320, 240]))[
            "points3d"
        ],
        as_list["points3d"],
    )
    # read_keypoints' frames of an input without frame numbers are -1.
    azimuth, elevation = np.linspace(0, 90, 5), np.zeros(5)
    np.testing.assert_array_equal(
        camloc.smooth_viewpoints(azimuth, elevation, frames=np.full(5, -1))[0],
        camloc.smooth_viewpoints(azimuth, elevation)[0],
    )
    # Points in millimetres make limbs no one has.
    pose3d = camloc.reconstruct(points)["points3d"]
    camloc.to_bvh(pose3d)
    with pytest.raises(ValueError, match="must be in metres"):
        camloc.to_bvh(pose3d * 1000.0)


def test_help_shows_the_stubs_docstrings():
    """A notebook's help() and ? read __doc__, which build.rs takes from camloc.pyi."""
    import inspect

    stub = (ROOT / "crates" / "camloc-py" / "camloc.pyi").read_text()
    for obj, phrase in [
        (camloc, "where the camera stood"),
        (camloc.reconstruct, "projected matching pursuit"),
        (camloc.Localizer, "A trained camera localizer"),
        (camloc.Localizer.localize, None),
        (camloc.read_keypoints, None),
        (camloc.to_bvh, None),
    ]:
        doc = inspect.getdoc(obj)
        assert doc and "see `camloc.pyi`" not in doc, obj
        assert phrase is None or phrase in doc, (obj, doc[:200])
        assert doc.splitlines()[0].strip() in stub, obj
    assert str(inspect.signature(camloc.read_bvh)) == "(path, unit_m=0.05644444444444444)"


def test_bone_lengths_json_is_the_file_reconstruct_reads(tmp_path, cli):
    got = camloc.reconstruct(example_points(), sequence=True)["person_bone_lengths"]
    path = tmp_path / "lengths.json"
    path.write_text(camloc.bone_lengths_json(got))
    again = camloc.reconstruct(example_points(), bone_lengths=path)["bone_lengths"]
    np.testing.assert_allclose(again, np.tile(got, (len(again), 1)), rtol=1e-12)
    code, rows = cli("reconstruct", "--input", KEYPOINTS / "example.json", "--bone-lengths", path)
    assert code == 0
    keys = camloc.BONE_KEYS
    np.testing.assert_allclose([rows[0]["bone_lengths_m"][k] for k in keys], got, rtol=1e-9)
    with pytest.raises(ValueError, match="14"):
        camloc.bone_lengths_json([0.3] * 13)


def test_hostile_sizes_and_units_raise_instead_of_aborting(tmp_path):
    # Broadcast views of 10^9 poses or frames are a few bytes in NumPy; copying them or
    # their outputs had aborted the interpreter.
    pose = example_points()[0]
    with pytest.raises(MemoryError):
        camloc.Localizer().localize(np.broadcast_to(pose, (10**9, 15, 2)))
    with pytest.raises(MemoryError):
        camloc.reconstruct(np.broadcast_to(pose, (10**9, 15, 2)))
    angles = np.broadcast_to(np.float64(10.0), (10**10,))
    with pytest.raises(MemoryError):
        camloc.smooth_viewpoints(angles, angles)
    points3d = camloc.reconstruct(pose)["points3d"]
    with pytest.raises(MemoryError):
        camloc.to_bvh(np.broadcast_to(points3d, (10**9, 15, 3)))
    # A unit that made every coordinate infinite.
    with pytest.raises(ValueError, match="unit_m must be from"):
        camloc.to_bvh(points3d, unit_m=5e-324)
    with pytest.raises(ValueError, match="unit_m must be from"):
        camloc.read_bvh(tmp_path / "any.bvh", unit_m=5e-324)
    # A focal length wrong by orders of magnitude is the pose's error, not NaN results; one
    # under a pixel is refused.
    got = camloc.reconstruct(pose, focal_px=2.0)
    assert "focal lengths" in got["error"]
    with pytest.raises(ValueError, match="focal_px must be a finite number of pixels >= 1"):
        camloc.reconstruct(pose, focal_px=5e-324)
    # A file without poses: empty arrays, and a warning (the command line refuses it).
    empty = tmp_path / "empty.json"
    empty.write_text('{"format": "camloc-keypoints", "version": 1, "poses": []}')
    with pytest.warns(UserWarning, match="no poses in"):
        read = camloc.read_keypoints(empty)
    assert read["points"].shape == (0, 15, 2)
    # A folder whose poses are all in its sub-folders: said, as the command line says it.
    nested = tmp_path / "videos" / "clip"
    nested.mkdir(parents=True)
    (nested / "poses.json").write_text((KEYPOINTS / "example.json").read_text())
    with pytest.warns(UserWarning, match=r"its sub-folders are read with recursive=True"):
        camloc.read_keypoints(tmp_path / "videos")
    assert camloc.read_keypoints(tmp_path / "videos", recursive=True)["points"].shape[0] == 3


def test_a_rolled_camera_is_warned_of():
    # The example's poses turned 40 degrees clockwise as shown (v down) about their centre,
    # six times over: their torsos lean alike, as from a phone held askew.
    points = np.tile(example_points(), (2, 1, 1))
    centre = np.nanmean(points.reshape(-1, 2), axis=0)
    a = np.radians(40.0)
    turn = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    rolled = (points - centre) @ turn.T + centre
    with pytest.warns(UserWarning, match="lean (39|4[0-9]) deg.*counterclockwise"):
        camloc.Localizer().localize(rolled)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        camloc.Localizer().localize(points)


def test_a_known_camera_aims_the_localization(cli):
    points = example_points()
    localizer = camloc.Localizer(camera_height="any")
    plain = localizer.localize(points)
    aimed = localizer.localize(points, focal_px=500.0, principal_point=[-400.0, -300.0])
    assert not np.allclose(plain["probabilities"], aimed["probabilities"])
    # As the command line gives it.
    path = KEYPOINTS / "example.json"
    _, rows = cli(
        "localize", "--input", path, "--camera-height", "any",
        "--focal-px", "500", "--principal-point", "-400,-300",
    )
    for row, probabilities in zip(rows, aimed["probabilities"]):
        expected = [row["probabilities"][f"{k:02d}"] for k in range(1, 13)]
        np.testing.assert_allclose(probabilities, expected, atol=1e-12)
    # Without a principal point nothing changes; one without a focal length is refused.
    with pytest.warns(UserWarning, match="focal_px without principal_point"):
        same = localizer.localize(points, focal_px=500.0)
    np.testing.assert_array_equal(same["probabilities"], plain["probabilities"])
    with pytest.raises(ValueError, match="principal_point needs focal_px"):
        localizer.localize(points, principal_point=[1.0, 2.0])


def test_a_person_off_the_axis_of_a_known_camera_is_not_called_rolled():
    # The example's upright poses seen by a camera turned away from them (the smallest
    # rotation taking the pelvis's ray 75 degrees off the axis, up and to the right in the
    # image): they lean in the image, with no roll. With the intrinsics the lean is measured on the poses
    # as the camera aimed at them sees them, as they are localized.
    points = np.tile(example_points()[:2], (3, 1, 1))
    f, centre = 300.0, np.array([320.0, 240.0])
    d = np.array([3.0, -2.0, 1.0]) / np.sqrt(14.0)
    v = np.cross([0.0, 0.0, 1.0], d)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    turn = np.eye(3) + k + k @ k * ((1 - d[2]) / (v @ v))
    seen = []
    for pose in points:
        rays = np.c_[(pose - pose[0]) / f, np.ones(len(pose))] @ turn.T
        seen.append(centre + f * rays[:, :2] / rays[:, 2:3])
    seen = np.array(seen)
    with pytest.warns(UserWarning, match="torsos lean"):
        camloc.Localizer().localize(seen)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        camloc.Localizer().localize(seen, focal_px=f, principal_point=centre)


def test_masked_entries_are_missing_landmarks():
    """A numpy.ma.MaskedArray's masked joints are missing (NaN), not the values under the
    mask; a sequence of which no frame was reconstructed has no lengths (NaN)."""
    points = example_points()
    masked = np.ma.masked_array(points.copy(), mask=np.zeros(points.shape, bool))
    # A wrist misplaced by 40 px under the mask (a detector's guess it marked unseen).
    masked[0, 11] = points[0, 11] + [40.0, -40.0]
    masked.mask[0, 11] = True
    missing = np.where(masked.mask, np.nan, masked.data)
    got, want = camloc.Localizer().localize(masked), camloc.Localizer().localize(missing)
    np.testing.assert_array_equal(got["label"], want["label"])
    np.testing.assert_array_equal(got["probabilities"], want["probabilities"])
    # The values under the mask, read as joints, give another answer.
    unmasked = camloc.Localizer().localize(masked.data)
    assert not np.array_equal(unmasked["probabilities"], want["probabilities"])
    rebuilt = camloc.reconstruct(masked)
    assert rebuilt["imputed"][0, 11] and rebuilt["imputed"].sum() == 1
    # A list of masked poses keeps their masks.
    listed = camloc.Localizer().localize(list(masked))
    np.testing.assert_array_equal(listed["probabilities"], want["probabilities"])
    # With a score channel, a masked joint (or one masked coordinate) is missing, and a
    # masked score is 0; a masked scores array likewise.
    scored = np.ma.masked_array(np.concatenate([points, np.ones(points.shape[:2] + (1,))], -1))
    scored[0, 11, 0] = np.ma.masked
    got = camloc.Localizer().localize(scored)
    np.testing.assert_array_equal(got["probabilities"], want["probabilities"])
    scores = np.ma.masked_array(np.ones(points.shape[:2]))
    scores[0, 11] = np.ma.masked
    got = camloc.Localizer().localize(points, scores=scores)
    np.testing.assert_array_equal(got["probabilities"], want["probabilities"])
    # Masked viewpoints are none, as NaN ones.
    azimuth = np.ma.masked_array([10.0, 20.0, 300.0, 40.0], mask=[0, 0, 1, 0])
    smoothed, _ = camloc.smooth_viewpoints(azimuth, np.full(4, 5.0))
    nan_smoothed, _ = camloc.smooth_viewpoints([10.0, 20.0, np.nan, 40.0], np.full(4, 5.0))
    np.testing.assert_array_equal(smoothed, nan_smoothed)
    with pytest.warns(UserWarning):
        empty = camloc.reconstruct(np.full((5, 15, 2), np.nan), sequence=True)
    assert np.isnan(empty["person_bone_lengths"]).all()
    with pytest.warns(UserWarning):
        given = camloc.reconstruct(
            np.full((5, 15, 2), np.nan), sequence=True, bone_lengths=LENGTHS
        )
    np.testing.assert_allclose(given["person_bone_lengths"], LENGTHS)


def test_bools_and_complex_numbers_are_refused_not_converted():
    """A bool given for a number (it would be read as 1 or 0) and complex coordinates (their
    imaginary parts would be dropped) are TypeErrors naming what they are."""
    points = example_points()
    for call, name in [
        (lambda flag: camloc.reconstruct(points, min_score=flag), "min_score"),
        (lambda flag: camloc.Localizer().localize(points, min_score=flag), "min_score"),
        (lambda flag: camloc.read_keypoints(KEYPOINTS / "example.json", min_score=flag), "min_score"),
        (lambda flag: camloc.to_bvh(np.zeros((2, 15, 3)), fps=flag), "fps"),
        (lambda flag: camloc.to_bvh(np.zeros((2, 15, 3)), unit_m=flag), "unit_m"),
    ]:
        for flag in (True, np.False_):
            with pytest.raises(TypeError, match=f"{name}: expected a number, not a bool"):
                call(flag)
        # Text, as a command line would give it, names the argument too.
        with pytest.raises(TypeError, match=f"{name}: expected a number, got str"):
            call("30")
    with pytest.raises(TypeError, match="complex"):
        camloc.Localizer().localize(points.astype(np.complex128))
    # Points as booleans or text: refused, not every pose failed or the text parsed.
    with pytest.raises(TypeError, match="points: an array of booleans"):
        camloc.Localizer().localize(points > 100)
    with pytest.raises(TypeError, match="points: an array of text"):
        camloc.reconstruct(points.astype(str))
    # Dates, durations and records convert to numbers without a word: refused too.
    for dtype, what in [("datetime64[s]", "dates"), ("timedelta64[s]", "durations")]:
        with pytest.raises(TypeError, match=f"points: an array of {what}"):
            camloc.Localizer().localize(points.astype(np.int64).astype(dtype))
    records = np.zeros(points.shape, dtype=[("v", "f8")])
    with pytest.raises(TypeError, match="points: an array of records"):
        camloc.reconstruct(records)
    # NumPy's bools are no focal length or principal point either.
    with pytest.raises(TypeError, match="focal_px: .*got a"):
        camloc.reconstruct(points, focal_px=np.bool_(True))
    with pytest.raises(TypeError, match="principal_point: two numbers"):
        camloc.reconstruct(points, focal_px=1500.0, principal_point=[True, False])
    # Scores may be visibility flags.
    flags = np.ones(points.shape[:2], dtype=bool)
    assert camloc.Localizer().localize(points, scores=flags)["label"].shape == (len(points),)
    with pytest.raises(TypeError, match="complex"):
        camloc.reconstruct(np.ma.masked_array(points.astype(np.complex64)))
    with pytest.raises(TypeError, match="complex"):
        camloc.Localizer().localize([pose + 50j for pose in points])
    with pytest.raises(TypeError, match="complex"):
        camloc.to_bvh([np.zeros((15, 3)) + 1j, np.zeros((15, 3))])
    with pytest.raises(TypeError, match="complex"):
        camloc.reconstruct(points, focal_px=1000.0, principal_point=np.array([500 + 1j, 500]))
    with pytest.raises(TypeError, match="complex"):
        camloc.reconstruct(points, focal_px=np.complex128(1000 + 5j))


def test_the_camera_height_shares_are_returned_as_the_command_line_writes_them(cli, tmp_path):
    """``camera_height_shares`` is the estimate every pose was localized under, the command
    line's ``--npz`` shares: near eye level's for a call of a few poses."""
    few = example_points()
    shares = camloc.Localizer().localize(few)["camera_height_shares"]
    assert shares.sum() == pytest.approx(1.0) and shares[1] > 0.6
    many = np.concatenate([few] * 40)
    path = tmp_path / "many.npy"
    np.save(path, many)
    code, _ = cli("localize", "--input", path, "--npz", tmp_path / "out.npz", "-q")
    assert code == 0
    want = np.load(tmp_path / "out.npz")["camera_height_shares"]
    assert np.isfinite(want).all() and want.sum() == pytest.approx(1.0)
    views = np.load(tmp_path / "out.npz")["camera_height_views"]
    # 40 copies of the same few poses: about as many views as the few, not 40 times as many.
    assert views.shape == (1,) and 0 < views[0] < 2 * len(few), views
    elevations = np.load(tmp_path / "out.npz")["camera_height_elevations_deg"]
    # Only the middle height's mean elevation is estimated.
    assert np.isnan(elevations[[0, 2]]).all() and -22.5 < elevations[1] < 45, elevations
    for got in (camloc.Localizer().localize(many), camloc.reconstruct(many)):
        np.testing.assert_allclose(got["camera_height_shares"], want, rtol=1e-12)
        np.testing.assert_allclose(got["camera_height_elevations_deg"], elevations, rtol=1e-12)
        assert got["camera_height_views"] == pytest.approx(views[0], rel=1e-12)
    eye_level = camloc.Localizer("eye-level").localize(many)
    assert np.isnan(eye_level["camera_height_shares"]).all()
    assert np.isnan(eye_level["camera_height_views"])
    assert np.isnan(eye_level["camera_height_elevations_deg"]).all()


def test_one_persons_rows_take_the_shares_of_the_whole_video():
    """``camera_height_shares`` given: a call on one person's rows localizes under the shares
    of a call on every row, as the command line estimates them once for the whole file."""
    many = np.concatenate([example_points()] * 40)
    whole = camloc.Localizer().localize(many)
    shares = whole["camera_height_shares"]
    part = many[::3]
    alone = camloc.Localizer().localize(part)
    elevations = whole["camera_height_elevations_deg"]
    given = camloc.Localizer().localize(
        part, camera_height_shares=shares, camera_height_elevations_deg=elevations
    )
    np.testing.assert_allclose(given["camera_height_shares"], shares, rtol=1e-12)
    np.testing.assert_allclose(given["camera_height_elevations_deg"], elevations, rtol=1e-12)
    # The viewpoints move toward the whole video's elevation, as the whole call's did.
    np.testing.assert_allclose(given["elevation_deg"], whole["elevation_deg"][::3], rtol=1e-12)
    shares_alone = camloc.Localizer().localize(part, camera_height_shares=shares)
    assert np.isnan(shares_alone["camera_height_elevations_deg"]).all()
    assert np.isnan(given["camera_height_views"]) and np.isfinite(alone["camera_height_views"])
    np.testing.assert_array_equal(given["label"], whole["label"][::3])
    np.testing.assert_allclose(given["probabilities"], whole["probabilities"][::3], rtol=1e-12)
    rebuilt = camloc.reconstruct(part, camera_height_shares=list(shares))
    np.testing.assert_allclose(rebuilt["camera_height_shares"], shares, rtol=1e-12)
    with pytest.raises(ValueError, match="camera_height_shares: expected three numbers"):
        camloc.Localizer().localize(part, camera_height_shares=[0.5, 0.5])
    with pytest.raises(ValueError, match="camera_height_elevations_deg: only with"):
        camloc.Localizer().localize(part, camera_height_elevations_deg=elevations)
    for bad, match in [
        ([np.nan, 95, np.nan], "expected degrees in"),
        ([0, 10, np.nan], "only the middle height's is used"),
    ]:
        with pytest.raises(ValueError, match="camera_height_elevations_deg: invalid .*" + match):
            camloc.Localizer().localize(
                part, camera_height_shares=shares, camera_height_elevations_deg=bad
            )
    for bad in ([True, False, True], np.array([np.nan, 1, np.nan]) > 0, "abc", 5):
        with pytest.raises(TypeError, match="camera_height_elevations_deg: expected three"):
            camloc.Localizer().localize(
                part, camera_height_shares=shares, camera_height_elevations_deg=bad
            )
    with pytest.raises(TypeError, match="camera_height_shares: expected three numbers.*bool"):
        camloc.Localizer().localize(part, camera_height_shares=[True, True, False])
    with pytest.raises(ValueError, match="camera_height_shares"):
        camloc.reconstruct(part, camera_height_shares=[-1.0, 1.0, 1.0])
    with pytest.raises(TypeError, match="camera_height_shares"):
        camloc.Localizer().localize(part, camera_height_shares="middle")
    # The shares replace the estimate of "from-input": with another height they contradict it.
    for height in ("any", "eye-level"):
        with pytest.raises(ValueError, match='only with camera_height="from-input"'):
            camloc.Localizer(height).localize(part, camera_height_shares=shares)
        with pytest.raises(ValueError, match='only with camera_height="from-input"'):
            camloc.reconstruct(part, camera_height=height, camera_height_shares=shares)


def test_no_camera_height_is_the_default_one():
    """``Localizer(camera_height=None)`` is the default ``"from-input"``, as ``reconstruct``'s
    ``camera_height=None`` is the localizer's own."""
    assert camloc.Localizer(camera_height=None).camera_height == "from-input"
    assert camloc.Localizer.load(
        ROOT / "fixtures" / "default-model.bin", camera_height=None
    ).camera_height == "from-input"


def test_a_model_file_given_to_the_constructor_points_to_load():
    """``Localizer(model=...)``, ``Localizer("m.bin")`` or ``Localizer(Path("m.bin"))`` (what
    a user tries first) says that ``Localizer.load`` reads model files."""
    model = str(ROOT / "fixtures" / "default-model.bin")
    for call in (
        lambda: camloc.Localizer(model=model),
        lambda: camloc.Localizer(path=model, camera_height="any"),
    ):
        with pytest.raises(TypeError, match=r"keyword argument .*Localizer\.load\(path\)"):
            call()
    with pytest.raises(ValueError, match=r"got .*default-model\.bin.*Localizer\.load\(path\)"):
        camloc.Localizer(model)
    # A path object too (it had pyo3's "cannot be converted to 'PyString'").
    with pytest.raises(TypeError, match=r"got a path .*Localizer\.load\(path\)"):
        camloc.Localizer(ROOT / "fixtures" / "default-model.bin")
    # Other wrong heights get no such hint.
    with pytest.raises(ValueError, match='got "high"$'):
        camloc.Localizer("high")
    with pytest.raises(TypeError, match="camera_height must be a str .*not int"):
        camloc.Localizer(3)
    # Loading a model and reconstructing say the same of a height that is not text.
    with pytest.raises(TypeError, match="camera_height must be a str .*not float"):
        camloc.Localizer.load(model, camera_height=1.5)
    with pytest.raises(TypeError, match="camera_height must be a str .*not int"):
        camloc.reconstruct(example_points(), camera_height=2)
    assert camloc.Localizer.load(model, camera_height=None).camera_height == "from-input"


def test_a_landmark_far_off_is_missing_as_the_command_line_says(cli, tmp_path):
    """A landmark far off the others is read as missing and filled in: ``missing`` marks it,
    as the command line's JSON and ``--npz`` do."""
    points = example_points()[:1].copy()
    wrist = camloc.LANDMARKS.index("left_wrist")
    points[0, wrist] = [5000.0, 5000.0]
    got = camloc.Localizer().localize(points)
    assert got["missing"][0, wrist] and got["missing"][0].sum() == 1
    path = tmp_path / "far.npy"
    np.save(path, points)
    code, printed = cli("localize", "--input", path, "-q")
    assert code == 0 and printed[0]["missing"] == ["left_wrist"]
    code, _ = cli("localize", "--input", path, "-q", "--npz", tmp_path / "far.npz")
    assert code == 0
    np.testing.assert_array_equal(np.load(tmp_path / "far.npz")["missing"], got["missing"])


def test_an_image_size_the_wrong_way_round_is_warned_of(tmp_path):
    # The example's person seen from the left (the check compares people seen from a side),
    # 15 times a little apart, upright in a portrait 1080 x 1920 video, as YOLO-pose files
    # (COCO-17, normalised; the face points at the head).
    names = camloc.LANDMARKS
    coco17 = ["head"] * 5 + [
        f"{side}_{joint}"
        for joint in ["shoulder", "elbow", "wrist", "hip", "knee", "ankle"]
        for side in ["left", "right"]
    ]
    points = example_points()
    for frame in range(15):
        pose = points[1]
        values = []
        for name in coco17:
            u, v = pose[names.index(name)]
            if np.isnan(u):
                values += [0.0, 0.0, 0.0]
            else:
                x, y = 3 * (u - 320) + 540 + 4 * frame, 3 * (v - 270) + 960
                values += [x / 1080, y / 1920, 0.9]
        line = "0 0.5 0.5 0.4 0.6 " + " ".join(f"{v:.6f}" for v in values)
        (tmp_path / f"clip_{frame + 1}.txt").write_text(line + "\n")
    with pytest.warns(camloc.CamlocWarning, match=r"better with the image 1080x1920 than 1920x1080"):
        camloc.read_keypoints(tmp_path, image_size=(1920, 1080))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        read = camloc.read_keypoints(tmp_path, image_size=(1080, 1920))
    assert read["points"].shape == (15, 15, 2)
