"""An animation of a simulated response: the chain's links moving, as a GIF (or MP4).

Each frame draws the chain (root, nodes, tip: :func:`~prbdm_pin.views.chain_geometry.
chain_points`) at one sample of the trajectory in a side view (x, z), beside its straight pose;
a spatial chain adds a top view (x, y) and the tip section seen from the tip (its width turned
by the tip's twist). The frames are samples evenly spread over the trajectory, the first its
first sample. matplotlib's animation writes them: PillowWriter for a GIF (pillow is a
matplotlib dependency), FFMpegWriter for an MP4 where ffmpeg is installed.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

from ..errors import BeamInputError
from ..io.atomic import atomic_path
from .chain_geometry import chain_points, check_model

__all__ = ["ANIMATION_FORMATS", "animation_format", "animate_response", "frame_samples"]

ANIMATION_FORMATS = ("gif", "mp4")


def animation_format(path: str | os.PathLike) -> str:
    """Return ``gif`` or ``mp4`` by the suffix of ``path``.

    Raises
    ------
    BeamInputError
        Another suffix, or ``.mp4`` without ffmpeg (naming the path).
    """
    fmt = Path(path).suffix.lower().lstrip(".")
    if fmt not in ANIMATION_FORMATS:
        raise BeamInputError(f"path = {str(path)!r}: an animation is written as .gif or .mp4 "
                             "(by the suffix)")
    if fmt == "mp4":
        from matplotlib.animation import FFMpegWriter

        if not FFMpegWriter.isAvailable():
            raise BeamInputError(f"path = {str(path)!r}: an MP4 needs ffmpeg, which is not "
                                 "installed here; write a .gif instead")
    return fmt


def frame_samples(n_samples: int, frames: int) -> np.ndarray:
    """Return the sample index of each of ``frames`` frames spread evenly over ``n_samples``."""
    if not (isinstance(frames, int) and not isinstance(frames, bool) and frames >= 1):
        raise BeamInputError(f"frames = {frames!r}: must be an integer >= 1")
    return np.rint(np.linspace(0.0, n_samples - 1, frames)).astype(int)


def _twist_bar(model, q: np.ndarray, data) -> np.ndarray:
    """Return the tip section's ends (y, z), m: the half-width along the tip frame's y."""
    w = 0.0 if model.beam is None else float(model.beam.half_width_m[-1])
    _, R = model.tip_pose(q, data)
    return np.array([-w * R[1:, 1], w * R[1:, 1]])


def animate_response(model, trajectory, path: str | os.PathLike, *, frames: int = 60,
                     fps: float = 20.0, title: str = "", progress: bool | None = None) -> Path:
    """Write an animation of ``trajectory`` of ``model`` to ``path`` (GIF or MP4); return it.

    Parameters
    ----------
    model : PrbdmModel
        The chain simulated (clamped or on a hub).
    trajectory : Trajectory
        The response (:func:`prbdm_pin.simulate`); ``q_rad`` rows are the poses, rad.
    path : path-like
        ``.gif`` (pillow) or ``.mp4`` (ffmpeg; refused where it is not installed).
    frames : int
        Frames, spread evenly over the samples (the first is the first sample).
    fps : float
        Frames per second of the file, 1/s.
    title : str
        Above the views (default: the chain and the time span).
    progress : bool, optional
        A progress bar over the frames (default: only when stderr is a terminal).

    Returns
    -------
    Path
        The file, written atomically.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from PIL import Image
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> run = pp.simulate(model, 0.2, q0=[0.01, 0.0])  # s, rad
    >>> path = pp.animate_response(model, run, Path(tempfile.mkdtemp()) / "ring.gif", frames=4)
    >>> path.suffix, Image.open(path).n_frames
    ('.gif', 4)
    """
    from matplotlib.animation import FFMpegWriter, FuncAnimation, PillowWriter

    from .plots import new_figure

    check_model(model)
    fmt = animation_format(path)
    if not (isinstance(fps, (int, float)) and np.isfinite(fps) and 0.0 < fps <= 100.0):
        raise BeamInputError(f"fps = {fps!r}: must be a number in (0, 100] (frames per second)")
    idx = frame_samples(int(trajectory.t_s.size), frames)
    d = model.new_data()
    pts = chain_points(model, np.asarray(trajectory.q_rad)[idx], d)  # (F, P, 3)
    rest = chain_points(model, None, d)
    spatial = bool(model.axes.spatial)
    fig = new_figure((9.0, 3.6) if spatial else (6.5, 3.6))
    side = fig.add_subplot(1, 3 if spatial else 1, (1, 2) if spatial else 1)
    span = float(np.ptp(np.r_[pts[..., 0].ravel(), rest[:, 0]]))
    pad = 0.05 * span
    lo, hi = min(pts[..., 2].min(), 0.0), max(pts[..., 2].max(), 0.0)
    side.plot(rest[:, 0], rest[:, 2], ":", color="0.6", label="straight pose")
    (line,) = side.plot([], [], "o-", color="C0", label="chain")
    side.set_xlim(rest[:, 0].min() - pad, pts[..., 0].max() + pad)
    # the motion's own range: small deflections fill the view (the axes give the scale)
    pad_z = 0.15 * (hi - lo) if hi > lo else 0.01 * span
    side.set_ylim(lo - pad_z, hi + pad_z)
    side.set_xlabel("x (m)")
    side.set_ylabel("z (m)")
    side.legend(fontsize=7, loc="lower left")
    stamp = side.text(0.02, 0.95, "", transform=side.transAxes, fontsize=8, va="top")
    if spatial:
        top = fig.add_subplot(2, 3, 3)
        end = fig.add_subplot(2, 3, 6)
        top.plot(rest[:, 0], rest[:, 1], ":", color="0.6")
        (line_top,) = top.plot([], [], "o-", color="C0")
        ylim = max(float(np.abs(pts[..., 1]).max()), pad)
        top.set_xlim(side.get_xlim())
        top.set_ylim(-1.2 * ylim, 1.2 * ylim)
        top.set_xlabel("x (m)", fontsize=8)
        top.set_ylabel("y (m)", fontsize=8)
        top.set_title("top view", fontsize=8)
        bars = np.array([_twist_bar(model, q, d) for q in np.asarray(trajectory.q_rad)[idx]])
        tip = pts[:, -1, :]
        (line_end,) = end.plot([], [], "-", color="C0", lw=2, label="tip section")
        r = float(np.abs(bars).max()) + float(np.abs(tip[:, 1:]).max()) + 1e-9
        end.set_xlim(-1.1 * r, 1.1 * r)
        end.set_ylim(-1.1 * r, 1.1 * r)
        end.set_aspect("equal")
        end.set_xlabel("y (m)", fontsize=8)
        end.set_ylabel("z (m)", fontsize=8)
        end.set_title("tip section, seen from the tip (twist)", fontsize=8)
        for a in (top, end):
            a.tick_params(labelsize=7)
    t = np.asarray(trajectory.t_s)[idx]
    fig.suptitle(title or f"{model.n_joints}R PRBDM, {t[0]:.3g} to {t[-1]:.3g} s", fontsize=9)
    fig.tight_layout()

    def draw(i: int):
        line.set_data(pts[i, :, 0], pts[i, :, 2])
        stamp.set_text(f"t = {t[i]:.4g} s")
        if spatial:
            line_top.set_data(pts[i, :, 0], pts[i, :, 1])
            line_end.set_data(tip[i, 1] + bars[i, :, 0], tip[i, 2] + bars[i, :, 1])
            return line, stamp, line_top, line_end
        return line, stamp

    anim = FuncAnimation(fig, draw, frames=idx.size, blit=False)
    writer = PillowWriter(fps=fps) if fmt == "gif" else FFMpegWriter(fps=fps)
    show = sys.stderr.isatty() if progress is None else bool(progress)
    bar = None
    if show:
        from tqdm import tqdm

        bar = tqdm(total=idx.size, desc="frames", unit="frame", file=sys.stderr)
    p = Path(path)
    try:
        with atomic_path(p) as tmp:
            # the writers pick the container by the file's suffix, which the temporary's lacks
            named = f"{tmp}.{fmt}"
            try:
                anim.save(named, writer=writer, progress_callback=None if bar is None
                          else (lambda i, n: bar.update(1)))
                os.replace(named, tmp)
            finally:
                if os.path.exists(named):
                    os.remove(named)
    finally:
        if bar is not None:
            bar.close()
    return p
