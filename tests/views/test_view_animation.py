"""The response animation read back with PIL: its frame count, and the pose its first frame shows.

The trajectory is made by hand: it starts at a pose A bent down and ends at B = -A/2 bent up.
The tip's drawn height above the straight pose, in pixels, measured on the first and the last
frame, must stand in the ratio of the tip heights that forward kinematics by hand gives for A
and B (a linear map from metres to pixels cancels in the ratio).
"""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import prbdm_pin as pp
from prbdm_pin.simulation.trajectory import Trajectory
from prbdm_pin.views.animate import animate_response

LENGTHS = np.array([0.25, 0.2, 0.15])
BLUE = np.array([31, 119, 180])  # matplotlib's C0: the chain
GREY = np.array([153, 153, 153])  # 0.6 grey: the straight pose
# colours after the GIF's palette quantisation stay within this distance (0..255 per channel)
COLOUR_TOL = 40.0


@pytest.fixture(scope="module")
def model(tapered):
    lengths = LENGTHS * tapered.length_m / LENGTHS.sum()
    return pp.build_model(tapered, lengths, pp.finite_segment_stiffness(tapered, lengths))


def _trajectory(q_start: np.ndarray, samples: int) -> Trajectory:
    s = np.linspace(0.0, 1.0, samples)[:, None]
    q = q_start[None, :] * (1.0 - 1.5 * s)  # A at the first sample, -A/2 at the last
    t = np.linspace(0.0, 0.1, samples)
    return Trajectory(t, q, np.zeros_like(q), np.zeros((samples, 3)), samples, "by hand", 0.0)


def _tip_z(lengths: np.ndarray, q: np.ndarray) -> float:
    # a rotation th about +y turns the x axis to (cos th, 0, -sin th); link i follows joint i
    return float(-np.sum(lengths[1:] * np.sin(np.cumsum(q))))


def _near(rgb: np.ndarray, colour: np.ndarray) -> np.ndarray:
    return np.linalg.norm(rgb.astype(float) - colour, axis=-1) < COLOUR_TOL


def _tip_height_px(frame: Image.Image) -> tuple[float, float]:
    """The tip marker's height above the straight pose's line (px, up positive), its error."""
    rgb = np.asarray(frame.convert("RGB"))
    rows, cols = np.nonzero(_near(rgb, BLUE))
    tip = cols >= cols.max() - 3  # the rightmost blue: the tip marker
    grey_rows, _ = np.nonzero(_near(rgb, GREY))
    straight = np.bincount(grey_rows).argmax()  # the dotted line's row holds most grey
    # the marker's centre from its pixels' rows, and the line's row: 1 px each at most
    return float(straight - rows[tip].mean()), 2.0


def test_the_gif_has_the_frames_asked_and_starts_at_the_first_pose(model, tmp_path):
    A = np.array([0.15, 0.2])
    path = animate_response(model, _trajectory(A, 13), tmp_path / "r.gif", frames=7,
                            progress=False)
    im = Image.open(path)
    assert im.n_frames == 7
    im.seek(0)
    h0, e0 = _tip_height_px(im)
    im.seek(im.n_frames - 1)
    h1, e1 = _tip_height_px(im)
    lengths = np.asarray(model.lengths_m)
    ratio = _tip_z(lengths, A) / _tip_z(lengths, -0.5 * A)
    assert h0 < 0.0 < h1  # first bent down (A), last bent up (B)
    # the ratio's error from a pixel's quantisation of each height
    tol = abs(ratio) * (e0 / abs(h0) + e1 / abs(h1))
    assert abs(h0 / h1 - ratio) <= tol, (h0, h1, ratio)


def test_bad_input_is_refused_by_name_and_nothing_written(model, tmp_path):
    tr = _trajectory(np.array([0.1, 0.1]), 5)
    with pytest.raises(pp.BeamInputError, match="path"):
        animate_response(model, tr, tmp_path / "r.avi")
    with pytest.raises(pp.BeamInputError, match="frames = 0"):
        animate_response(model, tr, tmp_path / "r.gif", frames=0)
    with pytest.raises(pp.BeamInputError, match="fps"):
        animate_response(model, tr, tmp_path / "r.gif", fps=0.0)
    from matplotlib.animation import FFMpegWriter

    if not FFMpegWriter.isAvailable():
        with pytest.raises(pp.BeamInputError, match="ffmpeg"):
            animate_response(model, tr, tmp_path / "r.mp4")
    assert list(tmp_path.iterdir()) == []
