"""camloc: where the camera stood, from the 2D landmarks of a human pose.

Which of the 12 cameras of Table 1 (3 heights x front/left/back/right of the person) saw a 2D
pose, with probabilities, and a plausible 3D skeleton for it. NumPy arrays in, dicts of NumPy
arrays out; the work is done by camloc's Rust library, in parallel, without holding the GIL.

Poses are arrays of shape (N, J, 2) (or one pose (J, 2)) in image coordinates (x to the right,
y down, any unit the same on both axes, usually pixels: coordinates divided by an image's
width and by its height squash the pose, and all within [0, 1] are warned of), J joints in a
``layout``:

- ``camloc15``: camloc's 15 landmarks in ``LANDMARKS`` order (pelvis first);
- ``coco17``, ``h36m17``, ``body25``, ``mpii16``, ``lsp14``: detector and dataset layouts,
  mapped to the 15 landmarks as documented in docs/keypoints.md of the repository (the head of
  COCO-17 and BODY_25 is the mean of the face points; a missing pelvis or neck is the midpoint
  of the hips or shoulders);
- ``mediapipe33``: MediaPipe Pose's 33 landmarks, in pixels (its normalised ``x`` times the
  image's width and ``y`` times its height: a portrait phone video is 1080 wide and 1920
  high, and NumPy's ``image.shape`` is (height, width); ``visibility`` as the scores, ``z``
  left out): the head is the mean of nose, eyes and ears, hands and feet are not used.

A joint whose two coordinates are NaN is missing (a pose with a torso but fewer than 8 of the
15 landmarks is localized from those it has, with a ``UserWarning``, and not reconstructed).
Scores, either a third channel (N, J, 3) or ``scores`` of shape (N, J), must lie in [0, 1]; a
joint scoring 0 or below ``min_score`` is missing.

Batch calls never fail for one bad pose: each result dict has an ``error`` list with ``None``
where the pose is fine and the library's message where it is not (NaN and label 0 in that
pose's rows). Wrong shapes, unknown layouts and bad option values raise ``ValueError``;
values of the wrong type (a bool given for a number, complex numbers) ``TypeError``;
unreadable files ``OSError``; other library errors ``CamlocError``. For one pose (J, 2) the
leading N axis is left out of every array and ``error`` is a single value.
"""

from os import PathLike
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
LAYOUTS: List[str]
"""The joint layouts: coco17, h36m17, body25, mpii16, lsp14, camloc15, mediapipe33."""
FORMATS: List[str]
"""The keypoint file formats ``read_keypoints`` reads."""
LANDMARKS: List[str]
"""camloc's 15 landmarks, in the order of the ``camloc15`` layout and of every output."""
BONE_KEYS: List[str]
"""The 14 limbs (pelvis to left hip, left thigh, ...), in the order of ``bone_lengths``."""

class CamlocError(Exception):
    """An error of camloc's Rust library (malformed file, unusable model, ...), with its message."""

class CamlocWarning(UserWarning):
    """The warnings camloc gives (points with v up, a rolled camera, a call whose every pose
    failed, rows of a sequence that jump between people, ...): a ``UserWarning``, so shown once
    per place by default; ``warnings.simplefilter("ignore", camloc.CamlocWarning)`` silences
    them without matching their text, which names the call's numbers."""

_Path = Union[str, PathLike]

class Localizer:
    """A trained camera localizer. It can be pickled and copied (``pickle``, ``copy``,
    multiprocessing): the copy holds the same model and camera height. Processes forked from
    one that has already run camloc (``multiprocessing``'s ``fork`` start method) run their
    work on thread pools of their own."""

    def __init__(self, camera_height: Optional[str] = "from-input") -> None:
        """The default model embedded in camloc (trained on CMU motion capture).

        camera_height: what is known of the camera's height, a prior over the cameras that
        reweighs the model's probabilities (docs/conventions.md section 5):
        ``"from-input"`` (each ``localize`` call first estimates from its first 20,000 poses
        how their cameras divide among the three heights and the mean elevation of its middle
        cameras, then localizes every pose under those shares, each middle-ring viewpoint
        regressing toward that elevation instead of the training's (give one camera's poses
        per call): a pose's answer
        depends on the other poses of the call, as with
        ``camloc localize``; the estimate starts from 5 views of a camera at eye level and
        a video's frames count little each, so a few photos or a short clip are read about as
        ``"eye-level"`` reads them: give ``"any"`` for single photos from well above or below;
        a call without a pose with a torso leaves each on its own, as ``"any"`` does),
        ``"any"`` (the model's own priors; each pose on its own) or ``"eye-level"`` (a
        tripod, handheld phone or studio camera at about a standing person's eye level, a
        few metres away: a middle-ring camera is 8 times as likely a priori); ``None`` is
        ``"from-input"``, as ``reconstruct``'s ``camera_height=None`` is the localizer's own.
        Raises ValueError for another text, as for every other bad argument, and TypeError for
        a value that is not text (a number, a path: ``Localizer.load`` reads model files)."""

    @staticmethod
    def load(path: _Path, camera_height: Optional[str] = "from-input") -> "Localizer":
        """Reads a model file written by ``camloc train``; ``camera_height`` as for the
        default model (not stored in the file).

        Raises OSError if it cannot be read, CamlocError if it is not a valid model."""

    @property
    def camera_height(self) -> str:
        """The prior over the camera's height this localizer applies: ``"from-input"``,
        ``"any"`` or ``"eye-level"``."""

    @property
    def cameras(self) -> List[Dict[str, Any]]:
        """The camera classes, one dict per label: ``label`` (1-based; column ``label - 1`` of
        ``probabilities``), ``level`` (lower/middle/upper), ``side`` (front/left/back/right),
        ``azimuth_deg``, ``elevation_deg`` (degrees, person's canonical frame: azimuth 180 =
        front, 270 = the person's left) and ``rotation`` (3, 3) (rows: camera axes)."""

    def localize(
        self,
        points: npt.ArrayLike,
        layout: str = "camloc15",
        scores: Optional[npt.ArrayLike] = None,
        min_score: float = 0.0,
        sequence: bool = False,
        focal_px: Optional[float] = None,
        principal_point: Optional[Sequence[float]] = None,
        fps: float = 30.0,
        frames: Optional[npt.ArrayLike] = None,
        camera_height_shares: Optional[npt.ArrayLike] = None,
        camera_height_elevations_deg: Optional[npt.ArrayLike] = None,
    ) -> Dict[str, Any]:
        """Localizes the camera of every pose.

        points: (N, J, 2) or (N, J, 3) with scores, or one pose (J, 2) / (J, 3); J is the
        layout's joint count; NaN coordinates mark a missing joint, and so does a masked
        coordinate of a ``numpy.ma.MaskedArray`` (or of a list of them, one per pose; a
        masked score is 0). Converted to float64; complex numbers, points given as booleans
        or text, and bools given for numbers (``min_score=True``) are ``TypeError``s.
        A pose with missing landmarks, 8 or more of the 15 present, is localized with them
        filled in from the embedded pose basis seen by camera hypotheses, its probabilities
        tempered for what was filled in (docs/conventions.md section 6, "Filled-in poses");
        with fewer, a pose with a torso is localized from the landmarks' training means, one
        whose torso cannot be found (pelvis or neck missing, and a hip or shoulder to stand in
        for it) gets an error. A filled-in pose costs far more than a complete one:
        about 0.2 ms of wall time on two cores against 1-6 us (2,100 poses of the examples
        with a shoulder missing); a simulated user's million COCO-17 poses, 12% of them
        missing a hip or shoulder, took 50 s against 1.3 s (every pose with a landmark
        missing costs about that). Each call also costs a few
        microseconds of its own (11 us for one pose, 32 us with ``camera_height=
        "from-input"``): give many poses per call.
        scores: optional (N, J) (or (J,)) confidences in [0, 1] for 2-channel points (a
          masked entry of a ``numpy.ma.MaskedArray`` is 0: the joint is missing).
        min_score: joints scoring below it are missing (finite, >= 0; above 0 it needs
          scores, given or as a third channel: a ``ValueError`` without). For a detector's
          output try 0.3: its weak joints are often misplaced (a simulated user's flickering
          COCO-17 detector: 6-13 mm closer, a third of the jitter); but single frames of
          seated people whose legs a desk hides came out worse (the legs filled in standing:
          110 against 78 mm; with ``sequence=True`` 62 against 66).
        sequence: the poses are one person's frames of a video, in time order (a row of NaN
          where the person was missed): the result also has each frame's camera and viewpoint
          smoothed over the frames, as ``camloc localize --sequence`` gives them, and
          ``swapped_sides`` (N, 2) bool: the rows whose legs (column 0) or arms (column 1) a
          detector read with the left and right sides swapped, swapped back and localized
          again, with a ``UserWarning`` (docs/cli.md section Sequences), and
          ``left_out_of_sequence`` (N,) bool: the rows left out of the smoothing (below); and a
          ``UserWarning`` says where the pose jumps across the image as one person cannot (rows
          of several people), and another where rows (up to 10 in a row, at an end too: the
          rows are consecutive frames) lie apart from the rows before and after them while
          those agree (another person's detection): as the
          command line does, they are left out of the smoothing (their smoothed camera comes
          from the rows around them, their smoothed viewpoint is NaN). A row of NaN counts as
          a frame, where the command line skips a frame number no record has: the smoothed
          probabilities can differ there.
        focal_px, principal_point: the camera's focal length and principal point (u, v),
          pixels, when known (the points must be in pixels): each pose is localized as the
          camera turned to aim at the person would see it, as ``camloc localize --focal-px``
          does (a person near the edge of a wide-angle image is otherwise drawn out by the
          perspective: 59% against 77% 12-class accuracy on a trial's views at f = 500 px,
          500 px off-centre); without a principal point nothing changes (a ``UserWarning``
          says so). ``reconstruct``'s
          ``focal_px`` and ``principal_point`` aim its localizations alike.
        fps: with ``sequence``, the video's frames a second (30 by default), as ``camloc
          localize --sequence --fps``: the smoothing, the side swaps swapped back and the
          rows left out are judged over as long a time at faster rates (7 rows at 30 frames a
          second, 25 at 120: 3 x round(fps / 30) on each side, fps above 1,000 taken as 1,000).
          Without ``sequence`` it changes nothing (from 0.000278 to 1,000,000).
        frames: with ``sequence``, each row's video frame number (N,) (whole numbers from 0 to
          2^53 that do not decrease; all -1, ``read_keypoints``' frames of an input without
          numbers, are none), as ``reconstruct``'s ``frames``: the frame numbers between rows
          count as time passing, and of several rows of one frame (an untracked detector's
          people) the one nearest the person's rows around it is the person's, the others left
          out (a ``UserWarning``), as ``camloc localize --sequence`` reads the poses of one
          person number with their ``frame``s. Default: the rows are consecutive frames.
          A ``ValueError`` without ``sequence``.
        camera_height_shares: the shares of the lower, middle and upper cameras to localize
          under (three numbers, normalised; a ``ValueError`` for a negative one or none > 0,
          or with a ``camera_height`` other than ``"from-input"``, a ``TypeError`` for other
          than numbers), in place of this call's own estimate: give
          one person's rows of a video with the shares of a call on all its rows (its
          ``camera_height_shares``, and its ``camera_height_elevations_deg`` too: without
          them no viewpoint is moved), as ``camloc localize --sequence`` estimates them once
          for the whole file (estimated from one person's rows, a simulated user's four
          walkers under a ceiling camera were 85.2% right against the command line's 99.1%).
        camera_height_elevations_deg: with ``camera_height_shares``, the mean elevation of
          the cameras of each height (three numbers, degrees above the pelvis, NaN for none;
          only the middle one may be a number), as that call's
          ``camera_height_elevations_deg`` gives them (a ``ValueError`` alone).
        A ``UserWarning`` says when most of the (first 20,000) poses have the head below both
        ankles, the body within about 60 degrees of upside down: points with v up (``camloc
        localize`` warns alike); another when their torsos lean alike by 20 degrees or more and
        their shins 10 degrees or more the same way (a rolled camera: turn the points upright;
        docs/keypoints.md); another when a pose has a landmark at
        exactly (0, 0) outside the box of its other landmarks (a detector's
        placeholder for a joint it did not find: give scores or NaN); another when every pose
        of the call failed, with the first error other than "nothing detected", or, when no
        pose has a landmark, asking whether ``min_score`` is on the scale of the scores;
        another, at the default ``min_score`` of 0 with scores, when 1% or more of the
        landmarks of the first 2,000 poses score below 0.3 (used as detected;
        docs/keypoints.md); another when, of the first 60 poses of a call of 100 or more,
        those seen from a side fit a body clearly better with x divided or multiplied by
        (16/9)^2 (normalised coordinates multiplied by the image's width and height swapped;
        about 0.06 s, once per localizer: at its first call with 10 or more such poses;
        docs/keypoints.md).
        No poses ((0, J, 2) points) give empty arrays and no warning, where ``camloc
        localize`` refuses an input without poses (exit 1).

        Returns a dict:
          label (N,) int64: most probable camera, 1..K, K = 12 with Table 1 (0 where it failed);
          folded_label (N,) int64: the label with back cameras folded to the front;
          probability (N,) float64: probability of ``label``;
          probabilities (N, K) float64: probability of each camera (column label - 1);
          azimuth_deg, elevation_deg (N,) float64: the continuous viewpoint, degrees, in the
            person's canonical frame (azimuth 180 = front, 270 = left, 0 = back, 90 = right;
            elevation + above); NaN where the pose failed or the model has no direction heads;
          uncertainty_deg (N,) float64: angular radius calibrated to hold about 68% of the
            viewpoint error over the training views' mix of postures and cameras; it held
            63-84% of held-out views by protocol, less for acrobatics (30-50%) and for low
            frames under ``jittered`` views (45-64%; docs/RESULTS.md);
          missing, derived (N, 15) bool: the landmarks (``LANDMARKS`` order) missing from the
            pose as read, or far off the others in a localized pose (read as missing and filled
            in; every one of a pose that could not be read) and those derived rather
            than read (a pelvis from the hips, a COCO head from the face points), as ``camloc
            localize --npz`` writes them;
          camera_height_shares (3,) float64: with ``camera_height="from-input"``, how the
            call's cameras were estimated to divide among the lower, middle and upper rings
            (the prior every pose was localized under, as ``camloc localize --npz`` writes
            it); NaN when no estimate was used (no pose with a torso, ``"any"``,
            ``"eye-level"``);
          camera_height_elevations_deg (3,) float64: with ``camera_height="from-input"``,
            per height (lower, middle, upper) the mean elevation above the pelvis (degrees)
            of the call's cameras of that height, as the direction heads read its poses with
            their pull toward the training's elevations undone (and pulled back toward the
            training's, about 7 degrees, when the call's poses are worth few views): each
            ``elevation_deg`` of that height regresses toward it instead of the training's
            mean (docs/conventions.md section 5). Only the
            middle height's (body height, within 22.5 degrees of level) is estimated, from
            the poses put there: it is not the elevation of a camera whose poses were put
            in the upper ring (the median ``elevation_deg`` of one camera's poses is); NaN
            for the lower and upper heights, for the middle one when no pose was put there,
            and when no estimate was used;
          camera_height_views float: the number of independent views the estimate counted
            its poses as worth (a video's frames little each, unrelated photos one each; the
            estimate starts from 5 views of a camera at eye level), as ``camloc localize``
            says it on a terminal; NaN when no estimate was made;
          with ``sequence``: smoothed_label (N,) int64 and smoothed_probability (N,), the
            camera on the hidden Markov model's most probable path and its posterior (0 and NaN
            when no frame was localized; a frame that was not counts as a flat one);
            smoothed_azimuth_deg, smoothed_elevation_deg (N,): the mean direction of the frames
            within 3 rows (``smooth_viewpoints``; those within 45 deg of the row's own when at
            least half are: a cut), NaN where the frame has no viewpoint;
          error: list of N messages, None where the pose was localized.

        Raises ValueError for a wrong shape, an unknown layout or a bad ``min_score``;
        MemoryError, before any work, for more poses than the outputs can be allocated for (a
        broadcast view of 10^9 poses). Ctrl-C raises ``KeyboardInterrupt`` after the block of
        65,536 poses being localized.
        """

    def __repr__(self) -> str: ...

def reconstruct(
    points: npt.ArrayLike,
    layout: str = "camloc15",
    camera: Optional[str] = None,
    scores: Optional[npt.ArrayLike] = None,
    min_score: float = 0.0,
    localizer: Optional[Localizer] = None,
    basis: Optional[_Path] = None,
    bone_lengths: Optional[Union[Mapping[str, float], Sequence[float], _Path]] = None,
    focal_px: Optional[float] = None,
    principal_point: Optional[npt.ArrayLike] = None,
    sequence: bool = False,
    camera_height: Optional[str] = None,
    lifter: Union[bool, _Path] = True,
    person_height: Optional[float] = None,
    fps: float = 30.0,
    frames: Optional[npt.ArrayLike] = None,
    sequence_max_rows: int = 200_000,
    camera_height_shares: Optional[npt.ArrayLike] = None,
    camera_height_elevations_deg: Optional[npt.ArrayLike] = None,
) -> Dict[str, Any]:
    """Reconstructs the 3D pose of every pose by projected matching pursuit on camloc's pose
    basis (principal components and cluster centres), then rebuilds each pose with the
    person's own bone lengths (docs/cli.md, "The person's proportions"). Missing landmarks
    (NaN, or a score below ``min_score``) are first filled in from the pose basis seen by the
    localized camera (in every mode; see ``imputed``); a pose whose torso cannot be found
    (pelvis or neck missing, and a hip or shoulder to stand in for it) has it filled in as
    ``Localizer.localize`` does. A pose with missing landmarks and fewer than 8 present gets
    an error (most of its 3D would be the basis's guess; with ``sequence``, counted after
    short gaps are filled in from the rows around them).

    points, layout, scores, min_score: as for ``Localizer.localize``.
    camera: ``opt`` (Procrustes camera), ``classified`` (the rotation of the classified
    camera) or ``hybrid`` (the camera of the localized continuous viewpoint refined by
    Procrustes, the default, as on the command line; with the embedded lifter about the time
    of ``opt``).
      With ``classified`` and ``hybrid`` and the embedded model, each pose is rebuilt from the
      depths the embedded depth lifter predicts for the classified camera (docs/conventions.md
      section 6) rather than from the pursuit's pose: the two modes then give the same shape
      for a complete pose (the same error after a similarity alignment, to a few mm; a pose
      with landmarks filled in may differ more: they are filled in again from each mode's
      first solve), and ``hybrid`` holds the rotation of the
      localized continuous viewpoint (one solve, as ``classified``) and levels the pose to
      the localized elevation, where ``classified`` keeps the class's camera (the skeleton's
      refinement adjusts it by a few degrees, as in every mode), 30-45 degrees off the true
      camera at the class's edges. Without the lifter (``lifter=False``) ``hybrid`` refines its
      rotation by Procrustes and has the lower 3D error.
    localizer: the model that classifies the camera (default: the embedded one). The
      embedded depth lifter predicts depths per Table-1 camera: a model of Table 1's cameras
      (the embedded one, or one trained with ``camloc train``) keeps it, as ``camloc
      reconstruct --model`` does; a model of other cameras reconstructs without it.
    basis: a pose basis file (default: the embedded one).
    bone_lengths: the person's 14 limb lengths in metres, as a mapping of ``BONE_KEYS``, 14
      numbers in ``BONE_KEYS`` order, or the path of a bone lengths JSON file (docs/cli.md);
      every pose then has exactly these. Lengths whose legs make a person taller than 2.6 m
      are a ``ValueError`` (lengths in feet are named). With ``sequence=True`` a
      ``UserWarning`` says when they fit the rows 1.5 times worse or more than lengths
      estimated from the same rows (another person's, limbs swapped, another unit, another
      skeleton's landmark placement; a second solve). Default:
      estimated from the 2D under a prior learned from motion capture (proportions only; the
      size is the prior's, people of about 1.7 m).
    person_height: the person's standing height in metres (soles to the top of the head,
      0.5-2.6; not a bool), as ``camloc reconstruct --person-height``: the estimated lengths
      keep their proportions and each answer is scaled, with its camera, so that its legs
      (thigh plus shin) are 0.491 of it (Winter's proportions for adults: a young child
      comes out about 12% large, docs/cli.md); the image is unchanged. With ``sequence``,
      ``world_points3d`` then walks real distances (with ``focal_px`` too). Not with
      ``bone_lengths``, which give the size.
    focal_px, principal_point: the camera's focal length and principal point (pixels; the
      principal point, two numbers as a tuple, list or array, defaults to the centre of the
      bounding box of each pose's given landmarks): a final full-perspective refinement, and each pose localized
      as the camera aimed at it would see it (as ``Localizer.localize``'s). The poses must be
      in pixels too: a pose whose root mean square radius is under 1/1000 of ``focal_px``
      (normalised coordinates) fails.
    sequence: the poses are the frames of one person, in time order: one set of bone lengths
      for all of them, depths chosen consistently over time, temporal smoothness, each
      landmark first smoothed over the frames within 1/15 s (``smooth_landmarks`` in the
      Rust library; the limbs' jitter halved, docs/cli.md; not at 15 ``fps`` and below),
      and a landmark missing for at most 0.7 s between rows that have it filled in from
      those rows (``fill_short_gaps``; ``imputed`` still names it).
      Legs or arms
      a detector read with the left and right sides swapped for up to 5 rows in a row (at 30
      frames a second; as long in time at a faster ``fps``) are
      swapped back first, with a ``UserWarning``, as ``camloc reconstruct --sequence`` does
      (docs/cli.md section Sequences). A
      ``UserWarning`` says where the pose jumps across the image or changes size as one person
      cannot from one row to the next (rows of several people: split them by the ``persons``
      of ``read_keypoints``, each with the ``camera_height_shares`` of a call on all rows), and another where rows (up to 10 in a row at 30 frames a second,
      as long in time at a faster ``fps``, at an end too: the
      rows are consecutive frames) lie apart from the rows before and after them while those
      agree (another person's detection): as
      ``camloc reconstruct --sequence`` does, they are reconstructed on their own, outside
      the sequence's bone lengths, smoothness and world placement (``world_points3d`` NaN).
      A row of NaN (nothing detected) gets the error "the pose has no landmarks (nothing
      detected)". Like ``Localizer.localize``, it warns when most poses have the head below
      both ankles, of a rolled camera, of landmarks at the image origin, of weakly scored
      landmarks used at ``min_score`` 0, of pixels stretched across or squeezed (every call
      of 100 poses or more), and when every pose failed.
    camera_height: ``"from-input"`` (the camera heights estimated from the poses of this
      call), ``"any"`` or ``"eye-level"``, the prior over the camera's height the localizer
      applies (as ``Localizer(camera_height=...)``; the embedded depth lifter stays).
      Default: the localizer's own (``"from-input"`` for the embedded one).
    lifter: ``False`` reconstructs without the embedded depth lifter (the pursuit's pose starts
      the refinement), as ``camloc reconstruct --no-lifter``; a path, with the lifter of that
      file instead (as ``DepthLifter::save`` writes one, with or without its lifter of the
      midpoint placement; ``camloc reconstruct --lifter FILE``): for instance
      ``fixtures/default-lifter.bin``, the embedded lifter of CMU's pelvis and neck alone, for
      poses projected from CMU motion capture that a view from far above or behind could read
      as a detector's midpoints.
    fps: with ``sequence``, the video's frames a second (30 by default), as ``camloc
      reconstruct --sequence --fps``: above 30 the smoothing over frames, the side swaps
      swapped back, the rows left out and the placement in the world keep their windows in
      time (1/30 s and longer; rates above 1,000 keep those of 1,000), so give the video's rate (a held-out walk at 120 frames a
      second: accelerations 483 m/s^2 told 30, 34 told 120). Without ``sequence`` it changes
      nothing (but must still be a frame rate: 0.000278 to 1,000,000, as the command line's
      ``--fps``).
    frames: with ``sequence``, each row's video frame number (N,) (whole numbers from 0 to
      2^53 that do not decrease; all -1, ``read_keypoints``' frames of an input without
      numbers, are none; booleans, text and float16 are a ``TypeError``), so that rows are
      read as ``camloc reconstruct --sequence`` reads one person number's poses with their
      ``frame``s: the numbers between rows are frames the person is missing from (time passes
      there; 3 or more missing in a row at 30 frames a second split the sequence into runs),
      and of several rows of one frame (an untracked detector's people:
      ``read_keypoints(path)["frames"]`` of a file without track ids) the one nearest the
      person's rows around it is the person's, the others are reconstructed on their own and
      marked in ``left_out_of_sequence`` (a ``UserWarning``; no tracker: a person missed for
      a while may be taken for another one within reach when seen again). ``world_points3d``
      is placed on that timeline (rows spread over more than 100 frame numbers each are
      placed as consecutive frames) but keeps one entry per row: for ``to_bvh``, put the rows
      on the video's frames first (``t = frames - frames.min(); keep =
      ~r["left_out_of_sequence"]; timeline = np.full((t.max() + 1, 15, 3), np.nan);
      timeline[t[keep]] = r["world_points3d"][keep]``; ``to_bvh`` fills the NaN frames, as the
      command line's BVH has them; for rows more than 100 frame numbers apart each, which the
      command line plays one after another, and for rows without frame numbers (all -1,
      which the recipe would put on one frame), pass ``r["world_points3d"][keep]`` itself).
      Default: the rows are consecutive frames. A ``ValueError`` without ``sequence``.
    sequence_max_rows: with ``sequence``, more rows are a ``ValueError`` before any work (as
      ``camloc reconstruct --sequence-max-poses``, 200,000 by default): a person's frames take
      12-15 KB each while they are solved together (100,000 frames: 1.2 GB).
    camera_height_shares: as ``Localizer.localize``'s: the shares of the camera heights to
      localize under instead of this call's estimate (give each person's rows of a video the
      shares of a call on all of them, as ``camloc reconstruct --sequence`` estimates them
      once for the whole file; a ``ValueError`` with a ``camera_height`` other than
      ``"from-input"``); with ``camera="opt"`` nothing is localized.
    camera_height_elevations_deg: with ``camera_height_shares``, as ``Localizer.localize``'s.

    Returns a dict:
      points3d (N, 15, 3) float64: the 3D landmarks in metres (the given bone lengths, else
        the estimated ones at the prior's size or ``person_height``), in the basis's canonical
        body frame (pelvis at the origin, z up; see docs/conventions.md), ``LANDMARKS`` order;
      rotation (N, 3, 3), scale (N,) (image units per metre), translation (N, 2) (image units):
        the weak-perspective camera, image = scale * rotation[:2] @ X + translation (after a
        perspective refinement, that camera's approximation at the pelvis;
        docs/conventions.md section 6);
      projection_error (N,): norm of the reprojection residuals of the fitted camera (the
        perspective one when there is one), image units, over the landmarks it was fitted
        to: all but those filled in from the basis (``imputed``; with ``sequence``, those
        interpolated over a short gap count as seen);
      outside_limits_rad (N,): how far the pose lies outside the joint-angle limits learned
        from the motion capture (the sum over thighs, shins, upper arms and forearms of the
        angle beyond them, radians; 0 within them): a pose the 2D bends beyond them (a knee
        seen bent backwards) has it above 0, check such poses before using them; NaN where
        the pose failed. When more than 60% of 10 or more poses are over 0.1, a ``UserWarning``
        asks whether the landmarks are in the order of ``layout``;
      reflected (N,) bool: whether the pose is the depth-mirrored reading of the 2D (the
        command line's ``reflected``: with the lifter, of its depths, so False for every
        answer; without it, of the pursuit's pose);
      label (N,) int64: the classified camera (0 for ``opt`` and failed poses);
      probability, azimuth_deg, elevation_deg (N,) float64: the localization's probability of
        ``label`` and its continuous viewpoint in degrees (as ``Localizer.localize`` gives
        them; the camera of ``hybrid`` stands at that elevation); NaN for ``opt`` and failed
        poses;
      bone_lengths (N, 14): each pose's limb lengths in metres, ``BONE_KEYS`` order;
      translation_m (N, 3), focal_px (N,), principal_point (N, 2): the perspective camera the
        final refinement fitted (with ``focal_px`` that one; without it, the camera at the
        estimated distance, the pelvis on its optical axis, mostly the prior's distance for a
        single pose), image = focal_px * (R X + T)[:2] / (R X + T)[2] + principal_point with
        R = rotation, T = translation_m: the pelvis in the camera's frame in metres (absolute
        only with given ``bone_lengths`` or ``person_height``); NaN where there is none (weak perspective);
      imputed (N, 15) bool: the landmarks that were missing and filled in (their 3D is a
        guess, from the basis or with ``sequence`` from the rows around a short gap, not a
        measurement; with ``sequence``, a ``CamlocWarning`` names those
        filled in a quarter or more of the reconstructed rows or in every row over half a
        second at ``fps`` (in ``frames``' numbers when given), and without it one counts the
        rows with landmarks filled in, as the command line does);
      person_bone_lengths (14,): with ``sequence``, the person's lengths (given or estimated;
        NaN when none were given and no frame of the sequence was reconstructed), between the
        input's own landmarks: from a detector's (the neck and pelvis at the shoulder and hip
        midpoints) the torso is longer and the pelvis-to-hip shorter than a motion-capture
        skeleton's of the same person (docs/cli.md);
      swapped_sides (N, 2) bool: with ``sequence``, whether the row's legs (column 0) and arms
        (column 1) were read with the left and right sides swapped and swapped back;
      left_out_of_sequence (N,) bool: with ``sequence``, the rows reconstructed on their own,
        outside the sequence (another person's detection: the ``UserWarning`` above; their
        ``world_points3d`` NaN), as the command line's ``left_out_of_sequence``;
      world_points3d (N, 15, 3): with ``sequence``, the frames placed where a camera standing
        still saw them, as ``camloc reconstruct --sequence --bvh`` animates them (a z-up world
        of the camera, the first pelvis above the origin, planted feet kept in place on the
        floor; docs/animation.md): ``to_bvh(r["world_points3d"], r["fps"],
        r["person_bone_lengths"])`` walks and turns (the command line's file, whose limbs are
        the mean lengths of its frames' poses, has its root up to a few millimetres higher);
        NaN where a frame failed; a ``CamlocWarning`` when rows go more than 15 cm below the
        floor (a camera that moved, depths misjudged, or a floor that is not flat); a camera
        that panned to follow the person gives no such warning and walks them short: place
        them in place then (``to_bvh``). Without ``frames`` the rows are
        taken as consecutive video frames: give a frame the person is missing from as a row
        of NaN, or the rows' ``frames``, so that time passes there (the frames on each side of
        3 or more frames in a row that fail are solved as runs of their own, with the person's
        one set of bone lengths);
      camera_height_shares (3,), camera_height_elevations_deg (3,), camera_height_views: as
        ``Localizer.localize`` returns them (NaN for ``opt``, which localizes no complete pose,
        unless given: then as given);
      camera: the mode used;
      fps: the frames a second the call took (its ``fps``), to give ``to_bvh``, whose own
        default is 30: the animation of a 120 fps video written without it plays 4 times
        slower;
      error: list of N messages, None where the pose was reconstructed.

    Raises ValueError for a wrong shape, layout or camera mode, a ``person_height`` outside
    0.5-2.6 m or given with ``bone_lengths``, bone lengths that are refused
    (a missing or unknown key, not 14 numbers, a length outside 0.01-1.5 m, a bone lengths file
    that cannot be read or is malformed), a focal length that is not finite or under 1 pixel, or a
    principal point without a focal length or an unknown ``camera_height`` (as ``Localizer``);
    OSError / CamlocError for an unreadable or invalid basis; MemoryError, before any work,
    for more poses than the outputs can be allocated for. A focal length or principal point
    wrong by orders of magnitude (the pose over 10 focal lengths from its centroid or the
    principal point) is each pose's error.

    Ctrl-C raises ``KeyboardInterrupt`` after the block of 1,024 poses being reconstructed
    (0.2 s on two idle cores); with ``sequence`` only when the person's frames are solved (a
    20,000-frame sequence: 12 s on two idle cores, twice that on a loaded machine).
    """

def bone_lengths_json(
    lengths: Union[Mapping[str, float], Sequence[float], _Path],
) -> str:
    """The text of a bone lengths JSON file (docs/cli.md) of ``lengths``: a mapping of
    ``BONE_KEYS``, 14 numbers in that order (``reconstruct``'s ``bone_lengths`` or
    ``person_bone_lengths`` row), or such a file. Written to a file, it is what
    ``bone_lengths=PATH`` and ``camloc reconstruct --bone-lengths`` read.

    Raises ValueError for a missing or unknown key, not 14 numbers, a length outside
    0.01-1.5 m, or legs that make a person taller than 2.6 m (lengths in feet are named)."""

def smooth_viewpoints(
    azimuth_deg: npt.ArrayLike,
    elevation_deg: npt.ArrayLike,
    frames: Optional[npt.ArrayLike] = None,
    fps: float = 30.0,
) -> Tuple[np.ndarray, np.ndarray]:
    """One person's continuous viewpoints smoothed over the frames of a video, as ``camloc
    localize --sequence`` smooths them (its ``smoothed_azimuth_deg``, ``smoothed_elevation_deg``):
    each frame's direction is the mean of the unit directions of the frames whose numbers lie
    within 3 of its own (7 frames; docs/cli.md, "Sequences").

    azimuth_deg, elevation_deg (N,): each frame's viewpoint, e.g. ``Localizer.localize``'s
      ``azimuth_deg`` and ``elevation_deg`` of one person's rows in time order; NaN (or
      masked, in a ``numpy.ma.MaskedArray``) where the frame has none.
    frames (N,): the frames' numbers (whole numbers from 0 to 2^53, increasing: ValueError
      otherwise; default: 0, 1, 2, ...), so that frames far apart in time are not averaged.
      All -1 (``read_keypoints``' frames of an input without frame numbers) is the default.
    fps: the video's frames a second (30 by default): at faster rates the frames within as
      long a time (3 x round(fps / 30) numbers on each side; fps above 1,000 taken as 1,000).

    Returns (azimuth_deg, elevation_deg), (N,) each, degrees (azimuth in [0, 360)); NaN where
    the frame had no viewpoint or the directions around it cancel (opposite views). Raises
    ValueError for arrays that are not one-dimensional or of different lengths, an elevation
    outside [-90, 90] (an infinite azimuth is a frame without a viewpoint), or frame numbers
    that are not whole numbers from 0 to 2^53 or do not increase. Smooth only consecutive frames of one camera: on a few frames sampled
    over a long clip it is worse than the frames' own viewpoints.
    """

def read_keypoints(
    path: _Path,
    format: Optional[str] = None,
    layout: Optional[str] = None,
    min_score: float = 0.0,
    image_size: Optional[Union[Tuple[float, float], Sequence[float], str]] = None,
    lsp_invisible: str = "missing",
    derive_torso: bool = True,
    recursive: bool = False,
    max_input_bytes: int = 1 << 30,
) -> Dict[str, Any]:
    """Reads a keypoint file, or every keypoint file (.json, .csv, .npy; YOLO's .txt in a folder
    without those) of a folder.

    format: one of ``FORMATS`` (camloc, lsp, coco, openpose, mmpose, mediapipe, npy, mpii,
      yolo); None detects it from the extension and content.
    layout: the joint layout of .npy arrays and MMPose keypoints (None: from the joint count).
    min_score: joints scoring below it are missing (formats with scores).
    image_size: (width, height) in pixels (a tuple, list or array) or "W,H", to scale MediaPipe's
        and YOLO's normalised coordinates (width first: a portrait phone video is (1080, 1920);
        a ``UserWarning`` says when those of the first 60 poses seen from a side fit a body
        better the other way round; people seen from the front or back are not compared).
    lsp_invisible: ``missing`` or ``use`` (LSP joints marked visible=0; with ``use``, a joint
      with a coordinate <= 0 is a placeholder without a position and stays missing).
    derive_torso: derive a missing pelvis / neck from the hips / shoulders.
    recursive: for a folder, read its sub-folders too.
    max_input_bytes: a text input (JSON, CSV) longer than this is refused (1 GiB by default,
      as the command line's ``--max-input-bytes``; the readers stream, so a larger limit
      costs no memory of its own).

    Returns a dict:
      points (N, 15, 2) float64: the 15 landmarks (``LANDMARKS`` order), NaN where missing;
        ready for ``Localizer.localize(points)`` (layout camloc15);
      derived (N, 15) bool: landmarks computed from other points rather than read;
      ids, sources: lists of N str (pose id; file and place in it);
      frames, persons (N,) int64: video frame and person, -1 where the format has none
        (docs/keypoints.md: e.g. COCO's integer ``image_id`` and ``track_id``, MMPose's
        ``frame_id`` and ``track_id``); a pose without a tracker's id whose format numbers
        people by their order in the frame (OpenPose, MMPose, YOLO) has the person followed
        from frame to frame by where it is, as ``camloc localize --sequence`` does (docs/cli.md,
        Sequences; at 30 frames a second), so that a bystander listed first is not the walker,
        with a ``CamlocWarning`` naming persons that may be one (one starting where and soon
        after another ended) and one naming persons seen for under a third of a second (false
        detections, duplicates);
        split a video's rows by person before ``reconstruct(..., sequence=True)``;
      file_errors: for a folder, (file, message) of each file that could not be read (the
        others are still read, and a ``UserWarning`` names the first); empty for a file;
      pose_errors: (source, message) of each pose the reader refused (a 17-joint pose whose
        first five joints contradict its layout, a ``.npy`` row no pose holds): its row is
        kept, without landmarks, and the poses after it are read, as the command line does
        (a ``UserWarning`` names the first).
    A file or folder without poses gives empty arrays and a ``UserWarning`` ("no poses in
    ...", which ``camloc`` on the command line makes an error); a folder without poses where
    a file could not be read raises that file's error, as reading it alone does. A
    ``min_score`` that leaves no pose a landmark is warned of (is it on the scores' scale?),
    and so is the default ``min_score`` of 0 when 1% or more of the landmarks of the first
    2,000 poses score below 0.3 (used as detected; docs/keypoints.md).

    Raises OSError if the file cannot be read, CamlocError if it is malformed (the message
    names the file and place), ValueError for bad options (also a ``layout`` the file's format
    does not take: only ``.npy`` arrays and MMPose keypoints take one, other formats only their
    own).
    """

def to_bvh(
    points3d: npt.ArrayLike,
    fps: float = 30.0,
    limb_lengths: Optional[Union[Mapping[str, float], Sequence[float], _Path]] = None,
    unit_m: float = 0.01,
) -> str:
    """The 3D poses as the text of a BVH animation file, for Blender, MotionBuilder and other
    3D packages (the writer of ``camloc reconstruct --bvh``; docs/animation.md).

    points3d: (N, 15, 3) frames (or one pose (15, 3)) in metres, z up, ``LANDMARKS`` order, as
      ``reconstruct`` returns them (masked entries of a ``numpy.ma.MaskedArray`` are NaN); a
      frame that is all NaN (a pose that could not be
      reconstructed, or a video frame the person is missing from) is filled: between two
      complete frames it turns from one to the other (the pelvis along a straight line, each
      limb's direction along the great circle), before the first and after the last it holds
      that frame.
    fps: frames per second (``Frame Time`` = 1 / fps): the video's, as ``reconstruct``
      returns the one it took (``r["fps"]``).
    limb_lengths: the 14 bone lengths in metres, as ``reconstruct``'s ``bone_lengths`` takes
      them (a mapping of ``BONE_KEYS``, 14 numbers in that order, or a bone lengths JSON file;
      each 0.01-1.5 m, the legs a person of 2.6 m at most); default: the mean of each limb over
      the complete frames, held to the same range (points in millimetres raise ValueError).
    unit_m: metres per file unit (0.01: centimetres; Blender imports them with scale 0.01),
      from 1e-6 to 1000.

    The skeleton is a T-pose in MotionBuilder naming (``Hips``, ``LeftUpLeg``, ``LeftLeg``,
    ``LeftFoot``, ``Neck``, ``Head``, ``LeftArm``, ``LeftForeArm``, ``LeftHand``, ...) whose
    joint origins are the 15 landmarks; each frame keeps its limb directions, with the given
    lengths, and the root follows the pelvis. The file is y up: a point (x, y, z) is
    (x, z, -y) / unit_m in it. The points are written where they are: a pose of
    ``reconstruct`` has its pelvis at the origin and its feet below the floor; to make one
    pose stand as ``camloc reconstruct --bvh`` does, lift it: ``p[:, 2] -= p[:, 2].min()``.
    The frames of a clip have each their own lowest point (one shift for all leaves the
    frames of a squat floating): give ``reconstruct(..., sequence=True)``'s
    ``world_points3d``, or for a camera that panned or moved (whose motion would become the
    person's) the frames in place as ``--bvh-in-place`` makes them, ``r["points3d"] +
    r["world_points3d"][:, :1] * [0, 0, 1]`` (each pelvis above the origin, at the height
    the placement gives it).

    Raises ValueError for a wrong shape, a frame with some (not all) NaN, no complete frame, a
    limb without direction, an fps outside 0.000278 to 1,000,000, a non-positive unit or
    length, or a unit out of range;
    MemoryError, before any work, for more frames than can be allocated.
    """

def read_bvh(path: _Path, unit_m: float = 0.0254 / 0.45) -> Dict[str, Any]:
    """The 15 landmarks of every frame of a BVH file (camloc's reader: CMU or MotionBuilder
    joint names, docs/conventions.md section 3).

    unit_m: metres per file unit (default: CMU's unit, 1/0.45 inch; 0.01 for the files
      ``to_bvh`` and ``camloc reconstruct --bvh`` write).

    Returns a dict:
      points3d (N, 15, 3) float64: metres, z up (a file point (x, y, z) is (x, -z, y) * unit_m);
      frame_time_s: seconds between frames.

    Raises OSError if the file cannot be read, CamlocError if it is malformed (the message names
    the line) or larger than 1 GiB, ValueError for a unit outside 1e-6 to 1000.
    """
