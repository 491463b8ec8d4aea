"""A video's rows given with their frame numbers (``frames=``): frames the person is missing
from, and an untracked second person in some frames, read as the command line reads the same
poses with their ``frame`` numbers (``camloc reconstruct --sequence``, ``camloc localize
--sequence``)."""

import json
import warnings

import numpy as np
import pytest

import camloc
from helpers import LENGTHS, example_points


def untracked_video():
    """(rows (N, 15, 2), frame numbers (N,), the rows of the second person): one person
    walking 3 px a frame at frames 0-11 and 17-28 (missing from 12-16), and another person
    600 px to the right at frames 4 and 20, listed before the walker there (a detector
    without a tracker)."""
    pose = example_points()[0]
    sway = np.array([[0.0, 4.0]]) * np.sin(np.linspace(0, 1, 15))[:, None]
    rows, numbers, second = [], [], []
    for t in list(range(12)) + list(range(17, 29)):
        walker = pose + [3.0 * t, 0.0] + sway * np.sin(0.5 * t)
        if t in (4, 20):
            second.append(len(rows))
            rows.append(walker + [600.0, 10.0])
            numbers.append(t)
        rows.append(walker)
        numbers.append(t)
    return np.array(rows), np.array(numbers), second


def write_keypoints(path, rows, numbers):
    poses = [
        {"id": f"pose-{i}", "frame": int(f), "landmarks": dict(zip(camloc.LANDMARKS, p.tolist()))}
        for i, (p, f) in enumerate(zip(rows, numbers))
    ]
    path.write_text(json.dumps({"format": "camloc-keypoints", "version": 1, "poses": poses}))
    return path


def test_frame_numbers_give_the_command_line_s_sequence(tmp_path, cli):
    rows, numbers, second = untracked_video()
    path = write_keypoints(tmp_path / "video.json", rows, numbers)
    _, expected = cli("reconstruct", "--input", path, "--sequence", "--camera-height", "any")
    by_id = {o["id"]: o for o in expected}
    with pytest.warns(UserWarning, match="2 row\\(s\\) share their frame number"):
        got = camloc.reconstruct(rows, sequence=True, frames=numbers, camera_height="any")
    assert got["left_out_of_sequence"].tolist() == [i in second for i in range(len(rows))]
    for i in range(len(rows)):
        want = by_id[f"pose-{i}"]
        assert want.get("left_out_of_sequence", False) == (i in second)
        landmarks = [want["landmarks_m"][name] for name in camloc.LANDMARKS]
        np.testing.assert_allclose(got["points3d"][i], landmarks, rtol=1e-9, atol=1e-12)
    # The second person is not placed in the world; the walker is, in every frame.
    assert np.isnan(got["world_points3d"][second]).all()
    assert np.isfinite(np.delete(got["world_points3d"], second, axis=0)).all()
    # The same rows as consecutive frames (no numbers) are another sequence: the gap is no
    # longer a break between runs, and the second person's rows are frames of their own.
    consecutive = camloc.reconstruct(rows, sequence=True, camera_height="any")
    assert not np.allclose(consecutive["points3d"], got["points3d"])

    _, expected = cli("localize", "--input", path, "--sequence", "--camera-height", "any")
    by_id = {o["id"]: o for o in expected}
    localizer = camloc.Localizer(camera_height="any")
    with pytest.warns(UserWarning, match="share their frame number"):
        smoothed = localizer.localize(rows, sequence=True, frames=numbers)
    for i in range(len(rows)):
        want = by_id[f"pose-{i}"]
        assert bool(smoothed["left_out_of_sequence"][i]) == want.get("left_out_of_sequence", False)
        assert smoothed["smoothed_label"][i] == want["smoothed_label"]
        if i in second:
            assert np.isnan(smoothed["smoothed_azimuth_deg"][i])
        else:
            for key in ["smoothed_azimuth_deg", "smoothed_elevation_deg"]:
                np.testing.assert_allclose(smoothed[key][i], want[key], atol=1e-4)


def test_bad_frame_numbers_are_refused():
    rows, numbers, _ = untracked_video()
    with pytest.raises(ValueError, match="frames is for sequence=True"):
        camloc.reconstruct(rows, frames=numbers)
    with pytest.raises(ValueError, match="frames must not decrease"):
        camloc.reconstruct(rows, sequence=True, frames=numbers[::-1])
    with pytest.raises(ValueError, match="one number per row \\(26\\), got 25"):
        camloc.Localizer().localize(rows, sequence=True, frames=numbers[:-1])
    with pytest.raises(ValueError, match="whole numbers from 0 to 2\\^53, got 0.5 at 0"):
        camloc.reconstruct(rows, sequence=True, frames=numbers + 0.5)
    masked = np.ma.masked_array(numbers, mask=np.arange(len(numbers)) == 3)
    with pytest.raises(ValueError, match="got NaN \\(masked\\?\\) at 3"):
        camloc.reconstruct(rows, sequence=True, frames=masked)
    # Booleans and text are no frame numbers (NumPy would read them as 0/1 and numbers).
    for given in (numbers > 5, numbers.astype(str), numbers.astype(np.float16)):
        with pytest.raises(TypeError, match="frames must be frame numbers"):
            camloc.reconstruct(rows, sequence=True, frames=given)
    # read_keypoints' frames of an input without numbers (all -1) are consecutive rows.
    same = camloc.reconstruct(rows[:4], sequence=True, frames=np.full(4, -1))
    np.testing.assert_array_equal(
        same["points3d"], camloc.reconstruct(rows[:4], sequence=True)["points3d"]
    )


def test_long_sequences_and_large_files_have_limits_that_can_be_raised(tmp_path):
    """A sequence longer than sequence_max_rows (the command line's --sequence-max-poses) is
    refused before any work; a text file longer than max_input_bytes too."""
    rows, _, _ = untracked_video()
    with pytest.raises(ValueError, match="more than sequence_max_rows \\(10\\)"):
        camloc.reconstruct(rows, sequence=True, sequence_max_rows=10)
    assert camloc.reconstruct(rows[:4], sequence=True, sequence_max_rows=4)["points3d"].shape == (
        4, 15, 3)
    path = write_keypoints(tmp_path / "video.json", rows, np.arange(len(rows)))
    with pytest.raises(camloc.CamlocError, match="max_input_bytes"):
        camloc.read_keypoints(path, max_input_bytes=100)
    assert len(camloc.read_keypoints(path, max_input_bytes=10**9)["ids"]) == len(rows)
    for none in (0, -1):
        with pytest.raises(ValueError, match="max_input_bytes: expected a whole number >= 1"):
            camloc.read_keypoints(path, max_input_bytes=none)


def test_other_people_s_rows_leave_the_person_s_3d_as_it_is():
    """Rows of other people in the person's frames (an untracked detector's crowd) are left out
    and change nothing of the person's sequence: they had counted as missing frames, split the
    sequence into runs and moved the person's 3D by up to 16 cm."""
    pose = example_points()[0]
    rng = np.random.default_rng(7)
    walker = np.stack([pose + [3.0 * t, 0.0] + rng.normal(0, 0.5, (15, 2)) for t in range(20)])
    rows, numbers, mine = [], [], []
    for t in range(20):
        people = [walker[t], walker[t] + [700.0, 5.0], walker[t] + [-700.0, -5.0]]
        for k in rng.permutation(3):
            if k == 0:
                mine.append(len(rows))
            rows.append(people[k])
            numbers.append(t)
    # The person is the first pose of the first frame.
    first = int(np.argmax(np.array(numbers) == 0))
    rows[first], rows[mine[0]] = rows[mine[0]], rows[first]
    mine[0] = first
    with pytest.warns(UserWarning, match="share their frame number"):
        crowd = camloc.reconstruct(np.array(rows), sequence=True, frames=np.array(numbers),
                                   camera_height="any")
    alone = camloc.reconstruct(walker, sequence=True, camera_height="any")
    assert not crowd["left_out_of_sequence"][mine].any()
    np.testing.assert_allclose(crowd["points3d"][mine], alone["points3d"], atol=1e-9)


def test_people_of_an_untracked_openpose_folder_are_followed(tmp_path):
    """OpenPose without tracking numbers people by their order in each frame: a bystander
    listed before the walker in a frame is not the walker's person there (``read_keypoints``
    follows each person by where it is, as ``camloc --sequence`` does)."""
    rows, numbers, second = untracked_video()
    body25 = {"head": 0, "neck": 1, "right_shoulder": 2, "right_elbow": 3, "right_wrist": 4,
              "left_shoulder": 5, "left_elbow": 6, "left_wrist": 7, "pelvis": 8,
              "right_hip": 9, "right_knee": 10, "right_ankle": 11, "left_hip": 12,
              "left_knee": 13, "left_ankle": 14}
    frames = {}
    for i, (pose, t) in enumerate(zip(rows, numbers)):
        keypoints = np.zeros((25, 3))
        for name, point in zip(camloc.LANDMARKS, pose):
            keypoints[body25[name]] = [point[0], point[1], 0.9]
        frames.setdefault(int(t), []).append(
            {"person_id": [-1], "pose_keypoints_2d": keypoints.ravel().tolist()})
    for t, people in frames.items():
        (tmp_path / f"walk_{t:012d}_keypoints.json").write_text(
            json.dumps({"version": 1.3, "people": people}))
    read = camloc.read_keypoints(tmp_path)
    bystander = read["points"][:, 0, 0] > rows[:, 0, 0].min() + 400
    assert bystander.sum() == len(second)
    # Listed first at frames 4 and 20, the bystander is never person 0, the walker always
    # (the bystander, unseen for 16 frames in between, is a new person at frame 20).
    assert (read["persons"][bystander] != 0).all()
    assert (read["persons"][~bystander] == 0).all()
    assert {s.rsplit("people", 1)[1] for s in np.array(read["sources"])[bystander]} == {"[0]"}


def test_a_sequence_warns_of_landmarks_filled_in_most_of_its_rows():
    """A landmark missing in most rows of a sequence, or for half a second in a row, is named in
    a ``CamlocWarning`` with its count (its 3D is the basis's guess), as the command line names
    it per person, and a limb it hides in every row is named as the length prior's guess; one
    missing now and then is not."""
    pose = example_points()[0]
    rows = np.stack([pose + [4.0 * t, 0.0] for t in range(16)])
    wrist = camloc.LANDMARKS.index("left_wrist")
    ankle = camloc.LANDMARKS.index("right_ankle")
    rows[:, wrist] = np.nan
    rows[::8, ankle] = np.nan
    with pytest.warns(
        camloc.CamlocWarning,
        match=r"of the 16 reconstructed rows: left_wrist in 16 \(for 16 frames from frame 0\); "
        r"seen in no frame, the lengths of the left forearm are the length prior's guess$",
    ):
        got = camloc.reconstruct(rows, sequence=True)
    assert got["imputed"][:, wrist].all() and got["imputed"][::8, ankle].all()
    # With the lengths given, the hidden forearm's length is not the prior's.
    with pytest.warns(
        camloc.CamlocWarning,
        match=r"of the 16 reconstructed rows: left_wrist in 16 \(for 16 frames from frame 0\)$",
    ):
        camloc.reconstruct(rows, sequence=True, bone_lengths=LENGTHS)
    # Row by row, the rows with landmarks filled in are counted, the most filled named.
    with pytest.warns(
        camloc.CamlocWarning,
        match=r"16 of 16 poses have landmarks filled in, not seen \(most often left_wrist in 16, "
        r"right_ankle in 2\)",
    ):
        camloc.reconstruct(rows)
    # 16 rows in a row of 80 (a fifth): named at 30 frames a second (half a second is 15
    # rows), not at 60 (30 rows).
    rows = np.stack([pose + [2.0 * t, 0.0] for t in range(80)])
    knee = camloc.LANDMARKS.index("right_knee")
    rows[30:46, knee] = np.nan
    with pytest.warns(camloc.CamlocWarning, match=r"right_knee in 16 \(for 16 frames from frame 30\)$"):
        camloc.reconstruct(rows, sequence=True, fps=30)
    with warnings.catch_warnings():
        warnings.simplefilter("error", camloc.CamlocWarning)
        camloc.reconstruct(rows, sequence=True, fps=60)
