"""What the tests of the camloc package share: the repository's fixtures, a person's bone
lengths, the example poses."""

from pathlib import Path

import camloc

ROOT = Path(__file__).resolve().parents[3]
KEYPOINTS = ROOT / "fixtures" / "keypoints"
SAMPLES = KEYPOINTS / "samples"
# A person's 14 limb lengths in metres, ``camloc.BONE_KEYS`` order.
LENGTHS = [0.11, 0.44, 0.41, 0.11, 0.44, 0.41, 0.52, 0.16, 0.19, 0.30, 0.27, 0.19, 0.30, 0.27]


def example_points():
    """The three example poses (3, 15, 2) of fixtures/keypoints/example.json."""
    return camloc.read_keypoints(KEYPOINTS / "example.json")["points"]
