"""``calibrate``: a clamped planar PRBDM's E, rho and damping fitted to measurements.

The data: a free ring-down, a trajectory driven by measured inputs or an FRF
(:mod:`.calibration_measured`; the last two's model: :mod:`.calibrate_measured`).

The parameters are scale factors of E (every spring scales with E) and of rho (every link's mass
and inertia), the ratio ``damping[k]`` of mode k + 1 (the modal damping of
``linearize(..., damping="modal")``) and constant sensor offsets ``offset[CHANNEL]``. The
ring-down's unknown initial state (each mode's amplitude and phase, as (a_k, b_k):
:mod:`.calibration_basis`) and the offsets are linear in the response and are
eliminated by variable projection (Golub and Pereyra; Kaufman's Jacobian), so the nonlinear
search sees only the named parameters. A grid over E/rho first puts the frequencies within the
basin of the phase: over T seconds a relative frequency error e drifts mode 1 by omega_1 T e rad.

Standard errors are s^2 (J^T J)^-1 of the full problem (the parameters and the initial state
together), s^2 the residual's mean square over N - p degrees of freedom: the linearised
covariance, which the projected problem gives too. Each channel is weighted by 1 / its data's
standard deviation, so channels of different units count alike. A Jacobian whose columns (each
scaled to unit length) have a condition number beyond 1 / sqrt(EPS) is refused, naming the
parameters of its near-null direction: a free ring-down sees E / rho only, and so does a
response to a base acceleration (its load scales with rho); a response to a force sees both,
and so does a ring-down on a hub of known inertia (:mod:`.calibrate_hub`).
"""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np
from scipy.optimize import least_squares

from ..errors import BeamInputError, InputTypeError
from ..options.validate import check_damping_ratio
from .calibrate_measured import chain_gains, forced_start, measured_problem
from .calibration_data import RingDown, channel_name
from .calibration_measured import DrivenTrajectory, FrequencyResponse, read_calibration_data
from .calibration_problem import DAMPING, OFFSET, RAYLEIGH, Problem, rank_check, start
from .calibration_result import CalibrationResult, calibration_result

__all__ = ["CalibrationResult", "calibrate", "PARAMETER_NAMES"]

PARAMETER_NAMES = ("E", "rho", "damping[k]", *RAYLEIGH, "offset[CHANNEL]")
_SCALE_BOUNDS = (1e-3, 1e3)
_ZETA_MAX = 0.99


def _parse(parameters) -> tuple[tuple[str, ...], list[int]]:
    if isinstance(parameters, str):
        parameters = [p.strip() for p in parameters.split(",")]
    if not isinstance(parameters, Sequence) or not parameters:
        raise InputTypeError(f"parameters = {parameters!r:.60}: must name at least one of "
                             "E, rho, damping[k]")
    names, modes = [], []
    for i, p in enumerate(parameters):
        if not isinstance(p, str):
            raise InputTypeError(f"parameters[{i}] = {p!r:.40}: must be a string")
        m = DAMPING.match(p)
        if p not in ("E", "rho", *RAYLEIGH) and m is None and OFFSET.match(p) is None:
            raise BeamInputError(f"parameters[{i}] = {p!r:.40}: must be E, rho, damping[k] "
                                 "(k = 0 for mode 1), rayleigh_alpha, rayleigh_beta or "
                                 "offset[CHANNEL]")
        if p in names:
            raise BeamInputError(f"parameters[{i}] = {p!r}: named twice")
        names.append(p)
        if m is not None:
            modes.append(int(m.group(1)))
    if modes and set(RAYLEIGH) & set(names):
        raise BeamInputError("parameters: damping[k] and rayleigh_alpha/rayleigh_beta are two "
                             "damping forms; fit one")
    return tuple(names), modes


def _chain_modes(model, channels: tuple[str, ...]):
    """Return omega0 (n,) and the modal Cq, Cv (c, n) of the clamped planar chain."""
    w0, cq, cv, _ = chain_gains(model, ("tip_force_z",), channels,
                                f"data: the channels ({', '.join(channels)}) are outputs")
    return w0, cq, cv


def calibrate(model, data: RingDown | DrivenTrajectory | FrequencyResponse | str | os.PathLike,
              parameters: Sequence[str] | str = ("E", "damping[0]", "damping[1]"), *,
              n_modes: int | None = None, damping_ratio: float = 0.02,
              initial_state: bool | None = None) -> CalibrationResult:
    """Fit E, rho and the damping of ``model`` to a ring-down, a driven trajectory or an FRF.

    Parameters
    ----------
    model : PrbdmModel
        A planar chain with its beam (the E and rho it has are the starting values), clamped
        or on a hub of known inertia (a ring-down then fits E and rho apart; ``damping[k]`` and
        ``n_modes`` count the flexible modes, the hub's rigid rotation undamped).
    data : RingDown, DrivenTrajectory, FrequencyResponse or path
        The measurement (a CSV path: its kind told by its header,
        :func:`~prbdm_pin.fitting.calibration_measured.read_calibration_data`).
    parameters : sequence of str or str
        Names from ``E``, ``rho``, ``damping[k]`` (the ratio of mode k + 1),
        ``rayleigh_alpha`` (1/s) and ``rayleigh_beta`` (s) of C = alpha M + beta K (mode k's
        ratio alpha / (2 omega_k) + beta omega_k / 2; not with ``damping[k]``),
        ``offset[CHANNEL]`` (a constant sensor offset of that data channel; not for an FRF),
        or one comma-separated string.
    n_modes : int, optional
        The lowest modes whose initial state (amplitude and phase) is fitted: a ring-down's
        response (default: enough for every ``damping[k]``, two with both Rayleigh
        coefficients, else 1), a driven trajectory's with ``initial_state`` (same default).
        An FRF and a trajectory from rest take none: every chain mode is in their response.
    damping_ratio : float
        The ratio of the modes whose damping is not fitted, and the fitted ones' start.
    initial_state : bool, optional
        A driven trajectory: fit the initial state of its lowest ``n_modes`` modes (default
        False: from rest). A ring-down always has it fitted, an FRF never.

    Returns
    -------
    CalibrationResult

    Raises
    ------
    BeamInputError
        Naming the argument: unknown parameters, too few samples for the unknowns, a
        constant channel, a parameter the data cannot determine (and which).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> w = np.sqrt(1.1) * model.natural_frequencies()[0]  # rad/s: E 10 % up
    >>> t = np.arange(500) * 2e-3  # s
    >>> y = 1e-3 * np.exp(-0.01 * w * t) * np.cos(w * np.sqrt(1 - 0.01**2) * t)  # m, ratio 0.01
    >>> data = pp.RingDown(t_s=t, y=y[:, None], channels=("tip_z",))
    >>> cal = pp.calibrate(model, data, ("E", "damping[0]"))
    >>> round(cal.E_scale, 4), round(float(cal.damping_ratio[0]), 4)
    (1.1, 0.01)
    """
    from ..model.prbdm_model import PrbdmModel

    if not isinstance(model, PrbdmModel):
        raise InputTypeError(f"model = {model!r:.60}: must be a PrbdmModel")
    names, modes = _parse(parameters)
    if isinstance(data, (str, os.PathLike)):
        data = read_calibration_data(data)
    if not isinstance(data, (RingDown, DrivenTrajectory, FrequencyResponse)):
        raise InputTypeError(f"data = {data!r:.60}: must be a RingDown, DrivenTrajectory, "
                             "FrequencyResponse or a CSV path")
    if initial_state is not None and not isinstance(initial_state, bool):
        raise InputTypeError(f"initial_state = {initial_state!r:.40}: must be True or False")
    ring = isinstance(data, RingDown)
    free = ring or bool(initial_state) and isinstance(data, DrivenTrajectory)
    if initial_state is not None and free != initial_state:
        raise BeamInputError(f"initial_state = {initial_state}: "
                             f"{'a ring-down always has' if ring else 'an FRF has no'} initial "
                             "state fitted")
    zeta = check_damping_ratio("damping_ratio", damping_ratio)
    need = max(modes, default=-1) + 1
    n_given = n_modes  # a hub counts its flexible modes: calibrate_hub checks its own
    if model.hub is not None and model.bus is None:  # E and rho apart: calibrate_hub
        if not ring:
            raise BeamInputError("data: a model on a hub is calibrated from a free ring-down "
                                 "(its FRF and driven runs are not built yet); give a "
                                 "ring-down, or the clamped model")
        from .calibrate_hub import calibrate_on_hub

        _offsets(names, data)  # the offsets name channels of the data
        return calibrate_on_hub(model, data, names, modes, n_given, zeta, _initial, _bounds)
    if not free and n_modes is not None:
        raise BeamInputError(f"n_modes = {n_modes!r:.40}: the modes whose initial state is "
                             "fitted; this data has none (an FRF, or a driven trajectory "
                             "without initial_state)")
    if free and n_modes is None:
        n_modes = max(need if ring else 0, 2 if set(RAYLEIGH) <= set(names) else 1)
    low = max(need, 1) if ring else 1
    if free and (isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer))
                 or not low <= n_modes):
        raise BeamInputError(f"n_modes = {n_modes!r:.40}: must be an integer >= {low}"
                             + (" (at least 1; every damping[k] needs mode k + 1)" if ring
                                else ""))
    n_free = int(n_modes) if free else 0
    offsets = _offsets(names, data)
    nonlinear = tuple(n for n in names if OFFSET.match(n) is None)
    sd = (np.sqrt(np.mean(np.abs(data.H) ** 2, axis=0)) if isinstance(data, FrequencyResponse)
          else data.y.std(axis=0))
    if np.any(sd == 0.0):
        raise BeamInputError(f"data: {data.channels[int(np.argmin(sd))]}: constant; nothing to "
                             "fit")
    if ring:
        omega0, cq, cv = _chain_modes(model, data.channels)
        omega0_all = omega0
        _check_modes(need, n_free, omega0.size)
        prob = Problem(nonlinear, data.t_s - data.t_s[0], (data.y / sd).ravel(), 1.0 / sd,
                       omega0[:n_free], cq[:, :n_free], cv[:, :n_free], np.full(n_free, zeta),
                       offsets)
    else:
        prob = measured_problem(model, data, nonlinear, offsets, zeta, n_free)
        omega0 = prob.omega0
        omega0_all = omega0
        _check_modes(need, n_free, omega0.size)
    unknowns = len(names) + 2 * n_free  # the offsets are among the names
    if prob.yw.size <= unknowns:
        c = len(data.channels)
        size = (f"f_hz: {data.f_hz.size} frequencies x {c} transfer function(s) x 2 (real, "
                "imaginary)" if isinstance(data, FrequencyResponse)
                else f"t_s: {data.y.shape[0]} samples x {c} channel(s)")
        raise BeamInputError(f"data: {size} for {unknowns} unknowns ({len(names)} parameters, "
                             f"{2 * n_free} of the initial state); need more")
    # the Jacobian's columns: the nonlinear parameters, the initial state, the offsets
    labels = [*nonlinear, *([None] * 2 * n_free),
              *(n for n in names if OFFSET.match(n) is not None)]
    x0 = _initial(nonlinear, zeta, omega0[:n_free] if ring else omega0[:2])
    x0 = start(prob, x0) if ring else forced_start(prob, x0)
    B, coef, dy = prob.model_jacobian(x0)
    x = x0
    if nonlinear:
        rank_check(labels, np.hstack([dy, B]))
        lo, hi = _bounds(nonlinear)
        x = least_squares(prob.residual, np.clip(x0, lo, hi), jac=prob.projected_jacobian,
                          bounds=(lo, hi), x_scale="jac", method="trf").x
        B, coef, dy = prob.model_jacobian(x)
    return calibration_result(model, data, names, labels, prob, x, B, coef, dy, zeta,
                              omega0_all)


def _check_modes(need: int, n_free: int, n: int) -> None:
    if need > n:
        raise BeamInputError(f"parameters: damping[{need - 1}] is mode {need}'s; the model has "
                             f"{n} modes")
    if n_free > n:
        raise BeamInputError(f"n_modes = {n_free}: the model has {n} modes")


def _offsets(names, data) -> tuple[int, ...]:
    """Return the data channel of each ``offset[CHANNEL]`` in ``names``."""
    out = []
    for i, n in enumerate(names):
        m = OFFSET.match(n)
        if m is None:
            continue
        if isinstance(data, FrequencyResponse):
            raise BeamInputError(f"parameters[{i}] = {n!r}: an FRF has no sensor offset")
        ch = channel_name(m.group(1))
        if ch not in data.channels:
            raise BeamInputError(f"parameters[{i}] = {n!r}: no channel {ch!r} in the data "
                                 f"(its channels: {', '.join(data.channels)})")
        out.append(data.channels.index(ch))
    return tuple(out)


def _initial(names, zeta: float, w: np.ndarray) -> np.ndarray:
    """Return the start: scales 1, ratios zeta, Rayleigh giving modes 1 and n the ratio zeta."""
    w1, wn = w[0], w[-1]
    if w.size > 1 and {"rayleigh_alpha", "rayleigh_beta"} <= set(names):
        ab = (2 * zeta * w1 * wn / (w1 + wn), 2 * zeta / (w1 + wn))
    else:  # one coefficient alone carries mode 1's zeta
        ab = (2 * zeta * w1, 2 * zeta / w1)
    start_of = {"rayleigh_alpha": ab[0], "rayleigh_beta": ab[1], "E": 1.0, "rho": 1.0}
    return np.array([start_of.get(n, zeta) for n in names])


def _bounds(names) -> tuple[np.ndarray, np.ndarray]:
    lo = {"E": _SCALE_BOUNDS[0], "rho": _SCALE_BOUNDS[0]}
    hi = {"E": _SCALE_BOUNDS[1], "rho": _SCALE_BOUNDS[1], "rayleigh_alpha": np.inf,
          "rayleigh_beta": np.inf}
    return (np.array([lo.get(n, 0.0) for n in names]),
            np.array([hi.get(n, _ZETA_MAX) for n in names]))
