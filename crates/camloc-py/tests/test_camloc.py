"""Tests of the camloc Python package: answers equal the `camloc` command line's on the
fixtures, shapes and dtypes, missing joints, bad input, a 100k-pose batch (the package as
users call it, sequences, warnings and hostile input: test_usage.py).

The command-line comparisons run the `camloc` binary of the `cli` fixture (conftest.py).
"""

import json
import shutil
import threading
import warnings

import numpy as np
import pytest

import camloc
from helpers import KEYPOINTS, LENGTHS, ROOT, SAMPLES, example_points


# Inputs as (path, command-line options, the same options for read_keypoints).
CLI_INPUTS = [
    (KEYPOINTS / "example.json", [], {}),
    (KEYPOINTS / "partial.json", [], {}),
    (KEYPOINTS / "single_pose.json", [], {}),
    (KEYPOINTS / "tiny_lsp.csv", [], {}),
    (KEYPOINTS / "tiny_lsp.csv", ["--lsp-invisible", "use"], {"lsp_invisible": "use"}),
    (KEYPOINTS / "tiny_coco.json", [], {}),
    (KEYPOINTS / "tiny_coco_results.json", [], {}),
    (SAMPLES / "camloc15.npy", [], {}),
    (SAMPLES / "h36m17_scores.npy", ["--layout", "h36m17"], {"layout": "h36m17"}),
    (
        SAMPLES / "h36m17_scores.npy",
        ["--layout", "h36m17", "--min-score", "0.1"],
        {"layout": "h36m17", "min_score": 0.1},
    ),
    (SAMPLES / "mmpose.json", [], {}),
    (SAMPLES / "mpii.json", [], {}),
    (SAMPLES / "mediapipe.json", ["--image-size", "640,480"], {"image_size": (640, 480)}),
    (SAMPLES / "openpose_coco18_000000000007_keypoints.json", [], {}),
    (SAMPLES / "openpose", [], {}),
]


@pytest.mark.parametrize(
    "path, options, read_options",
    CLI_INPUTS,
    ids=[" ".join([path.name, *options]) for path, options, _ in CLI_INPUTS],
)
def test_localize_equals_the_command_line(cli, localizer, path, options, read_options):
    code, expected = cli("localize", "--input", path, *options)
    read = camloc.read_keypoints(path, **read_options)
    got = localizer.localize(read["points"])
    assert len(expected) == len(read["ids"]) == len(got["error"]) > 0
    assert code == (1 if any(e is not None for e in got["error"]) else 0)
    for i, want in enumerate(expected):
        assert read["ids"][i] == want["id"]
        assert read["sources"][i] == want["source"]
        if "error" in want:
            assert got["error"][i] == want["error"]
            assert got["label"][i] == 0 and np.isnan(got["probabilities"][i]).all()
            assert np.isnan(got["azimuth_deg"][i]) and np.isnan(got["uncertainty_deg"][i])
            continue
        assert got["error"][i] is None
        assert got["label"][i] == want["label"]
        assert got["folded_label"][i] == want["folded_label"]
        assert got["probability"][i] == pytest.approx(want["probability"], rel=1e-12)
        probabilities = [want["probabilities"][f"{c['label']:02}"] for c in localizer.cameras]
        np.testing.assert_allclose(got["probabilities"][i], probabilities, rtol=1e-12)
        for key in ("azimuth_deg", "elevation_deg", "uncertainty_deg"):
            assert got[key][i] == pytest.approx(want[key], rel=1e-12, abs=1e-9), key
        derived = [camloc.LANDMARKS[j] for j in np.flatnonzero(read["derived"][i])]
        assert derived == want["derived"]
        missing = [camloc.LANDMARKS[j] for j in np.flatnonzero(np.isnan(read["points"][i, :, 0]))]
        assert missing == want["missing"]


# The arrays of `localize --npz`: name, dtype and number of dimensions (docs/cli.md).
NPZ_ARRAYS = {
    **dict.fromkeys(["label", "folded_label"], (np.uint16, 1)),
    "probabilities": (np.float64, 2),
    **dict.fromkeys(["azimuth_deg", "elevation_deg", "uncertainty_deg"], (np.float64, 1)),
    "failed": (np.bool_, 1),
    **dict.fromkeys(["missing", "derived"], (np.bool_, 2)),
    **dict.fromkeys(["frame", "person"], (np.int64, 1)),
    "id_utf8": (np.uint8, 1),
    "id_end": (np.uint64, 1),
    "camera_height_shares": (np.float64, 1),
    "camera_height_elevations_deg": (np.float64, 1),
    "camera_height_views": (np.float64, 1),
}


def mixed_poses(folder):
    """The example poses, one without its head under an id JSON escapes, one without a torso."""
    doc = json.loads((KEYPOINTS / "example.json").read_text())
    headless = dict(doc["poses"][1], id='é "quoted" \\ 人 🙂')
    headless["landmarks"] = {k: v for k, v in headless["landmarks"].items() if k != "head"}
    doc["poses"] += [headless, {"id": "no torso", "landmarks": {"head": [10.0, 20.0]}}]
    path = folder / "mixed.json"
    path.write_text(json.dumps(doc))
    return path


@pytest.mark.parametrize("input_name", ["mixed", "openpose", "camloc15.npy"])
def test_localize_npz_loads_without_pickle_and_equals_the_json_of_the_same_run(
    cli, tmp_path, input_name
):
    path = mixed_poses(tmp_path) if input_name == "mixed" else SAMPLES / input_name
    out = tmp_path / "views.npz"
    _, expected = cli("localize", "--input", path, "--npz", out)
    with np.load(out, allow_pickle=False) as npz:
        got = dict(npz)
    n = len(expected)
    assert set(got) == set(NPZ_ARRAYS)
    for name, (dtype, ndim) in NPZ_ARRAYS.items():
        assert got[name].dtype == dtype and got[name].ndim == ndim, name
        assert (
            name
            in ("id_utf8", "camera_height_shares", "camera_height_elevations_deg", "camera_height_views")
            or got[name].shape[0] == n
        ), name
    # The shares the run was localized under: near eye level's for these few poses.
    assert got["camera_height_shares"].shape == (3,)
    shares = got["camera_height_shares"]
    assert abs(shares.sum() - 1) < 1e-12 and shares[1] > 0.6, shares
    assert got["probabilities"].shape == (n, 12) and got["missing"].shape == (n, 15)
    # The ids as docs/cli.md decodes them.
    end = got["id_end"]
    raw = got["id_utf8"].tobytes()
    ids = [raw[a:b].decode() for a, b in zip(np.r_[0, end[:-1]], end)]
    assert ids == [want["id"] for want in expected]
    failures = 0
    for i, want in enumerate(expected):
        assert got["frame"][i] == want.get("frame", -1)
        assert got["person"][i] == want.get("person", -1)
        if "error" in want:
            failures += 1
            assert got["failed"][i] and got["label"][i] == 0 and got["folded_label"][i] == 0
            assert np.isnan(got["probabilities"][i]).all() and np.isnan(got["azimuth_deg"][i])
            continue
        assert not got["failed"][i]
        assert got["label"][i] == want["label"]
        assert got["folded_label"][i] == want["folded_label"]
        # Python parses JSON numbers correctly rounded: the values are equal, not close.
        probabilities = [want["probabilities"][f"{k:02}"] for k in range(1, 13)]
        np.testing.assert_array_equal(got["probabilities"][i], probabilities)
        assert got["probabilities"][i].max() == want["probability"]
        for key in ("azimuth_deg", "elevation_deg", "uncertainty_deg"):
            assert got[key][i] == want[key], key
        for key in ("missing", "derived"):
            assert [camloc.LANDMARKS[j] for j in np.flatnonzero(got[key][i])] == want[key], key
    assert failures == (1 if input_name == "mixed" else 0)


@pytest.mark.parametrize(
    "camera, lifter", [("opt", True), ("classified", True), ("hybrid", True), ("hybrid", False)]
)
def test_reconstruct_equals_the_command_line(cli, camera, lifter):
    """With the embedded model both use the embedded depth lifter; ``lifter=False``
    reconstructs without it, as ``--no-lifter`` does, and so does another model passed in."""
    path = KEYPOINTS / "example.json"
    options = [] if lifter else ["--no-lifter"]
    _, expected = cli("reconstruct", "--input", path, "--camera", camera, *options)
    if lifter:
        got = camloc.reconstruct(example_points(), camera=camera)
    else:
        got = camloc.reconstruct(example_points(), camera=camera, lifter=False)
    assert got["camera"] == camera
    for i, want in enumerate(expected):
        assert got["error"][i] is None
        landmarks = [want["landmarks_m"][name] for name in camloc.LANDMARKS]
        np.testing.assert_allclose(got["points3d"][i], landmarks, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(got["rotation"][i], want["camera"]["rotation"], atol=1e-12)
        assert got["scale"][i] == pytest.approx(want["camera"]["scale"], rel=1e-12)
        np.testing.assert_allclose(got["translation"][i], want["camera"]["translation"], atol=1e-9)
        assert got["projection_error"][i] == pytest.approx(want["projection_error"], rel=1e-9)
        assert got["label"][i] == (want["classified_label"] or 0)
        for key in ("probability", "azimuth_deg", "elevation_deg"):
            if want["classified_label"] is None:
                assert key not in want and np.isnan(got[key][i])
            else:
                assert got[key][i] == pytest.approx(want[key], rel=1e-12)




def test_a_lifter_file_is_the_command_line_s_lifter_file(cli):
    """``lifter=PATH`` reconstructs with that lifter, as ``--lifter FILE`` does: the embedded
    lifter of CMU's placement alone gives the example's detector poses other 3D than the
    embedded pair; a file that is no lifter is an error naming it."""
    path = KEYPOINTS / "example.json"
    own = KEYPOINTS.parent / "default-lifter.bin"
    _, expected = cli("reconstruct", "--input", path, "--lifter", own)
    got = camloc.reconstruct(example_points(), lifter=own)
    default = camloc.reconstruct(example_points())
    for i, want in enumerate(expected):
        landmarks = [want["landmarks_m"][name] for name in camloc.LANDMARKS]
        np.testing.assert_allclose(got["points3d"][i], landmarks, rtol=1e-9, atol=1e-12)
    assert not np.allclose(got["points3d"], default["points3d"])
    with pytest.raises(Exception, match="default-model.bin"):
        camloc.reconstruct(example_points(), lifter=KEYPOINTS.parent / "default-model.bin")


def test_proportions_options_equal_the_command_line(cli, tmp_path):
    """Given bone lengths (as a mapping, a list or a file), a focal length and a sequence give
    what the command line gives."""
    path = KEYPOINTS / "example.json"
    lengths_file = tmp_path / "lengths.json"
    named = dict(zip(camloc.BONE_KEYS, LENGTHS))
    lengths_file.write_text(json.dumps({"lengths": named}))
    options = ["--bone-lengths", lengths_file, "--focal-px", "900", "--principal-point", "320,240"]
    _, expected = cli("reconstruct", "--input", path, *options)
    for given in [named, LENGTHS, lengths_file, str(lengths_file)]:
        got = camloc.reconstruct(
            example_points(), bone_lengths=given, focal_px=900.0, principal_point=(320, 240)
        )
        for i, want in enumerate(expected):
            landmarks = [want["landmarks_m"][name] for name in camloc.LANDMARKS]
            np.testing.assert_allclose(got["points3d"][i], landmarks, rtol=1e-9, atol=1e-12)
            np.testing.assert_allclose(got["bone_lengths"][i], LENGTHS, rtol=1e-9)
            np.testing.assert_allclose(
                got["translation_m"][i], want["perspective"]["translation_m"], rtol=1e-9
            )
            assert got["focal_px"][i] == 900.0
            np.testing.assert_allclose(got["principal_point"][i], [320, 240], rtol=1e-12)
    # A value that is not a number is named (it was a bare TypeError).
    with pytest.raises(ValueError, match='"torso" must be a number of metres, got str'):
        camloc.reconstruct(example_points(), bone_lengths={**named, "torso": "0.5"})
    # A bool is not a length (True read as 1.0 made limbs of 1 m without a word).
    for given in ([True] * 14, dict.fromkeys(named, True), np.ones(14, bool)):
        with pytest.raises(TypeError, match="a length must be a number of metres, not a bool"):
            camloc.reconstruct(example_points(), bone_lengths=given)
    # The command line's --bone-lengths-out files (with "person") are read back.
    with_person = tmp_path / "person.json"
    text = camloc.bone_lengths_json(named).replace('"unit": "m",', '"unit": "m", "person": "person 3 of a.npy",')
    with_person.write_text(text)
    np.testing.assert_allclose(
        camloc.reconstruct(example_points(), bone_lengths=with_person)["bone_lengths"][0],
        [named[k] for k in camloc.BONE_KEYS],
        rtol=1e-9,
    )
    # Every missing key is named; a path given as bytes is not read as numbers.
    with pytest.raises(ValueError, match='missing key\\(s\\) "left_pelvis_hip", "torso"'):
        camloc.reconstruct(
            example_points(),
            bone_lengths={k: v for k, v in named.items() if k not in ("left_pelvis_hip", "torso")},
        )
    for given in (bytes(str(lengths_file), "utf-8"), bytearray(b"\x01" * 14)):
        with pytest.raises(TypeError, match="bytes are neither a path nor lengths"):
            camloc.reconstruct(example_points(), bone_lengths=given)
    with pytest.raises(ValueError, match=r"^bone_lengths: right thigh = -0.4 m"):
        camloc.reconstruct(example_points(), bone_lengths={**named, "right_thigh": -0.4})
    # A short person's lengths in feet pass each limb's range, not the height they make.
    with pytest.raises(ValueError, match="look like feet: divide by 3.28"):
        camloc.reconstruct(
            example_points(), bone_lengths={k: 0.8 * v / 0.3048 for k, v in named.items()}
        )
    with pytest.raises(ValueError, match="got 1e-300"):
        camloc.reconstruct(example_points(), focal_px=1e-300)
    _, expected = cli("reconstruct", "--input", path, "--sequence")
    got = camloc.reconstruct(example_points(), sequence=True)
    assert got["person_bone_lengths"].shape == (14,)
    for i, want in enumerate(expected):
        landmarks = [want["landmarks_m"][name] for name in camloc.LANDMARKS]
        np.testing.assert_allclose(got["points3d"][i], landmarks, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(got["bone_lengths"][i], got["person_bone_lengths"], rtol=1e-9)
        # Without a focal length: the camera at the distance the refinement estimated, if
        # finite.
        if "perspective" in want:
            for key in ["translation_m", "focal_px", "principal_point"]:
                np.testing.assert_allclose(got[key][i], want["perspective"][key], rtol=1e-9)
        else:
            assert np.isnan(got["translation_m"][i]).all() and np.isnan(got["focal_px"][i])
    # A faster video keeps the smoothing's windows in time, as --fps does.
    _, expected = cli("reconstruct", "--input", path, "--sequence", "--fps", "120")
    fast = camloc.reconstruct(example_points(), sequence=True, fps=120)
    for i, want in enumerate(expected):
        landmarks = [want["landmarks_m"][name] for name in camloc.LANDMARKS]
        np.testing.assert_allclose(fast["points3d"][i], landmarks, rtol=1e-9, atol=1e-12)
    assert not np.allclose(fast["points3d"], got["points3d"])
    with pytest.raises(ValueError, match="frame rate"):
        camloc.reconstruct(example_points(), sequence=True, fps=0)


def test_a_person_height_scales_the_answer_as_the_command_line_does(cli):
    """person_height gives the command line's --person-height answer: legs of 0.491 of the
    height, the same image, and a sequence's lengths and world scaled alike."""
    path = KEYPOINTS / "example.json"
    _, expected = cli("reconstruct", "--input", path, "--person-height", "1.9")
    got = camloc.reconstruct(example_points(), person_height=1.9)
    own = camloc.reconstruct(example_points())

    def legs(lengths):
        return (lengths[..., 1] + lengths[..., 2] + lengths[..., 4] + lengths[..., 5]) / 2

    np.testing.assert_allclose(legs(got["bone_lengths"]) / 0.491, 1.9, rtol=1e-12)
    np.testing.assert_allclose(got["projection_error"], own["projection_error"], rtol=1e-12)
    # The same image: the scale (image units per metre) falls as the person grows.
    np.testing.assert_allclose(
        got["scale"] * legs(got["bone_lengths"]),
        own["scale"] * legs(own["bone_lengths"]),
        rtol=1e-9,
    )
    for i, want in enumerate(expected):
        landmarks = [want["landmarks_m"][name] for name in camloc.LANDMARKS]
        np.testing.assert_allclose(got["points3d"][i], landmarks, rtol=1e-9, atol=1e-12)
    seq = camloc.reconstruct(example_points(), sequence=True, person_height=0.9)
    own = camloc.reconstruct(example_points(), sequence=True)
    factor = 0.9 / (legs(own["person_bone_lengths"]) / 0.491)
    np.testing.assert_allclose(
        seq["person_bone_lengths"], own["person_bone_lengths"] * factor, rtol=1e-9
    )
    np.testing.assert_allclose(seq["points3d"], own["points3d"] * factor, rtol=1e-9, atol=1e-12)
    with pytest.raises(ValueError, match="175 cm is 1.75 m"):
        camloc.reconstruct(example_points(), person_height=175)
    with pytest.raises(ValueError, match="bone lengths given already give the size"):
        camloc.reconstruct(example_points(), person_height=1.7, bone_lengths=LENGTHS)
    for flag in (True, np.True_):
        with pytest.raises(TypeError, match="person_height: expected a number, not a bool"):
            camloc.reconstruct(example_points(), person_height=flag)


@pytest.mark.parametrize(
    "options",
    [
        {"bone_lengths": LENGTHS[:13]},
        {"bone_lengths": [45.0] * 14},
        {"bone_lengths": {"torso": 0.5}},
        {"bone_lengths": {**dict(zip(["a"], [1.0]))}},
        {"focal_px": -1.0},
        {"focal_px": float("nan")},
        {"principal_point": (1.0, 2.0)},
    ],
)
def test_bad_proportions_options_are_value_errors(options):
    with pytest.raises(ValueError):
        camloc.reconstruct(example_points(), **options)


@pytest.mark.parametrize("min_score", [0.0, 0.1])
def test_raw_arrays_equal_the_command_line_on_the_same_file(cli, localizer, min_score):
    path = SAMPLES / "h36m17_scores.npy"
    _, expected = cli(
        "localize", "--input", path, "--layout", "h36m17", "--min-score", min_score
    )
    got = localizer.localize(np.load(path), layout="h36m17", min_score=min_score)
    np.testing.assert_array_equal(got["label"], [e["label"] for e in expected])
    for row, want in zip(got["probabilities"], expected):
        probabilities = [want["probabilities"][f"{c['label']:02}"] for c in localizer.cameras]
        np.testing.assert_allclose(row, probabilities, rtol=1e-12)


def test_raw_h36m_array_gives_the_labels_of_the_same_poses_in_camloc_json(localizer):
    # samples/h36m17_scores.npy holds the poses of example.json in the Human3.6M layout
    # (fixtures/keypoints/README.md), with a score channel.
    array = np.load(SAMPLES / "h36m17_scores.npy")
    assert array.shape == (3, 17, 3)
    reference = localizer.localize(example_points())
    with_channel = localizer.localize(array, layout="h36m17")
    separate = localizer.localize(array[..., :2], layout="h36m17", scores=array[..., 2])
    from_file = camloc.read_keypoints(SAMPLES / "h36m17_scores.npy", layout="h36m17")
    via_file = localizer.localize(from_file["points"])
    for got in (with_channel, separate, via_file):
        assert got["error"] == [None] * 3
        np.testing.assert_array_equal(got["label"], reference["label"])
    np.testing.assert_array_equal(with_channel["probabilities"], separate["probabilities"])
    np.testing.assert_array_equal(with_channel["probabilities"], via_file["probabilities"])


def test_a_separate_score_out_of_range_is_not_taken_for_a_third_coordinate(localizer):
    # The hint about (N, J, 3) arrays holding x, y, score is for a third channel; scores
    # given on their own (a simulated user's 1.5) get none, percentages still theirs.
    points = example_points()
    errors = localizer.localize(points, scores=np.full((3, 15), 1.5))["error"]
    assert all("score 1.5 is outside [0, 1]" in e for e in errors), errors
    assert not any("(N, J, 3)" in e for e in errors), errors
    percent = localizer.localize(points, scores=np.full((3, 15), 90.0))["error"]
    assert all("divide them by 100" in e for e in percent), percent
    channel = np.concatenate([points, np.full((3, 15, 1), 1.5)], axis=-1)
    assert all("(N, J, 3)" in e for e in localizer.localize(channel)["error"])


def test_min_score_drops_weak_joints_as_the_reader_does(alone):
    # Pose 1's right wrist scores 0.05 in the sample (fixtures/keypoints/README.md).
    array = np.load(SAMPLES / "h36m17_scores.npy")
    raw = alone.localize(array, layout="h36m17", min_score=0.1)
    read = camloc.read_keypoints(SAMPLES / "h36m17_scores.npy", layout="h36m17", min_score=0.1)
    assert np.isnan(read["points"][1, camloc.LANDMARKS.index("right_wrist")]).all()
    np.testing.assert_array_equal(
        raw["probabilities"], alone.localize(read["points"])["probabilities"]
    )
    # At the default min_score the weak wrist is used as detected, and said to be.
    weak = r"1 of the \d+ landmarks \(\d+\.\d%\) of the first 3 poses score below 0\.3"
    with pytest.warns(camloc.CamlocWarning, match=weak):
        full = alone.localize(array, layout="h36m17")
    with pytest.warns(camloc.CamlocWarning, match=weak):
        camloc.read_keypoints(SAMPLES / "h36m17_scores.npy", layout="h36m17")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        alone.localize(array, layout="h36m17", min_score=0.3)
        strong = array.copy()
        strong[..., 2] = 0.9
        alone.localize(strong, layout="h36m17")
    assert not np.array_equal(raw["probabilities"][1], full["probabilities"][1])
    np.testing.assert_array_equal(raw["probabilities"][[0, 2]], full["probabilities"][[0, 2]])
    # A threshold above every score is warned of (it had given all-NaN points without a word).
    with pytest.warns(camloc.CamlocWarning, match="none of the 3 poses has a landmark at min_score 30"):
        camloc.read_keypoints(SAMPLES / "h36m17_scores.npy", layout="h36m17", min_score=30)


def test_shapes_and_dtypes(alone):
    points = example_points()
    got = alone.localize(points)
    assert got["label"].shape == (3,) and got["label"].dtype == np.int64
    assert got["folded_label"].shape == (3,) and got["folded_label"].dtype == np.int64
    assert got["probability"].shape == (3,) and got["probability"].dtype == np.float64
    assert got["probabilities"].shape == (3, 12) and got["probabilities"].dtype == np.float64
    np.testing.assert_allclose(got["probabilities"].sum(axis=1), 1.0, rtol=1e-12)
    np.testing.assert_array_equal(got["probability"], got["probabilities"].max(axis=1))
    np.testing.assert_array_equal(got["label"], got["probabilities"].argmax(axis=1) + 1)
    for key in ("azimuth_deg", "elevation_deg", "uncertainty_deg"):
        assert got[key].shape == (3,) and got[key].dtype == np.float64
    assert ((got["azimuth_deg"] >= 0) & (got["azimuth_deg"] < 360)).all()
    assert ((got["elevation_deg"] >= -90) & (got["elevation_deg"] <= 90)).all()
    assert isinstance(got["error"], list) and got["error"] == [None] * 3
    assert [c["label"] for c in alone.cameras] == list(range(1, 13))
    assert alone.cameras[0]["rotation"].shape == (3, 3)

    one = alone.localize(points[1])
    assert one["label"].shape == () and one["probabilities"].shape == (12,)
    assert one["label"] == got["label"][1] and one["error"] is None
    np.testing.assert_array_equal(one["probabilities"], got["probabilities"][1])

    empty = alone.localize(np.zeros((0, 15, 2)))
    assert empty["label"].shape == (0,) and empty["probabilities"].shape == (0, 12)
    assert empty["error"] == []
    # No estimate (no poses, or none with a torso): NaN views beside the NaN shares.
    for none in (np.zeros((0, 15, 2)), np.full((3, 15, 2), np.nan), []):
        unseen = camloc.Localizer().localize(none)
        assert np.isnan(unseen["camera_height_views"]), unseen["camera_height_views"]
        assert np.isnan(unseen["camera_height_shares"]).all()
        unsolved = camloc.reconstruct(none)
        assert np.isnan(unsolved["camera_height_views"])
        assert np.isnan(unsolved["camera_height_shares"]).all()

    rec = camloc.reconstruct(points)
    assert rec["points3d"].shape == (3, 15, 3) and rec["points3d"].dtype == np.float64
    assert rec["rotation"].shape == (3, 3, 3) and rec["translation"].shape == (3, 2)
    assert rec["scale"].shape == rec["projection_error"].shape == rec["label"].shape == (3,)
    # The default camera is hybrid: it classifies each pose's camera as the alone does.
    np.testing.assert_array_equal(rec["label"], got["label"])
    np.testing.assert_array_equal(camloc.reconstruct(points, camera="opt")["label"], 0)
    for r in rec["rotation"]:
        np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-9)
    assert camloc.reconstruct(points[0])["points3d"].shape == (15, 3)

    read = camloc.read_keypoints(KEYPOINTS / "example.json")
    assert read["points"].shape == (3, 15, 2) and read["points"].dtype == np.float64
    assert read["derived"].shape == (3, 15) and read["derived"].dtype == np.bool_
    assert read["frames"].dtype == np.int64 and list(read["frames"]) == [-1] * 3
    assert read["file_errors"] == []


def test_other_dtypes_lists_and_strided_arrays_are_converted(localizer):
    points = example_points()
    reference = localizer.localize(points)
    fortran = np.asfortranarray(points)
    strided = np.repeat(points, 2, axis=0)[::2]
    assert not strided.flags.c_contiguous
    for variant in (fortran, strided, points.tolist()):
        got = localizer.localize(variant)
        np.testing.assert_array_equal(got["probabilities"], reference["probabilities"])
    as_float32 = localizer.localize(points.astype(np.float32))
    np.testing.assert_array_equal(as_float32["label"], reference["label"])
    as_int = localizer.localize(np.round(points).astype(np.int32))
    assert as_int["error"] == [None] * 3


def test_nan_marks_missing_joints(localizer):
    points = np.repeat(example_points(), 2, axis=0)
    elbow = camloc.LANDMARKS.index("right_elbow")
    points[1, elbow] = np.nan  # a missing limb joint: imputed, still localized
    no_torso = [camloc.LANDMARKS.index(name) for name in ("pelvis", "left_hip")]
    points[2, no_torso] = np.nan  # no pelvis, and it cannot be derived: filled in
    points[3, elbow, 0] = np.nan  # half a joint
    points[4, elbow, 1] = np.inf
    sparse = points[0].copy()  # 7 landmarks: too few to fill a torso in
    for name in ("pelvis", "left_hip", "left_knee", "right_knee", "left_ankle", "right_ankle",
                 "left_wrist", "right_wrist"):
        sparse[camloc.LANDMARKS.index(name)] = np.nan
    points = np.concatenate([points, sparse[None]])
    got = localizer.localize(points)
    for i in (0, 1, 2, 5):
        assert got["error"][i] is None and 1 <= got["label"][i] <= 12
    assert "one coordinate is NaN" in got["error"][3]
    assert "not a finite number" in got["error"][4]
    assert "pelvis" in got["error"][6] and "7 landmarks present" in got["error"][6]
    for i in (3, 4, 6):
        assert got["label"][i] == 0 and np.isnan(got["probabilities"][i]).all()
    np.testing.assert_array_equal(got["label"][[0, 5]], localizer.localize(points[[0, 5]])["label"])

    rec = camloc.reconstruct(points[[0, 1, 2, 6]])
    assert rec["error"][0] is None and rec["error"][1] is None  # the elbow is filled in
    assert rec["imputed"][1, elbow] and rec["imputed"][1].sum() == 1 and not rec["imputed"][0].any()
    assert np.isfinite(rec["points3d"][1]).all()
    assert rec["error"][2] is None and rec["imputed"][2, no_torso].all()  # the torso too
    assert rec["imputed"][2].sum() == 2 and np.isfinite(rec["points3d"][2]).all()
    assert "pelvis" in rec["error"][3] and np.isnan(rec["points3d"][3]).all()


def test_bad_shapes_layouts_and_options_raise_value_error(localizer):
    points = example_points()
    bad_calls = [
        lambda: localizer.localize(points[:, :14]),
        lambda: localizer.localize(points, layout="coco17"),
        lambda: localizer.localize(np.zeros((3, 15, 4))),
        lambda: localizer.localize(np.zeros(30)),
        lambda: localizer.localize(np.zeros((1, 3, 15, 2))),
        lambda: localizer.localize(points, layout="openpose"),
        lambda: localizer.localize(points, scores=np.ones((3, 14))),
        lambda: localizer.localize(np.zeros((3, 15, 3)), scores=np.ones((3, 15))),
        lambda: localizer.localize(points, min_score=-0.5),
        lambda: localizer.localize(points, min_score=float("nan")),
        lambda: localizer.localize([[1.0, 2.0], [3.0]]),
        lambda: camloc.reconstruct(points, camera="oracle"),
        lambda: camloc.reconstruct(points, camera="best"),
        lambda: camloc.reconstruct(points, layout="lsp"),
        lambda: camloc.read_keypoints(KEYPOINTS / "example.json", format="yaml"),
        lambda: camloc.read_keypoints(KEYPOINTS / "example.json", layout="coco18"),
        lambda: camloc.read_keypoints(KEYPOINTS / "example.json", image_size=(0, 480)),
        lambda: camloc.read_keypoints(KEYPOINTS / "example.json", lsp_invisible="hide"),
    ]
    for call in bad_calls:
        with pytest.raises(ValueError):
            call()
    with pytest.raises(ValueError, match="layout coco17 has 17"):
        localizer.localize(points, layout="coco17")
    with pytest.raises(ValueError, match="unknown layout"):
        localizer.localize(points, layout="openpose")


def test_file_errors_are_exceptions_with_the_library_message(tmp_path):
    with pytest.raises(OSError, match="no_such_file.json"):
        camloc.read_keypoints(tmp_path / "no_such_file.json")
    with pytest.raises(camloc.CamlocError, match="syntax.json"):
        camloc.read_keypoints(KEYPOINTS / "bad" / "syntax.json")
    with pytest.raises(OSError):
        camloc.Localizer.load(tmp_path / "missing-model.bin")
    with pytest.raises(camloc.CamlocError):
        camloc.Localizer.load(KEYPOINTS / "example.json")
    with pytest.raises(camloc.CamlocError):
        camloc.reconstruct(example_points(), basis=ROOT / "fixtures" / "default-model.bin")


def test_a_model_file_gives_the_embedded_models_answers(localizer):
    loaded = camloc.Localizer.load(ROOT / "fixtures" / "default-model.bin")
    points = example_points()
    np.testing.assert_array_equal(
        loaded.localize(points)["probabilities"], localizer.localize(points)["probabilities"]
    )
    classified = camloc.reconstruct(points, camera="classified", localizer=loaded)
    np.testing.assert_array_equal(classified["label"], localizer.localize(points)["label"])
    # The embedded model, loaded from its file or not, keeps the embedded lifter.
    np.testing.assert_array_equal(
        classified["points3d"], camloc.reconstruct(points, camera="classified")["points3d"]
    )


def test_each_pose_on_its_own_equals_the_command_line_and_the_default_reads_the_whole_call(
    cli, localizer, tmp_path
):
    alone = camloc.Localizer(camera_height="any")
    assert (localizer.camera_height, alone.camera_height) == ("from-input", "any")
    path = KEYPOINTS / "example.json"
    _, expected = cli("localize", "--input", path, "--camera-height", "any")
    points = camloc.read_keypoints(path)["points"]
    got = alone.localize(points)
    for i, want in enumerate(expected):
        probabilities = [want["probabilities"][f"{c['label']:02}"] for c in alone.cameras]
        np.testing.assert_allclose(got["probabilities"][i], probabilities, rtol=1e-12)
        # On its own, a pose gets the same answer in any call.
        np.testing.assert_array_equal(
            alone.localize(points[i : i + 1])["probabilities"][0], got["probabilities"][i]
        )
    # The default estimates the camera heights of the call's first poses (three read about as
    # a camera at eye level would be), and a pose's answer depends on the others, as with the
    # command line's default.
    middle = [i for i, c in enumerate(alone.cameras) if c["level"] == "middle"]
    three = localizer.localize(points)
    assert three["camera_height_shares"][1] > 0.6
    assert (three["probabilities"][:, middle].sum(1) > got["probabilities"][:, middle].sum(1)).all()
    many = np.tile(points, (40, 1, 1))
    together = localizer.localize(many)["probabilities"]
    assert np.abs(together[0] - three["probabilities"][0]).max() > 1e-9
    path = tmp_path / "many.npy"
    np.save(path, many)
    _, expected = cli("localize", "--input", path)
    for i in (0, 1, 2, len(many) - 1):
        probabilities = [expected[i]["probabilities"][f"{c['label']:02}"] for c in alone.cameras]
        np.testing.assert_allclose(together[i], probabilities, rtol=1e-12)


def test_eye_level_prior_equals_the_command_line_and_favours_the_middle_ring(cli, localizer):
    eye = camloc.Localizer(camera_height="eye-level")
    assert eye.camera_height == "eye-level"
    path = KEYPOINTS / "example.json"
    _, expected = cli("localize", "--input", path, "--camera-height", "eye-level")
    points = camloc.read_keypoints(path)["points"]
    got, before = eye.localize(points), camloc.Localizer(camera_height="any").localize(points)
    middle = [i for i, c in enumerate(localizer.cameras) if c["level"] == "middle"]
    for i, want in enumerate(expected):
        assert got["label"][i] == want["label"]
        probabilities = [want["probabilities"][f"{c['label']:02}"] for c in localizer.cameras]
        np.testing.assert_allclose(got["probabilities"][i], probabilities, rtol=1e-12)
        # The middle ring's share rises; each ring keeps its cameras' ratios.
        assert got["probabilities"][i][middle].sum() > before["probabilities"][i][middle].sum()
        ratio = got["probabilities"][i][middle] / before["probabilities"][i][middle]
        np.testing.assert_allclose(ratio, ratio[0], rtol=1e-9)
    loaded = camloc.Localizer.load(ROOT / "fixtures" / "default-model.bin", camera_height="eye-level")
    np.testing.assert_array_equal(loaded.localize(points)["probabilities"], got["probabilities"])
    with pytest.raises(ValueError, match="eye-level"):
        camloc.Localizer(camera_height="tripod")
    # reconstruct: the same prior as --camera-height, the embedded lifter kept.
    _, rebuilt = cli("reconstruct", "--input", path, "--camera-height", "eye-level")
    got = camloc.reconstruct(points, camera_height="eye-level")
    for i, want in enumerate(rebuilt):
        landmarks = [want["landmarks_m"][name] for name in camloc.LANDMARKS]
        np.testing.assert_allclose(got["points3d"][i], landmarks, rtol=1e-9, atol=1e-12)
        assert got["label"][i] == want["classified_label"]


def test_folders_read_every_file_and_report_bad_ones(tmp_path):
    folder = camloc.read_keypoints(SAMPLES / "openpose")
    # Frame 1's two poses lie 20 px apart, a quarter of their torso: one person's duplicate
    # detections, followed as person 0 (OpenPose without tracking ids).
    assert list(folder["frames"]) == [0, 1, 1] and list(folder["persons"]) == [0, 0, 0]
    shutil.copytree(SAMPLES / "openpose", tmp_path / "frames")
    shutil.copy(
        KEYPOINTS / "bad" / "openpose_truncated_000000000003_keypoints.json", tmp_path / "frames"
    )
    read = camloc.read_keypoints(tmp_path / "frames")
    np.testing.assert_array_equal(read["points"], folder["points"])
    assert len(read["file_errors"]) == 1
    file, message = read["file_errors"][0]
    assert file.endswith("openpose_truncated_000000000003_keypoints.json") and message


def test_mediapipe_needs_and_uses_the_image_size():
    path = SAMPLES / "mediapipe.json"
    pixels = camloc.read_keypoints(path, image_size=(640, 480))["points"]
    text = camloc.read_keypoints(path, image_size="640,480")["points"]
    np.testing.assert_array_equal(pixels, text)
    assert np.nanmax(pixels[..., 0]) > 1.5  # scaled from [0, 1] to pixels
    for given in ([640, 480], np.array([640.0, 480.0])):
        np.testing.assert_array_equal(camloc.read_keypoints(path, image_size=given)["points"], text)
    with pytest.raises(ValueError, match="two numbers"):
        camloc.read_keypoints(path, image_size=[640, 480, 3])
    for wrong, what in ((b"640,480", "7 bytes"), (np.ones((2, 2)), "got ndarray")):
        with pytest.raises(TypeError, match=what):
            camloc.read_keypoints(path, image_size=wrong)


def test_a_100k_pose_batch(alone):
    base = example_points()
    n = 100_000
    rng = np.random.default_rng(7)
    # Scaled and shifted copies: the descriptors are invariant to both.
    scale = rng.uniform(0.5, 2.0, size=(n, 1, 1))
    shift = rng.uniform(-500, 500, size=(n, 1, 2))
    points = base[np.arange(n) % 3] * scale + shift
    got = alone.localize(points)
    assert got["label"].shape == (n,) and got["probabilities"].shape == (n, 12)
    assert got["error"] == [None] * n
    reference = alone.localize(base)
    np.testing.assert_array_equal(got["label"], np.tile(reference["label"], n // 3 + 1)[:n])
    np.testing.assert_allclose(
        got["probabilities"], np.tile(reference["probabilities"], (n // 3 + 1, 1))[:n], atol=1e-9
    )


def test_threads_share_a_localizer(localizer):
    points = np.tile(example_points(), (2000, 1, 1))
    reference = localizer.localize(points)
    results = [None] * 4

    def work(k):
        results[k] = localizer.localize(points)["probabilities"]

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r in results:
        np.testing.assert_array_equal(r, reference["probabilities"])
