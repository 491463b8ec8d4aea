"""Warnings of inputs that run but are likely wrong: landmarks in another order than the
layout's, bone lengths that do not fit the rows."""

import warnings

import numpy as np
import pytest

import camloc
from helpers import LENGTHS, example_points


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
