"""What the tests of the camloc package share: the repository's fixtures, a person's bone
lengths, the example poses."""

import os
from pathlib import Path

import camloc

ROOT = Path(__file__).resolve().parents[3]
KEYPOINTS = ROOT / "fixtures" / "keypoints"
SAMPLES = KEYPOINTS / "samples"
# The shared data beside the repository (CAMLOC_DATA overrides it).
DATA = Path(os.environ.get("CAMLOC_DATA", ROOT.parent / "shared" / "data"))
# A person's 14 limb lengths in metres, ``camloc.BONE_KEYS`` order.
LENGTHS = [0.11, 0.44, 0.41, 0.11, 0.44, 0.41, 0.52, 0.16, 0.19, 0.30, 0.27, 0.19, 0.30, 0.27]


def example_points():
    """The three example poses (3, 15, 2) of fixtures/keypoints/example.json."""
    return camloc.read_keypoints(KEYPOINTS / "example.json")["points"]


def walk_trials():
    """The CMU trials the index beside the data describes as "walk"; None without the index."""
    index = DATA / "cmu" / "cmu-mocap-index-text.txt"
    if not index.is_file():
        return None
    walks = set()
    for line in index.read_text(encoding="utf-8", errors="replace").splitlines():
        trial, _, description = line.partition("\t")
        if description.strip().lower() == "walk":
            walks.add(trial.strip())
    return walks
