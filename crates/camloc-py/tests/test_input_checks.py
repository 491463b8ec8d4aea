"""Warnings of inputs that run but are likely wrong: landmarks in another order than the
layout's, bone lengths that do not fit the rows, pixels stretched across or squeezed."""

import warnings

import numpy as np
import pytest

import camloc
from helpers import DATA, LENGTHS, example_points, walk_trials


def test_landmarks_in_another_order_than_the_layout_are_warned_of():
    """A 14-joint array in camloc's order read as LSP-14 (a simulated animator's mistake) is
    reconstructed with most joints bent past the limits, and a warning says so; the right
    order says nothing."""
    rng = np.random.default_rng(0)
    many = np.concatenate([example_points() + rng.normal(0, 2, (3, 15, 2)) for _ in range(4)])
    wrong = np.delete(many, camloc.LANDMARKS.index("pelvis"), axis=1)
    with pytest.warns(UserWarning, match=r"of 12 poses were reconstructed with joints bent past"):
        camloc.reconstruct(wrong, layout="lsp14")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        camloc.reconstruct(many)


def test_given_lengths_that_fit_worse_than_estimated_ones_are_warned_of():
    """With ``sequence=True``, bone lengths that fit the frames worse than lengths estimated
    from them (the thighs and forearms swapped) are warned of, as the command line warns; the
    person's own estimated lengths given back are not."""
    walk = np.stack([example_points()[0] + [8.0 * t, 0.0] for t in range(20)])
    own = camloc.reconstruct(walk, sequence=True)["person_bone_lengths"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        camloc.reconstruct(walk, sequence=True, bone_lengths=list(own))
    swapped = list(LENGTHS)
    swapped[1], swapped[10] = swapped[10], swapped[1]
    swapped[4], swapped[13] = swapped[13], swapped[4]
    with pytest.warns(UserWarning, match="bone_lengths: the bone lengths given fit its 20 frames"):
        camloc.reconstruct(walk, sequence=True, bone_lengths=swapped)


def side_walk():
    """(150, 15, 2) pixels: the first 150 frames of the first CMU clip the index describes as a
    walk, seen from the side of its y axis (the way it walks) by a fixed camera 4 m from the
    mean pelvis at eye level, 1000 px focal length; skipped without the shared data."""
    folder, walks = DATA / "cmu" / "bvh", walk_trials()
    if walks is None or not folder.is_dir():
        pytest.skip(f"SKIPPED: the stretched-pixels test: {DATA / 'cmu'} not found (set CAMLOC_DATA)")
    clip = next((p for p in sorted(folder.glob("*.bvh")) if p.stem in walks), None)
    if clip is None:
        pytest.skip("SKIPPED: the stretched-pixels test: no walk in the CMU folder")
    truth = camloc.read_bvh(clip)["points3d"][:150]
    mean = truth[:, 0].mean(axis=0)
    depth = truth[..., 0] - mean[0] + 4.0
    u = -1000.0 * (truth[..., 1] - mean[1]) / depth + 960.0
    v = -1000.0 * (truth[..., 2] - mean[2]) / depth + 540.0
    return np.stack([u, v], axis=-1)


def test_pixels_stretched_across_or_squeezed_are_warned_of():
    """A walk seen from the side, its pixels made (16/9)^2 times too wide for their height
    (normalised coordinates multiplied by a portrait video's size given as landscape) or as
    much too narrow, is warned of by ``reconstruct`` and by a localizer's first call of 100
    poses or more, naming the way that fits; as given, nothing is said."""
    walk = side_walk()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        camloc.Localizer().localize(walk)
        camloc.reconstruct(walk)
    for factor, way in [((16 / 9) ** 2, "divided"), ((9 / 16) ** 2, "multiplied")]:
        scaled = walk * [factor, 1.0]
        localizer = camloc.Localizer()
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            localizer.localize(scaled[:99])
        with pytest.warns(UserWarning, match=f"fit a body better with x {way} by 3.16"):
            localizer.localize(scaled)
        # Once per localizer: a video's later chunks do not pay for it again.
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            localizer.localize(scaled)
        with pytest.warns(UserWarning, match="width and height swapped"):
            camloc.reconstruct(scaled)
