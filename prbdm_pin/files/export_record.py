"""The record every export carries.

It holds the exported model's own frequencies, its per-mode errors against the truth it was
fitted to, and the damping the file holds (with the modal ratios that damping gives). URDF and
MJCF hold it as an XML comment (:func:`read_export_record` reads it back), JSON as fields.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..chain.eigen import eig_scaled
from ..errors import BeamInputError
from ..options.choices import EXPORT_DAMPING_FORMS, FORMATS
from ..simulation.damping import damping_ratios
from .export_damping import MODAL_FIT_WARN_PCT, default_form, export_damping
from .export_plant import plant_inputs

__all__ = [
    "FORMATS",
    "EXPORT_DAMPING_FORMS",
    "WORST_MODE_WARN_PCT",
    "MODAL_FIT_WARN_PCT",
    "ExportRecord",
    "export_record",
    "read_export_record",
]

# a worst mode further off the truth than this, %, is worth a warning
WORST_MODE_WARN_PCT = 1.0
FLOAT_FIELDS = ("natural_frequencies_rad_s", "omega_truth_rad_s", "omega_errors_pct",
           "damping_ratio", "joint_damping_Nms_per_rad", "modal_damping_ratios",
           "hub_frequencies_rad_s", "strain_actuators_m", "damping_ratio_errors")


def _ro(a: np.ndarray | None) -> np.ndarray | None:
    if a is None:
        return None
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class ExportRecord:
    """What an exported file holds besides the model: its frequencies, errors and damping.

    n below is the number of spring coordinates (``model.n_springs``: the joints of a planar
    chain, the joints times the axes of a spatial one).

    Attributes
    ----------
    natural_frequencies_rad_s : ndarray, shape (n,)
        The exported model's natural frequencies at the straight pose (its M and K), rad/s.
    omega_truth_rad_s : ndarray, shape (N,) or None
        The truth frequencies the model was fitted to, rad/s (None: unknown).
    omega_errors_pct : ndarray, shape (min(n, N),) or None
        Signed per-mode errors 100 (omega_model / omega_truth - 1), %.
    worst_mode_error_pct : float or None
        ``max |omega_errors_pct|``, %.
    worst_mode : int or None
        The mode (1-based) of the worst error.
    damping_requested : str
        ``"stiffness"``, ``"modal"``, ``"modal_fit"`` or ``"none"`` (ratio 0).
    damping_form : str
        The form the file carries: ``"stiffness"``, ``"modal"`` (JSON only), ``"modal_fit"``
        (:mod:`~prbdm_pin.files.export_damping`) or ``"none"``.
    damping_ratio : ndarray, shape (n,)
        The asked ratios: mode 1's (stiffness form; every entry equal) or each mode's (modal,
        modal_fit).
    damping_beta_s : float or None
        beta of C = beta K (stiffness form), s.
    joint_damping_Nms_per_rad : ndarray, shape (n,)
        The diagonal joint damping written (zeros for modal or none), N m s/rad.
    modal_damping_ratios : ndarray, shape (n,)
        The ratio each mode of the straight pose gets from that damping (ascending frequency);
        for ``modal_fit`` the achieved ratios from the damped chain's complex eigenvalues.
    warnings : tuple of str
        A form asked for and not written; a worst mode off by more than ``WORST_MODE_WARN_PCT``.
    hub_frequencies_rad_s : ndarray, shape (n,) or None
        With a hub: the flexible natural frequencies of the model on its hub at the straight pose
        (the rigid mode, at 0, left out), rad/s; None without a hub. ``natural_frequencies_rad_s``
        and the errors stay the clamped model's (the fitted one; the truth is clamped), while the
        damping and ``modal_damping_ratios`` are the hub model's (what the file simulates).
    strain_actuators_m : ndarray, shape (k, 2)
        The strain actuators of the plant, [x_start_m, x_end_m] each, m from the root.
    inputs : tuple of str
        The inputs the file drives (MJCF ``<actuator>`` entries, by the package's input names;
        empty for URDF and JSON, which carry no actuators).
    strain_actuator_weights : tuple
        Per strain actuator, its fitted joint weights (a tuple, N m per N m) or None (the
        virtual-work map); empty when no actuator has weights.
    damping_ratio_errors : ndarray, shape (n,) or None
        ``modal_fit`` only: each mode's achieved minus asked ratio (absolute, dimensionless).
    """

    natural_frequencies_rad_s: np.ndarray
    omega_truth_rad_s: np.ndarray | None
    omega_errors_pct: np.ndarray | None
    worst_mode_error_pct: float | None
    worst_mode: int | None
    damping_requested: str
    damping_form: str
    damping_ratio: np.ndarray
    damping_beta_s: float | None
    joint_damping_Nms_per_rad: np.ndarray
    modal_damping_ratios: np.ndarray
    warnings: tuple = ()
    hub_frequencies_rad_s: np.ndarray | None = None
    strain_actuators_m: np.ndarray | None = None
    inputs: tuple = ()
    strain_actuator_weights: tuple = ()
    damping_ratio_errors: np.ndarray | None = None

    def __post_init__(self) -> None:
        """Shape the actuator spans, check one weight entry per actuator, freeze the arrays."""
        acts = np.zeros((0, 2)) if self.strain_actuators_m is None else self.strain_actuators_m
        object.__setattr__(self, "strain_actuators_m", np.reshape(acts, (-1, 2)))
        object.__setattr__(self, "inputs", tuple(self.inputs))
        w = tuple(None if v is None else tuple(float(x) for x in v)
                  for v in self.strain_actuator_weights)
        if all(v is None for v in w):
            w = ()
        elif len(w) != self.strain_actuators_m.shape[0]:
            raise ValueError(f"strain_actuator_weights: {len(w)} entries for "
                             f"{self.strain_actuators_m.shape[0]} actuators")
        object.__setattr__(self, "strain_actuator_weights", w)
        for name in FLOAT_FIELDS:
            object.__setattr__(self, name, _ro(getattr(self, name)))

    def actuators(self) -> tuple:
        """Return the recorded strain actuators as :class:`~prbdm_pin.model.inputs.StrainActuator`.

        Each carries its joint weights when it has them.
        """
        from ..model.inputs import StrainActuator

        w = self.strain_actuator_weights or (None,) * self.strain_actuators_m.shape[0]
        return tuple(StrainActuator(float(a), float(b), joint_weights=v)
                     for (a, b), v in zip(self.strain_actuators_m, w, strict=True))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready fields (SI units, %)."""
        def lst(a):
            return None if a is None else [float(v) for v in a]

        return {
            "natural_frequencies_rad_s": lst(self.natural_frequencies_rad_s),
            "frequencies_pose": "straight (q = 0)",
            "omega_truth_rad_s": lst(self.omega_truth_rad_s),
            "omega_errors_pct": lst(self.omega_errors_pct),
            "worst_mode_error_pct": self.worst_mode_error_pct,
            "worst_mode": self.worst_mode,
            "damping": {
                "requested": self.damping_requested,
                "form": self.damping_form,
                "ratio": lst(self.damping_ratio),
                "beta_s": self.damping_beta_s,
                "joint_damping_Nms_per_rad": lst(self.joint_damping_Nms_per_rad),
                "modal_ratios": lst(self.modal_damping_ratios),
                **({} if self.damping_ratio_errors is None else
                   {"ratio_errors": lst(self.damping_ratio_errors)}),
            },
            "warnings": list(self.warnings),
            "hub_frequencies_rad_s": lst(self.hub_frequencies_rad_s),
        }

    def comment_text(self) -> str:
        """Return the record as the text of an XML comment.

        One ``key: values`` line each; see :mod:`prbdm_pin.files.export_comment`.
        """
        from .export_comment import comment_text

        return comment_text(self)

    def summary_lines(self) -> list[str]:
        """Human-readable lines for a command's output."""
        out = ["frequencies (straight pose) rad/s: "
               + " ".join(f"{w:.6g}" for w in self.natural_frequencies_rad_s)]
        if self.omega_errors_pct is not None:
            out.append("errors vs truth %: " + " ".join(f"{e:+.3f}" for e in self.omega_errors_pct)
                       + f" (worst {self.worst_mode_error_pct:.3f} %, mode {self.worst_mode})")
        else:
            out.append("errors vs truth: unknown (no truth frequencies with this model)")
        if self.hub_frequencies_rad_s is not None:
            out.append("hub model, flexible frequencies (straight pose) rad/s: "
                       + " ".join(f"{w:.6g}" for w in self.hub_frequencies_rad_s))
        if self.damping_form == "none":
            out.append("damping: none")
        else:
            beta = "" if self.damping_beta_s is None else f", beta {self.damping_beta_s:.6g} s"
            out.append(f"damping: {self.damping_form}{beta}; modal ratios "
                       + " ".join(f"{x:.4g}" for x in self.modal_damping_ratios))
            if self.damping_ratio_errors is not None:
                out.append("damping ratio errors (achieved - asked): "
                           + " ".join(f"{x:+.3g}" for x in self.damping_ratio_errors))
        return out


def _errors(omega: np.ndarray, omega_truth) -> tuple:
    if omega_truth is None:
        return None, None, None, None
    wt = np.asarray(omega_truth, dtype=float).reshape(-1)
    if wt.size == 0 or not np.all(np.isfinite(wt) & (wt > 0.0)):
        raise BeamInputError(f"omega_truth = {wt.tolist()} rad/s: must be finite and > 0")
    k = min(omega.size, wt.size)
    err = 100.0 * (omega[:k] / wt[:k] - 1.0)
    i = int(np.argmax(np.abs(err)))
    return wt, err, float(abs(err[i])), i + 1


def export_record(
    model,
    fmt: str,
    damping_ratio: float | np.ndarray = 0.02,
    damping_form: str | None = None,
    omega_truth_rad_s: np.ndarray | None = None,
    *,
    actuators=(),
    inputs=None,
) -> ExportRecord:
    """Compute the :class:`ExportRecord` of ``model`` exported as ``fmt``.

    Parameters
    ----------
    model : PrbdmModel
        With or without a hub (:class:`prbdm_pin.Hub`).
    fmt : {"urdf", "mjcf", "json"}
    damping_ratio : float or ndarray (n,)
        Mode 1's ratio (stiffness form) or each mode's (modal form); 0 writes no damping. With a
        hub, mode 1 is the lowest flexible mode and the hub joint is undamped.
    damping_form : {"stiffness", "modal", "modal_fit"}, optional
        Default: ``"modal"`` for JSON; for URDF and MJCF ``"stiffness"`` with one ratio,
        ``"modal_fit"`` (a diagonal joint damping fitted to the ratios) with ratios that differ
        between modes. URDF and MJCF asked for ``"modal"`` get the stiffness form with one
        ratio, the fitted form with several, and a warning says so
        (:mod:`~prbdm_pin.files.export_damping`).
    omega_truth_rad_s : ndarray, optional
        Truth frequencies the model was fitted to (fit.json's ``omega_truth_rad_s``), rad/s.
    actuators : sequence of StrainActuator
        Strain actuators of the plant (each must lie on the beam).
    inputs : sequence of str, optional
        The inputs an MJCF drives (:func:`prbdm_pin.model.inputs.input_map` names). Default:
        ``hub_torque`` with a hub, and ``strain[i]`` for every actuator; URDF and JSON carry
        none and refuse any.
    """
    if fmt not in FORMATS:
        raise BeamInputError(f"format = {fmt!r}: must be one of {', '.join(FORMATS)}")
    requested = damping_form
    if requested is not None and requested not in EXPORT_DAMPING_FORMS:
        raise BeamInputError(f"damping_form = {requested!r}: must be one of "
                             f"{', '.join(EXPORT_DAMPING_FORMS)}")
    spans, weights, names = plant_inputs(model, fmt, actuators, inputs)
    n = model.n_springs  # modes: one per spring coordinate (n_joints on the planar chain)
    xi = damping_ratios(damping_ratio, n)
    M = model.mass_matrix()
    k = np.asarray(model.stiffness_Nm_per_rad, dtype=float)
    hub = model.hub is not None
    # the clamped (fitted) model is the hub model with the hub held: M without the hub's row;
    # one solve per export, so LAPACK's (loading the compiled solve would cost ~0.25 s)
    if model.bus is None:
        omega = eig_scaled(M[1:, 1:] if hub else M, 1.0 / np.sqrt(k), compiled=False)
    else:
        omega = np.asarray(model.natural_frequencies(), dtype=float)
    omega_hub = np.asarray(model.natural_frequencies(), dtype=float)[1:] if hub else None
    wt, err, worst, worst_mode = _errors(omega, omega_truth_rad_s)
    dmp = export_damping(model, M, fmt, requested or default_form(fmt, xi), xi, omega_hub)
    notes = list(dmp.notes)
    if worst is not None and worst > WORST_MODE_WARN_PCT:
        notes.append(f"mode {worst_mode} of the exported model is {err[worst_mode - 1]:+.3f} % "
                     f"off the truth (straight pose); more than {WORST_MODE_WARN_PCT:g} %")
    return ExportRecord(omega, wt, err, worst, worst_mode, dmp.requested, dmp.form, dmp.ratio,
                        dmp.beta_s, dmp.joint_damping_Nms_per_rad, dmp.modal_ratios,
                        tuple(notes), omega_hub, spans, names, weights, dmp.ratio_errors)


def read_export_record(text: str) -> ExportRecord | None:
    """Read the :class:`ExportRecord` in the comment of an exported URDF or MJCF text.

    None if there is none; see :func:`prbdm_pin.files.export_comment.read_export_record`.
    """
    from .export_comment import read_export_record as read

    return read(text)
