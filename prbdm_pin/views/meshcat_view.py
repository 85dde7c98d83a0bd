"""Pinocchio's meshcat visualiser of a chain: each link a box, the response played in a browser.

meshcat is optional: :func:`check_meshcat` refuses its absence before any work. The boxes span
each link's length, the beam's width at the link's middle and its thickness (a model read
from a URDF, which has no beam, gets boxes 1/50 of the span wide and 1/10 of that thick).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..errors import BeamInputError
from .chain_geometry import chain_frames, check_model

__all__ = ["check_meshcat", "link_boxes", "open_meshcat"]


def check_meshcat() -> None:
    """Refuse when meshcat is not installed (BeamInputError saying how to install it)."""
    import importlib.util

    if importlib.util.find_spec("meshcat") is None:
        raise BeamInputError("--meshcat: meshcat is not installed here (pip install meshcat); "
                             "nothing was written")


def link_boxes(model) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """Return each link's box: (Pinocchio frame id, centre in that frame (m), size (m, (3,)))."""
    frames = chain_frames(model)[:-1]  # the root and each node start a link
    span = float(np.sum(model.lengths_m))
    out = []
    for i, (f, length) in enumerate(zip(frames, model.lengths_m, strict=True)):
        if model.beam is None:
            width, thick = span / 50.0, span / 500.0
        else:
            mid = float(model.sections.start_m[i]) + 0.5 * float(length)
            width = 2.0 * float(model.beam.half_width_at(mid))
            thick = float(model.beam.thickness_at(mid))
        out.append((f, np.array([0.5 * float(length), 0.0, 0.0]),
                    np.array([float(length), width, thick])))
    return out


def open_meshcat(model, trajectory=None, *, open_browser: bool = True):
    """Show ``model`` in Pinocchio's meshcat visualiser and play ``trajectory`` (if given).

    Returns the ``pinocchio.visualize.MeshcatVisualizer`` (its ``viewer.url()`` is the page).

    Parameters
    ----------
    model : PrbdmModel
        The chain (clamped or on a hub); each link is drawn as a box (module docstring).
    trajectory : Trajectory, optional
        A response (:func:`prbdm_pin.simulate`) played at its own sample times, s.
    open_browser : bool
        Open the page in a browser (default True); False only starts the viewer's server.

    Returns
    -------
    pinocchio.visualize.MeshcatVisualizer
        The visualiser, its model loaded and shown at the straight pose.

    Raises
    ------
    InputTypeError
        ``model`` not a PrbdmModel.
    BeamInputError
        meshcat not installed (saying how to install it), refused before anything starts.

    Examples
    --------
    >>> import importlib.util
    >>> import prbdm_pin as pp
    >>> pp.open_meshcat("chain.urdf")  # a model, not a file name
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.InputTypeError: model = 'chain.urdf': must be a ...
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> if importlib.util.find_spec("meshcat") is None:  # refused, saying how to install it
    ...     try:
    ...         pp.open_meshcat(model, open_browser=False)
    ...     except pp.BeamInputError as err:
    ...         print("pip install meshcat" in str(err))
    ... else:  # installed: a viewer would start a server, which a doctest does not do
    ...     print(True)
    True
    """
    check_model(model)
    check_meshcat()
    import coal
    from pinocchio.visualize import MeshcatVisualizer

    pm = model.pin_model
    geom = pin.GeometryModel()
    for i, (f, centre, size) in enumerate(link_boxes(model)):
        frame = pm.frames[f]
        place = frame.placement * pin.SE3(np.eye(3), centre)
        obj = pin.GeometryObject(f"link_{i}", frame.parentJoint, f, place, coal.Box(*size))
        obj.meshColor = np.array([0.2, 0.4, 0.8, 1.0])
        geom.addGeometryObject(obj)
    viz = MeshcatVisualizer(pm, geom, geom)
    viz.initViewer(open=open_browser)
    viz.loadViewerModel()
    viz.display(np.zeros(pm.nq))
    if trajectory is not None:
        t = np.asarray(trajectory.t_s)
        dt = float(t[1] - t[0]) if t.size > 1 else 0.0
        viz.play(np.asarray(trajectory.q_rad), dt)
    return viz
