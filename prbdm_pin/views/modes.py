"""The figure of a chain's mode shapes beside the truth's: one panel per mode.

Each panel draws what the mode does along the span: the deflection w (z displacement, m) of a
bending mode, the in-plane y displacement of an in-plane one, the twist (rad) of a torsion mode.
The chain's curve is its points (root, nodes, tip: the rigid links are straight between them;
a twist is constant along each link, drawn as steps), the truth's its shape at stations along
the span. Both are scaled to a largest magnitude of 1 and the truth's sign is the one that
agrees best with the chain's, so the two are on the same scale. The title gives the chain's
frequency (Hz), the truth's and the signed error 100 (f_model / f_truth - 1) %.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError
from ..options.validate import real_vector
from .chain_geometry import ChainModes, chain_modes, check_model

__all__ = ["TruthShapes", "plot_mode_shapes", "mode_curve"]

# the component each kind draws: (index into the (P, 3) displacement, or None: the twist)
_COMPONENT = {"bending": 2, "in-plane": 1, "torsion": None}
_LABEL = {"bending": "deflection w / max|w| (-)", "in-plane": "in-plane y / max|y| (-)",
          "torsion": "twist / max|twist| (-)"}


@dataclass(frozen=True, eq=False)
class TruthShapes:
    """The truth's mode shapes along the span and its frequencies, paired with the chain's.

    Attributes
    ----------
    omega_rad_s : ndarray, shape (K,)
        The truth's frequency paired with each of the chain's modes, rad/s, in the chain's
        order; NaN where no truth mode is paired with it.
    stations_m : ndarray, shape (S,) or None
        Stations along the span, m; None when the truth's shapes are not known (the panels
        then give its frequency and the error only).
    deflection : ndarray, shape (K, S) or None
        Each mode's z deflection at the stations (any scale).
    twist : ndarray, shape (K, S) or None
        Each mode's twist at the stations (any scale); None where the truth has none (a 1D
        bending beam).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> x = np.linspace(0.0, 1.0, 21)  # m
    >>> bL = 1.8751041  # Euler-Bernoulli's first cantilever mode, L = 1 m
    >>> s = (np.sinh(bL) - np.sin(bL)) / (np.cosh(bL) + np.cos(bL))
    >>> phi = np.cosh(bL * x) - np.cos(bL * x) - s * (np.sinh(bL * x) - np.sin(bL * x))
    >>> shapes = pp.TruthShapes(omega_rad_s=[51.87], stations_m=x, deflection=phi[None, :])
    >>> shapes.deflection.shape, round(float(shapes.deflection[0, -1]), 4)  # the tip: 2 (any scale)
    ((1, 21), 2.0)
    >>> pp.TruthShapes(omega_rad_s=[51.87]).stations_m is None  # frequencies only
    True
    """

    omega_rad_s: np.ndarray
    stations_m: np.ndarray | None = None
    deflection: np.ndarray | None = None
    twist: np.ndarray | None = None

    def __post_init__(self) -> None:
        """Check sizes (BeamInputError naming the field)."""
        w = np.asarray(self.omega_rad_s, dtype=float)
        # NaN: a chain mode no truth mode is paired with
        if w.ndim != 1 or np.any(np.isinf(w)) or np.any(w[np.isfinite(w)] <= 0.0):
            raise BeamInputError(f"truth.omega_rad_s = {self.omega_rad_s!r:.80}: must be a "
                                 "list of frequencies > 0 (rad/s; NaN: no truth mode paired)")
        object.__setattr__(self, "omega_rad_s", w)
        if self.stations_m is None:
            return
        x = real_vector("truth.stations_m", self.stations_m, "m")
        object.__setattr__(self, "stations_m", x)
        for name in ("deflection", "twist"):
            a = getattr(self, name)
            if a is None:
                continue
            a = np.asarray(a, dtype=float)
            if a.ndim != 2 or a.shape != (w.size, x.size) or not np.all(np.isfinite(a)):
                raise BeamInputError(f"truth.{name}: must be finite, shape ({w.size}, "
                                     f"{x.size}): one row per frequency, one column per station")
            object.__setattr__(self, name, a)


def mode_curve(modes: ChainModes, k: int) -> tuple[np.ndarray, np.ndarray, str]:
    """Return the chain's curve of mode ``k`` (0-based): x (m), the value (unit max), its kind.

    The value is the component the mode's kind draws (module docstring), scaled to a largest
    magnitude of 1.
    """
    kind = modes.kinds[k]
    c = _COMPONENT[kind]
    y = modes.twist_rad[k] if c is None else modes.displacement_m[k, :, c]
    return modes.stations_m.copy(), _unit(y), kind


def _unit(y: np.ndarray) -> np.ndarray:
    peak = float(np.max(np.abs(y)))
    return np.asarray(y, dtype=float) / peak if peak > 0.0 else np.asarray(y, dtype=float)


def _truth_curve(truth: TruthShapes | None, k: int, kind: str, x_model: np.ndarray,
                 y_model: np.ndarray) -> np.ndarray | None:
    """Return the truth's mode ``k`` of the chain's ``kind``, unit max, signed as the chain's."""
    if (truth is None or truth.stations_m is None or k >= truth.omega_rad_s.size
            or not np.isfinite(truth.omega_rad_s[k])):
        return None
    rows = {"bending": truth.deflection, "torsion": truth.twist}.get(kind)
    if rows is None:
        return None  # the truth's shapes carry no in-plane motion
    y = _unit(rows[k])
    # the sign of best agreement at the truth's stations (the chain's curve interpolated)
    if kind == "torsion":
        at = y_model[np.clip(np.searchsorted(x_model, truth.stations_m, side="right") - 1, 0,
                             x_model.size - 1)]
    else:
        at = np.interp(truth.stations_m, x_model, y_model)
    return -y if float(at @ y) < 0.0 else y


def plot_mode_shapes(model, n_modes: int | None = None, truth: TruthShapes | None = None, *,
                     axes=None, path=None, title: str = ""):
    """Draw the chain's mode shapes beside the truth's, one panel per mode; return the Figure.

    Parameters
    ----------
    model : PrbdmModel
        The chain (clamped or on a hub; planar or spatial).
    n_modes : int, optional
        How many modes (default all the chain's flexible modes, at most 6).
    truth : TruthShapes, optional
        The truth's frequencies (rad/s) and shapes, paired with the chain's modes in order;
        without it the chain's shapes are drawn alone.
    axes : sequence of matplotlib Axes, optional
        One per mode to draw into (default: a new figure with a panel per mode).
    path : path-like, optional
        Also write the figure there (PNG, PDF or SVG by the suffix).
    title : str
        The figure's title (default: the chain and whether the truth is drawn).

    Returns
    -------
    matplotlib.figure.Figure
        The figure (of ``axes`` when given).

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> truth = pp.compute_truth(beam, model="beam", modes=2)
    >>> path = Path(tempfile.mkdtemp()) / "modes.png"
    >>> fig = pp.plot_mode_shapes(model, truth=pp.TruthShapes(truth.omega_rad_s), path=path)
    >>> len(fig.axes), path.exists()
    (2, True)
    >>> print(fig.axes[0].get_title())
    mode 1 (bending): 9.383 Hz
    truth 8.255 Hz, error +13.67 %
    >>> w, w_truth = float(model.natural_frequencies()[0]), float(truth.omega_rad_s[0])  # rad/s
    >>> round(w / (2 * 3.141592653589793), 3), round(100 * (w / w_truth - 1), 2)  # Hz, %
    (9.383, 13.67)
    """
    from .plots import figure_format, new_figure, save_figure

    check_model(model)
    if path is not None:
        figure_format(path)  # a bad suffix refused before drawing
    if n_modes is None:
        n_modes = min(chain_modes(model).omega_rad_s.size, 6)
    modes = chain_modes(model, n_modes)
    if axes is None:
        ncol = min(n_modes, 3)
        nrow = -(-n_modes // ncol)
        fig = new_figure((4.2 * ncol, 3.0 * nrow + 0.6))
        axes = [fig.add_subplot(nrow, ncol, i + 1) for i in range(n_modes)]
        own = True
    else:
        axes = list(np.ravel(axes))
        if len(axes) < n_modes:
            raise BeamInputError(f"axes: {len(axes)} given for {n_modes} modes; give one per "
                                 "mode")
        fig = axes[0].figure
        own = False
    for k in range(n_modes):
        ax = axes[k]
        x, y, kind = mode_curve(modes, k)
        step = "steps-post" if kind == "torsion" else "default"
        ax.plot(x, y, "o-", color="C0", drawstyle=step, label=f"{model.n_joints}R PRBDM")
        f_model = modes.omega_rad_s[k] / (2.0 * np.pi)
        head = f"mode {k + 1} ({kind}): {f_model:.4g} Hz"
        if truth is not None and k < truth.omega_rad_s.size and not np.isfinite(
                truth.omega_rad_s[k]):
            head += "\nno truth mode paired"
        elif truth is not None and k < truth.omega_rad_s.size:
            f_truth = truth.omega_rad_s[k] / (2.0 * np.pi)
            head += f"\ntruth {f_truth:.4g} Hz, error {100.0 * (f_model / f_truth - 1.0):+.2f} %"
            yt = _truth_curve(truth, k, kind, x, y)
            if yt is not None:
                ax.plot(truth.stations_m, yt, "--", color="C1", label="truth")
        ax.axhline(0.0, color="0.8", lw=0.6)
        ax.set_title(head, fontsize=8)
        ax.set_xlabel("x along the span (m)", fontsize=8)
        ax.set_ylabel(_LABEL[kind], fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=7, loc="best")
    if own:
        shown = "with the truth" if truth is not None and truth.stations_m is not None else (
            "truth frequencies only: its shapes are not available" if truth is not None
            else "truth not available: the model alone")
        fig.suptitle(title or f"{model.n_joints}R PRBDM mode shapes ({shown})", fontsize=9)
        fig.tight_layout()
    if path is not None:
        save_figure(fig, path)
    return fig
