"""The result of :func:`~prbdm_pin.fitting.calibrate.calibrate`: values, standard errors, model.

Standard errors are s^2 (J^T J)^-1 of the full problem (the parameters and the linear terms
together), s^2 the residual's mean square over N - p degrees of freedom: the linearised
covariance. The calibrated model is the chain with its beam's E and rho scaled and its springs
scaled with E.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError
from ..options.choices import LINK_FLOOR_FRACTION
from .calibration_data import RingDown
from .calibration_measured import DrivenTrajectory, FrequencyResponse
from .calibration_problem import rank_check

__all__ = ["CalibrationResult", "calibration_result", "estimates", "scaled_model",
           "frozen_result"]


@dataclass(frozen=True, eq=False)
class CalibrationResult:
    """The fitted parameters, their standard errors and the calibrated model.

    Attributes
    ----------
    parameters : tuple of str
        The names fitted, as asked (``E``, ``rho``, ``damping[k]``, ``offset[CHANNEL]``).
    values, std_errors : ndarray (p,)
        ``E`` in Pa, ``rho`` in kg/m^3 (the model's times the fitted scale; for a section-table
        member the scales themselves, of its stiffnesses and of its inertias), ``damping[k]``
        the ratio of mode k + 1 (dimensionless), ``offset[CHANNEL]`` the sensor's constant
        offset (the channel's unit); one standard error each, same units.
    E_scale, rho_scale : float
        The fitted scales (1 for one not fitted).
    damping_ratio : ndarray (n,)
        The ratio of each mode in the fit (fitted or the given ``damping_ratio``): a
        ring-down's ``n_modes``, every chain mode for an FRF or a driven trajectory.
    omega_rad_s : ndarray (n,)
        The calibrated undamped frequencies of those modes, rad/s.
    residual_rms : dict of str to float
        Per channel, the RMS of data less model, in the channel's unit (for an FRF the RMS
        of the complex difference's magnitude, per ``OUTPUT/INPUT``).
    fitted : ndarray (N, c)
        The calibrated model's response on the data's times (complex on an FRF's
        frequencies).
    data : RingDown, DrivenTrajectory or FrequencyResponse
    model : PrbdmModel
        The calibrated chain: its beam's E and rho scaled, its springs scaled with E.
    model_damping_ratio : ndarray (n_springs,)
        The modal ratio of every mode of the calibrated chain: the fitted ones, the given
        ``damping_ratio`` for the others (with Rayleigh damping, its ratio at each mode).

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
    >>> cal.parameters, round(float(cal.omega_rad_s[0] / w), 4)
    (('E', 'damping[0]'), 1.0)
    """

    parameters: tuple[str, ...]
    values: np.ndarray
    std_errors: np.ndarray
    E_scale: float
    rho_scale: float
    damping_ratio: np.ndarray
    omega_rad_s: np.ndarray
    residual_rms: dict
    fitted: np.ndarray
    data: RingDown | DrivenTrajectory | FrequencyResponse
    model: object
    model_damping_ratio: np.ndarray


def estimates(model, names, labels, J: np.ndarray, r: np.ndarray, est: np.ndarray):
    """Return the values and standard errors of ``names`` (SI units, see CalibrationResult).

    ``J`` (N, q) the Jacobian of the full problem (nonlinear parameters, then linear terms),
    its columns named by ``labels`` (None for an unnamed linear term); ``r`` the residual at the
    solution; ``est`` (q,) the estimates of those columns (E and rho as scales).
    """
    s2 = float(r @ r) / (r.size - J.shape[1])
    cov = s2 * np.linalg.pinv(J.T @ J)
    from ..member.section_table import SectionTable

    beam = model.beam
    # a section table is known by its properties, not by E and rho: its values are the scales
    # of its stiffnesses and of its inertias (dimensionless)
    base = ({} if isinstance(beam.section, SectionTable)
            else {"E": beam.material.E_Pa, "rho": beam.material.rho_kg_m3})
    # the offsets' coefficients multiply a weighted column: they are in the data's units
    column = {n: i for i, n in enumerate(labels) if n}
    values = np.array([base.get(n, 1.0) * est[column[n]] for n in names])
    std = np.array([base.get(n, 1.0) * np.sqrt(cov[column[n], column[n]]) for n in names])
    return values, std


def scaled_model(model, s_E: float, s_rho: float):
    """Return ``model`` with its beam's E and rho scaled and its springs scaled with E.

    A section-table member (whose material changes no result) has its table scaled instead:
    every stiffness (E I_y, E I_z, G J) by ``s_E``, the mass and rotary inertias by ``s_rho``.
    A model on a hub keeps its hub (unscaled: its inertia is known).
    """
    from ..member.section_table import SectionTable
    from ..model.prbdm_model import build_model

    beam = model.beam
    mat = dataclasses.replace(beam.material, E_Pa=beam.material.E_Pa * s_E,
                              rho_kg_m3=beam.material.rho_kg_m3 * s_rho)
    new = dataclasses.replace(beam, material=mat)
    t = beam.section
    if isinstance(t, SectionTable):
        table = SectionTable(
            EI_y_Nm2=t.EI_y_Nm2 * s_E, EI_z_Nm2=t.EI_z_Nm2 * s_E, GJ_Nm2=t.GJ_Nm2 * s_E,
            rhoA_kg_m=t.rhoA_kg_m * s_rho, rhoI_y_kg_m=t.rhoI_y_kg_m * s_rho,
            rhoI_z_kg_m=t.rhoI_z_kg_m * s_rho, rhoI_x_kg_m=t.rhoI_x_kg_m * s_rho)
        new = _with_table(beam, table)
    return build_model(new, model.lengths_m,
                       np.asarray(model.stiffness_Nm_per_rad) * s_E,
                       min_fraction=LINK_FLOOR_FRACTION, hub=model.hub)


def _with_table(beam, table):
    from ..member.section_member import table_beam

    return table_beam(beam.x_m, table, material=beam.material, tip_force_N=beam.tip_force_N,
                      name=beam.name, description=beam.description)


def over_damped(all_z: np.ndarray, what: str = "mode") -> None:
    """Refuse a Rayleigh fit that leaves a mode over-damped."""
    over = np.flatnonzero(all_z >= 1.0)
    if over.size:
        raise BeamInputError(f"parameters: the fitted Rayleigh damping gives {what} "
                             f"{over[0] + 1} a ratio {all_z[over[0]]:.3g} >= 1 "
                             "(over-damped); fit damping[k] instead")


def frozen_result(names, values, std, s_E, s_rho, z, w, res, fitted, data, model, all_z
                  ) -> CalibrationResult:
    """Return the CalibrationResult, its arrays read-only (``res``: data less model, (N, c))."""
    for a in (values, std, z, fitted, all_z):
        a.setflags(write=False)
    return CalibrationResult(
        parameters=tuple(names), values=values, std_errors=std, E_scale=float(s_E),
        rho_scale=float(s_rho), damping_ratio=z, omega_rad_s=w,
        residual_rms={ch: float(np.sqrt(np.mean(res[:, j] ** 2)))
                      for j, ch in enumerate(data.channels)},
        fitted=fitted, data=data, model=model, model_damping_ratio=all_z)


def calibration_result(model, data, names, labels, prob, x, B, coef, dy, zeta: float,
                       omega0: np.ndarray) -> CalibrationResult:
    """Return the result: values, standard errors, the fitted response, the new model.

    ``labels`` names the Jacobian's columns (None for the initial state's); ``x``, ``B``,
    ``coef`` and ``dy`` the solution, its linear terms, their coefficients and dy/dx;
    ``omega0`` (n,) every mode of the chain before calibration, rad/s.
    """
    J = np.hstack([dy, B])
    rank_check(labels, J)
    r = prob.residual(x)
    values, std = estimates(model, names, labels, J, r, np.r_[x, coef])
    sE, sR, z = prob.unpack(x)
    c = prob.weights.size
    model_w = prob.yw - r
    if isinstance(data, FrequencyResponse):
        fitted = model_w.reshape(-1, c, 2) / prob.weights[None, :, None]
        fitted = fitted[..., 0] + 1j * fitted[..., 1]
        res = np.abs(data.H - fitted)
    else:
        fitted = model_w.reshape(-1, c) / prob.weights
        res = data.y - fitted
    new = scaled_model(model, sE, sR)
    w_all = np.asarray(omega0) * np.sqrt(sE / sR)
    all_z = np.full(w_all.size, zeta)
    all_z[:z.size] = z
    ab = prob.rayleigh(x)
    if ab is not None:  # every mode of the calibrated chain takes the fitted Rayleigh ratio
        all_z = ab[0] / (2.0 * w_all) + ab[1] * w_all / 2.0
        over_damped(all_z, "mode")
    return frozen_result(names, values, std, sE, sR, z, w_all[:z.size], res, fitted, data, new,
                         all_z)
