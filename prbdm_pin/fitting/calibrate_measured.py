"""The set-up of a calibration to an FRF or to a driven trajectory (:func:`.calibrate.calibrate`).

The chain is linearised once (its undamped modes, each input's modal force, each output's
modal reading); E, rho and the damping then move the modes as :mod:`.calibration_forced` says,
without linearising again. Every chain mode is in the response (a forced response excites them
all, and the highest carry the quasi-static part); the modes whose damping is not fitted keep
the given ratio. A driven trajectory starts from rest, or with ``initial_state`` from a fitted
state of its lowest ``n_modes`` modes (their free response, linear in that state).
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from ..model.loads import BASE_ACCELS
from .calibration_forced_problem import ForcedProblem
from .calibration_measured import DrivenTrajectory, FrequencyResponse

__all__ = ["chain_gains", "forced_start", "measured_problem"]


def _unique(names) -> tuple[str, ...]:
    return tuple(dict.fromkeys(names))


def chain_gains(model, inputs: tuple[str, ...], outputs: tuple[str, ...],
                what: str | None = None):
    """Return omega0 (n,), cq, cv (p, n) and b (n, m) of the clamped planar chain, undamped.

    ``what`` prefixes linearize's refusal of a name (default: the data's inputs and outputs).
    """
    from ..chain.eigen import generalized_eigh
    from ..plant.linearize import linearize

    try:
        lin = linearize(model, inputs=inputs, outputs=outputs, damping_ratio=0.0)
    except BeamInputError as exc:  # the names are the data's columns: say so
        what = what or (f"data: its inputs ({', '.join(inputs)}) and outputs "
                        f"({', '.join(outputs)})")
        raise BeamInputError(f"{what}: {exc}") from None
    for M, label in ((lin.output_map_acceleration, "the acceleration"),
                     (lin.output_map_input, "the input")):
        if M is not None and np.any(M):
            bad = [c for c, row in zip(outputs, M, strict=True) if np.any(row)]
            raise BeamInputError(f"data: channel {bad[0]!r} reads {label}; a calibration "
                                 "channel must be a position or a rate")
    n = lin.mass_kg_m2.shape[0]
    w2, phi = generalized_eigh(lin.stiffness_Nm_per_rad, lin.mass_kg_m2, "calibrate")
    C = np.asarray(lin.C)
    return np.sqrt(w2), C[:, :n] @ phi, C[:, n:] @ phi, phi.T @ np.asarray(lin.input_map)


def measured_problem(model, data, nonlinear: tuple[str, ...], offsets: tuple[int, ...],
                     zeta: float, n_free: int) -> ForcedProblem:
    """Return the weighted problem of ``data`` (an FRF or a driven trajectory).

    ``nonlinear`` the parameters but the offsets; ``offsets`` the channels with one;
    ``zeta`` every mode's ratio at the start; ``n_free`` the modes whose initial state is
    fitted (a driven trajectory; 0 from rest).
    """
    if isinstance(data, FrequencyResponse):
        outs, ins = _unique(data.outputs), _unique(data.inputs)
        w0, cq, cv, b = chain_gains(model, ins, outs)
        out_in = tuple((outs.index(o), ins.index(i)) for o, i in
                       zip(data.outputs, data.inputs, strict=True))
        # each transfer function weighted by 1 / the RMS of its magnitude
        wts = 1.0 / np.sqrt(np.mean(np.abs(data.H) ** 2, axis=0))
        yw = (np.stack([data.H.real, data.H.imag], axis=2) * wts[None, :, None]).ravel()
        axis, u = data.f_hz, None
    else:
        assert isinstance(data, DrivenTrajectory)
        ins = data.inputs
        w0, cq, cv, b = chain_gains(model, ins, data.channels)
        wts = 1.0 / data.y.std(axis=0)
        yw = (data.y * wts).ravel()
        axis, u, out_in = data.t_s - data.t_s[0], data.u, ()
    # a base acceleration's load -m a scales with rho (calibration_forced's e_j)
    power = np.array([1.0 if i in BASE_ACCELS else 0.0 for i in ins])
    return ForcedProblem(nonlinear, axis, yw, wts, w0, cq, cv, np.full(w0.size, zeta),
                         offsets, frf=isinstance(data, FrequencyResponse), u=u, b=b,
                         rho_power=power, out_in=out_in, n_free=n_free)


def forced_start(prob: ForcedProblem, x0: np.ndarray) -> np.ndarray:
    """Return x0 with the E or rho scale from a grid over E/rho (the full model's cost).

    A forced response remembers its past over ~ 1 / (zeta omega_1) (or the record's length
    T, if shorter), and an FRF's peak is zeta wide: mode 1's frequency must be within
    ~ max(zeta, 1 / (omega_1 T)) of the data's to be in the basin. The grid steps half that,
    the ratio in [1/3, 3] (omega within -42 %, +73 %).
    """
    names = prob.names
    which = [n for n in names if n in ("E", "rho")]
    if not which:
        return x0
    memory = np.inf if prob.frf else prob.t[-1] - prob.t[0]
    z1 = max(float(prob.zeta0[0]), 1e-3)
    step = 0.5 * max(z1, 1.0 / (prob.omega0[0] * memory))
    r = np.exp(np.arange(np.log(1 / 3), np.log(3.0), 2.0 * step))
    i = names.index(which[0])
    x, cost = x0.copy(), []
    for ri in r:
        x[i] = ri if which[0] == "E" else 1.0 / ri
        cost.append(float(np.sum(prob.residual(x) ** 2)))
    best = r[int(np.argmin(cost))]
    x[i] = best if which[0] == "E" else 1.0 / best
    return x
