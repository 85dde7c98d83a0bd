"""The linearised plant: ``LinearModel`` and its modal view ``ModalData``.

``LinearModel`` holds the state space and its second-order form.

x = [dq; dv] (deviations of the joint angles, rad, and rates, rad/s, from the equilibrium),
u = input deviations from their nominal values, y = output deviations:

    M dv' + C_d dv + K_e dq = B_q u,   y = C_q dq + C_v dv + C_a dv' + D_u u
    A = [[0, I], [-M^-1 K_e, -M^-1 C_d]],  B = [[0], [M^-1 B_q]],
    C = [C_q - C_a M^-1 K_e, C_v - C_a M^-1 C_d],  D = C_a M^-1 B_q + D_u

C_a and D_u are zero but for the outputs that read the acceleration and the applied loads (the
root reaction, the strain near the root: :mod:`prbdm_pin.plant.acceleration_outputs`); with
them zero, C = [C_q, C_v] and D = 0.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..chain.eigen import generalized_eigh
from ..model.hub import schur_mass
from ..model.supports import free_modes_of, free_schur

__all__ = ["LinearModel", "ModalData"]


@dataclass(frozen=True, eq=False)
class ModalData:
    """Undamped modes of the linearised plant, ascending frequency.

    Attributes
    ----------
    omega_rad_s : ndarray (k,)
        Natural frequencies, rad/s (0 for a rigid mode; an unstable mode, omega^2 < 0 under a
        compressive load, is reported as 0 with its ``omega_squared``).
    omega_squared : ndarray (k,)
        omega^2, rad^2/s^2.
    damping_ratio : ndarray (k,)
        diag(Phi^T C_d Phi) / (2 omega), dimensionless (0 where omega is 0).
    shapes : ndarray (nv, k)
        Mass-normalised mode shapes (Phi^T M Phi = I), per sqrt(kg m^2).
    input_gains : ndarray (k, m)
        Phi^T B_q: modal force per unit input.
    output_gains_position, output_gains_rate : ndarray (p, k)
        C_q Phi and C_v Phi: output per unit modal coordinate and per unit modal rate.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> modes = pp.linearize(model, damping_ratio=0.02).modal()
    >>> modes.omega_rad_s.round(1), modes.damping_ratio.round(3)
    (array([ 59. , 320.9]), array([0.02, 0.02]))
    """

    omega_rad_s: np.ndarray
    omega_squared: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray
    input_gains: np.ndarray
    output_gains_position: np.ndarray
    output_gains_rate: np.ndarray


@dataclass(frozen=True, eq=False)
class LinearModel:
    """A PRBDM linearised about an equilibrium (see the module notes for the form).

    Attributes
    ----------
    A, B, C, D : ndarray
        State space, shapes (2 nv, 2 nv), (2 nv, m), (p, 2 nv), (p, m), SI units per the names.
    state_names, input_names, output_names : tuple of str
    input_units, output_units : tuple of str
    q_eq : ndarray (nv,)
        Equilibrium pose, rad (the hub angle first on a hub model).
    u_eq : ndarray (m,)
        Nominal input values at the equilibrium (the load's tip force components, the trim hub
        torque; 0 otherwise).
    y_eq : ndarray (p,)
        Output values at the equilibrium.
    mass_kg_m2, stiffness_Nm_per_rad, damping_Nms_per_rad : ndarray (nv, nv)
        M, the effective stiffness K_e (springs, load and gravity) and C_d.
    input_map : ndarray (nv, m)
        B_q, generalized force per unit input.
    output_map_position, output_map_rate : ndarray (p, nv)
        C_q and C_v (the direct paths; :attr:`C` adds the acceleration's).
    hub : bool
        Whether coordinate 0 is a hub joint.
    output_map_acceleration : ndarray (p, nv) or None
        C_a, output per rad/s^2 (None: zero).
    output_map_input : ndarray (p, m) or None
        D_u, the inputs' direct part of the outputs (None: zero).
    n_free : int
        Coordinates without a spring at the start (1 for a hub, 6 for a free bus's base).
    spin_rad_s : float
        The hub's steady rate the plant was linearised about, rad/s (0: at rest).
    gyroscopic_Nms_per_rad : ndarray (nv, nv) or None
        G = dh/dv of a spinning plant (skew; part of ``damping_Nms_per_rad``, which is
        C_d + G); None at rest. :meth:`modal` leaves it out (it solves (K_e, M)); G is zero
        at the straight pose, and :func:`prbdm_pin.plant.spin.gyroscopic_frequencies` takes
        it in elsewhere.

    The modal gains (:meth:`modal`) are of C_q and C_v only: an output that reads the
    acceleration has its C_a Phi path left out there (the state space has it).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> lin = pp.linearize(model)
    >>> lin.input_names, lin.output_names, lin.output_units
    (('tip_force_z',), ('tip_z',), ('m',))
    >>> static = lin.frequency_response(np.array([0.0]))[0].real[0, 0]  # m/N at 0 rad/s
    >>> tip = pp.statics(model, tip_force_N=[0.0, 0.0, 1e-3]).tip_displacement_m[2] / 1e-3
    >>> bool(np.isclose(static, tip, rtol=1e-4))
    True
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    input_units: tuple[str, ...]
    output_units: tuple[str, ...]
    q_eq: np.ndarray
    u_eq: np.ndarray
    y_eq: np.ndarray
    mass_kg_m2: np.ndarray
    stiffness_Nm_per_rad: np.ndarray
    damping_Nms_per_rad: np.ndarray
    input_map: np.ndarray
    output_map_position: np.ndarray
    output_map_rate: np.ndarray
    hub: bool = False
    output_map_acceleration: np.ndarray | None = None
    output_map_input: np.ndarray | None = None
    n_free: int = 0
    spin_rad_s: float = 0.0
    gyroscopic_Nms_per_rad: np.ndarray | None = None

    def to_control(self):
        """Return the plant as a ``control.StateSpace`` (python-control), with signal names.

        python-control refuses a '.' in a signal name (it separates a subsystem's name from
        its signal's): a station's decimal point is spelled 'p' there (``strain@0.05`` is
        ``strain@0p05``).
        """
        import control

        def safe(names):
            return [n.replace(".", "p") for n in names]

        return control.ss(self.A, self.B, self.C, self.D, states=safe(self.state_names),
                          inputs=safe(self.input_names), outputs=safe(self.output_names))

    def discretize(self, dt_s: float) -> tuple[np.ndarray, np.ndarray]:
        """Return the zero-order-hold discrete-time plant's (A_d, B_d) at sample time ``dt_s``.

        x[k+1] = A_d x[k] + B_d u[k], y[k] = C x[k] + D u[k], with A_d = exp(A dt) and
        B_d = int_0^dt exp(A s) ds B (python-control's ``sample(dt, "zoh")``).

        Raises
        ------
        BeamInputError
            ``dt_s`` not a finite number > 0 (naming it).
        """
        from ..options.checks import check_float

        dt = check_float("dt_s", dt_s, low=0.0, low_open=True, unit="s")
        d = self.to_control().sample(dt, method="zoh")
        return np.asarray(d.A, dtype=float), np.asarray(d.B, dtype=float)

    def frequency_response(self, omega_rad_s: np.ndarray) -> np.ndarray:
        """C (j omega I - A)^-1 B + D at each frequency (rad/s), complex, shape (f, p, m)."""
        w = np.atleast_1d(np.asarray(omega_rad_s, dtype=float))
        eye = np.eye(self.A.shape[0])
        out = np.empty((w.size, self.C.shape[0], self.B.shape[1]), dtype=complex)
        for i, wi in enumerate(w):
            out[i] = self.C @ np.linalg.solve(1j * wi * eye - self.A, self.B) + self.D
        return out

    def modal(self) -> ModalData:
        """Undamped modes of (K_e, M) with their damping ratios and modal gains.

        A hub model whose effective stiffness leaves the hub free (no load or gravity turning
        it) has its rigid mode taken out exactly (frequency 0, shape e_hub / sqrt(m_hh)); the
        rest solve the symmetric generalized eigenproblem, no inverse of M.
        """
        M, K = self.mass_kg_m2, self.stiffness_Nm_per_rad
        nf = max(self.n_free, int(self.hub))
        if self.hub and not np.any(K[0]) and not np.any(K[:, 0]):
            w2f, Pf = generalized_eigh(K[1:, 1:], schur_mass(M), "plant modes")
            nv = M.shape[0]
            Phi = np.zeros((nv, nv))
            Phi[0, 0] = 1.0 / np.sqrt(M[0, 0])
            Phi[1:, 1:] = Pf
            Phi[0, 1:] = -(M[0, 1:] @ Pf) / M[0, 0]
            w2 = np.concatenate([[0.0], w2f])
        elif nf > 1 and not np.any(K[:nf]) and not np.any(K[:, :nf]):
            # the free bus's six rigid modes taken out exactly (:mod:`prbdm_pin.model.supports`)
            w2f, Pf = generalized_eigh(K[nf:, nf:], free_schur(M, nf), "plant modes")
            Phi = free_modes_of(M, Pf, nf)
            w2 = np.concatenate([np.zeros(nf), w2f])
        else:
            w2, Phi = generalized_eigh(K, M, "plant modes")
        omega = np.sqrt(np.clip(w2, 0.0, None))
        c = np.einsum("ik,ij,jk->k", Phi, self.damping_Nms_per_rad, Phi)
        with np.errstate(divide="ignore", invalid="ignore"):
            zeta = np.where(omega > 0.0, c / (2.0 * np.where(omega > 0.0, omega, 1.0)), 0.0)
        return ModalData(omega, w2, zeta, Phi, Phi.T @ self.input_map,
                         self.output_map_position @ Phi, self.output_map_rate @ Phi)

    def to_dict(self) -> dict[str, Any]:
        """Names, units, the equilibrium and the modal table, JSON-ready (SI units)."""
        md = self.modal()
        return {
            "state_names": list(self.state_names),
            "input_names": list(self.input_names),
            "input_units": list(self.input_units),
            "output_names": list(self.output_names),
            "output_units": list(self.output_units),
            "hub": self.hub,
            "q_eq_rad": self.q_eq.tolist(),
            "u_eq": self.u_eq.tolist(),
            "y_eq": self.y_eq.tolist(),
            "modes": [
                {"omega_rad_s": float(md.omega_rad_s[k]),
                 "frequency_hz": float(md.omega_rad_s[k] / (2.0 * np.pi)),
                 "damping_ratio": float(md.damping_ratio[k]),
                 "input_gains": md.input_gains[k].tolist(),
                 "output_gains_position": md.output_gains_position[:, k].tolist(),
                 "output_gains_rate": md.output_gains_rate[:, k].tolist()}
                for k in range(md.omega_rad_s.size)
            ],
        }
