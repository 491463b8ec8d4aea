"""Tests of the camloc Python package: answers equal the `camloc` command line's on the
fixtures, shapes and dtypes, missing joints, bad input, a 100k-pose batch.

The command-line comparisons run the `camloc` binary of the `cli` fixture (conftest.py).
"""

import json
import shutil
import threading
from pathlib import Path

import numpy as np
import pytest

import camloc

ROOT = Path(__file__).resolve().parents[3]
KEYPOINTS = ROOT / "fixtures" / "keypoints"
SAMPLES = KEYPOINTS / "samples"

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


@pytest.fixture(scope="module")
def localizer():
    return camloc.Localizer()


@pytest.fixture(scope="module")
def alone():
    """Each pose on its own (the default reads a call's poses together)."""
    return camloc.Localizer(camera_height="any")


def example_points():
    return camloc.read_keypoints(KEYPOINTS / "example.json")["points"]


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
        assert name in ("id_utf8", "camera_height_shares") or got[name].shape[0] == n, name
    # These inputs are too small for an estimate of the camera heights.
    assert got["camera_height_shares"].shape == (3,)
    assert np.isnan(got["camera_height_shares"]).all()
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


LENGTHS = [0.11, 0.44, 0.41, 0.11, 0.44, 0.41, 0.52, 0.16, 0.19, 0.30, 0.27, 0.19, 0.30, 0.27]


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


def test_min_score_drops_weak_joints_as_the_reader_does(alone):
    # Pose 1's right wrist scores 0.05 in the sample (fixtures/keypoints/README.md).
    array = np.load(SAMPLES / "h36m17_scores.npy")
    raw = alone.localize(array, layout="h36m17", min_score=0.1)
    read = camloc.read_keypoints(SAMPLES / "h36m17_scores.npy", layout="h36m17", min_score=0.1)
    assert np.isnan(read["points"][1, camloc.LANDMARKS.index("right_wrist")]).all()
    np.testing.assert_array_equal(
        raw["probabilities"], alone.localize(read["points"])["probabilities"]
    )
    full = alone.localize(array, layout="h36m17")
    assert not np.array_equal(raw["probabilities"][1], full["probabilities"][1])
    np.testing.assert_array_equal(raw["probabilities"][[0, 2]], full["probabilities"][[0, 2]])


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
    # Three poses are too few to tell the camera heights: the default leaves each on its own.
    np.testing.assert_array_equal(localizer.localize(points)["probabilities"], got["probabilities"])
    # Enough poses: the default estimates the camera heights of the call's first poses, and a
    # pose's answer depends on the others, as with the command line's default.
    many = np.tile(points, (40, 1, 1))
    together = localizer.localize(many)["probabilities"]
    assert np.abs(together[0] - got["probabilities"][0]).max() > 1e-9
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
    assert list(folder["frames"]) == [0, 1, 1] and list(folder["persons"]) == [0, 0, 1]
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
    with pytest.warns(UserWarning, match="left out of the smoothing"):
        smoothed = camloc.Localizer().localize(swapped, sequence=True)
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
    np.testing.assert_array_equal(
        repaired["points3d"], camloc.reconstruct(walking, sequence=True)["points3d"]
    )
    expected = np.zeros((12, 2), bool)
    expected[4:6, 0] = True
    np.testing.assert_array_equal(repaired["swapped_sides"], expected)
    with pytest.warns(UserWarning, match=r"left and right legs of 2 row\(s\) are swapped"):
        located = camloc.Localizer().localize(crossed, sequence=True)
    clean = camloc.Localizer().localize(walking, sequence=True)
    np.testing.assert_array_equal(located["swapped_sides"], expected)
    for key in ("label", "probabilities", "azimuth_deg", "smoothed_label"):
        np.testing.assert_array_equal(located[key], clean[key])
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
    import time

    points = np.tile(example_points(), (40_000, 1, 1))
    timer = threading.Timer(0.3, _thread.interrupt_main)
    started = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            camloc.reconstruct(points)
    finally:
        timer.cancel()
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


def test_a_sequence_row_refused_for_its_layout_is_a_failed_frame_in_its_place():
    # Human3.6M's 17 joints of a standing person, and the same with the first five gathered
    # as a face's: that row is refused for its layout (it had failed the whole sequence).
    standing = np.array(
        [[100, 130], [85, 130], [84, 185], [83, 240], [115, 130], [116, 185], [117, 240],
         [100, 90], [100, 50], [100, 20], [100, 5], [125, 50], [130, 90], [132, 125],
         [75, 50], [70, 90], [68, 125]],
        dtype=float,
    )
    face = standing.copy()
    face[:5] = [[100 + 2 * j, 20 - j] for j in range(5)]
    rows = np.stack([standing + [4.0 * t, 0.0] for t in range(6)])
    rows[2] = face + [8.0, 0.0]
    got = camloc.reconstruct(rows, layout="h36m17", sequence=True)
    assert [e is not None for e in got["error"]] == [False, False, True, False, False, False]
    assert "likely coco17" in got["error"][2]
    assert np.isnan(got["points3d"][2]).all() and not np.isnan(got["points3d"][3]).any()


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
    with pytest.raises(TypeError, match="complex"):
        camloc.Localizer().localize(points.astype(np.complex128))
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
    """``camera_height_shares`` is the estimate every pose was localized under: NaN for a call
    of a few poses, the command line's ``--npz`` shares for 100 or more."""
    few = example_points()
    assert np.isnan(camloc.Localizer().localize(few)["camera_height_shares"]).all()
    many = np.concatenate([few] * 40)
    path = tmp_path / "many.npy"
    np.save(path, many)
    code, _ = cli("localize", "--input", path, "--npz", tmp_path / "out.npz", "-q")
    assert code == 0
    want = np.load(tmp_path / "out.npz")["camera_height_shares"]
    assert np.isfinite(want).all() and want.sum() == pytest.approx(1.0)
    for got in (
        camloc.Localizer().localize(many)["camera_height_shares"],
        camloc.reconstruct(many)["camera_height_shares"],
    ):
        np.testing.assert_allclose(got, want, rtol=1e-12)
    assert np.isnan(camloc.Localizer("eye-level").localize(many)["camera_height_shares"]).all()
