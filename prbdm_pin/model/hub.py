"""A rotating rigid hub at the beam's root.

Its description, its Pinocchio chain, and the frequencies and modes of a chain whose first
joint has no spring.

The hub turns about world x, y or z (``Hub.axis``) through its centre, the world origin; the
beam root is clamped to it at ``radius_m`` along x and the beam bends about y (deflecting in z).
So a hub about y turns the beam in its own bending plane (the lead-lag, in-plane case), a hub
about z turns it in the xy-plane with the bending out of that plane (flapping), and a hub about
x spins the beam about its own axis (with the radius along that axis too). In the Pinocchio model
the hub joint comes first (velocity index 0, no spring) and joint j + 1 of the beam follows as
velocity index j + 1.

The hub's rigid mode is taken out exactly rather than left to the eigensolver: with
K = diag(0, K_f) the hub row of K phi = omega^2 M phi reads omega^2 (m_hh phi_h + m_hf phi_f) = 0,
so the rigid mode is e_hub (omega = 0) and every flexible mode has phi_h = -m_hf phi_f / m_hh
with K_f phi_f = omega^2 S phi_f, S = M_ff - m_fh m_hf / m_hh (the Schur complement, positive
definite). The flexible problem keeps a diagonal K, so it goes through the package's scaled
eigensolver and its guard; the rigid frequency is exactly 0, not a rounding of it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..chain.eigen import eig_scaled, modes_from_mass
from ..errors import BeamInputError
from ..options.checks import check_float
from ..options.validate import MAX_HUB_INERTIA_KG_M2, check_size

__all__ = ["HUB_AXES", "Hub", "hub_chain", "hub_frequencies", "hub_modes", "schur_mass"]

HUB_JOINT = "hub"
HUB_AXES = ("x", "y", "z")
_JOINT = {"x": pin.JointModelRX, "y": pin.JointModelRY, "z": pin.JointModelRZ}


@dataclass(frozen=True)
class Hub:
    """A rigid hub turning about world ``axis`` at the root of the beam.

    Attributes
    ----------
    inertia_kg_m2 : float
        Rotational inertia of the hub about its axis, kg m^2 (> 0; the beam's own inertia is
        added by the chain).
    radius_m : float
        Distance from the hub centre to the beam's root along x, m (>= 0).
    axis : {"x", "y", "z"}
        The world axis the hub turns about, through the origin (default ``"y"``: in the
        beam's bending plane). ``"z"``: the beam sweeps the xy-plane and bends out of it;
        ``"x"``: the beam spins about its own axis (the radius then lies along the axis).

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> hub = pp.Hub(inertia_kg_m2=0.5, radius_m=0.05)
    >>> hub.axis, hub.inertia_kg_m2
    ('y', 0.5)
    """

    inertia_kg_m2: float
    radius_m: float = 0.0
    axis: str = "y"

    def __post_init__(self) -> None:
        """Check the inertia and the radius (BeamInputError naming the field).

        The inertia is > 0 and at most ``validate.MAX_HUB_INERTIA_KG_M2``; the radius is 0 or
        a size in [1e-5, 1e3] m (:func:`prbdm_pin.validate.check_size`).
        """
        J = check_float("Hub inertia_kg_m2", self.inertia_kg_m2, low=0.0, low_open=True,
                        high=MAX_HUB_INERTIA_KG_M2, unit="kg m^2")
        r = check_size("Hub radius_m", self.radius_m, low=0.0)
        if not isinstance(self.axis, str) or self.axis not in HUB_AXES:
            raise BeamInputError(f"Hub axis = {self.axis!r}: must be one of 'x', 'y', 'z' "
                                 "(the world axis the hub turns about)")
        object.__setattr__(self, "inertia_kg_m2", J)
        object.__setattr__(self, "radius_m", r)


def hub_chain(sections, lengths: np.ndarray, hub: Hub, name: str) -> tuple[pin.Model, int]:
    """Build the link chain of ``sections`` (cut at ``lengths``, m) on a hub joint at the origin.

    The hub joint turns about ``hub.axis``; the beam joints about y. Returns the
    ``pinocchio.Model`` (gravity zero) and the tip frame id.
    """
    from .pin_chain import TIP_FRAME

    n = lengths.size - 1
    model = pin.Model()
    model.name = name
    eye = np.eye(3)
    ident = pin.SE3.Identity()

    def inertia(i: int) -> pin.Inertia:
        c = sections.com_m[i] - np.array([sections.start_m[i], 0.0, 0.0])
        return pin.Inertia(float(sections.mass_kg[i]), c, sections.inertia_com_kg_m2[i])

    world = model.addBodyFrame("world", 0, ident, 0)
    hid = model.addJoint(0, _JOINT[hub.axis](), ident, HUB_JOINT)
    prev = model.addJointFrame(hid, world)
    model.appendBodyToJoint(hid, pin.Inertia(0.0, np.zeros(3), hub.inertia_kg_m2 * eye), ident)
    prev = model.addBodyFrame("hub_body", hid, ident, prev)
    root = pin.SE3(eye, np.array([hub.radius_m, 0.0, 0.0]))
    model.appendBodyToJoint(hid, inertia(0), root)
    prev = model.addBodyFrame("link_0", hid, root, prev)
    offset = hub.radius_m  # the first beam joint sits at radius + L_0 from the hub axis
    for j in range(1, n + 1):
        placement = pin.SE3(eye, np.array([offset + float(lengths[j - 1]), 0.0, 0.0]))
        offset = 0.0
        jid = model.addJoint(j, pin.JointModelRY(), placement, f"joint_{j}")
        jf = model.addJointFrame(jid, prev)
        model.appendBodyToJoint(jid, inertia(j), ident)
        prev = model.addBodyFrame(f"link_{j}", jid, ident, jf)
    tip_place = pin.SE3(eye, np.array([float(lengths[n]), 0.0, 0.0]))
    tip = model.addBodyFrame(TIP_FRAME, n + 1, tip_place, prev)
    model.gravity = pin.Motion.Zero()
    return model, tip


def schur_mass(M: np.ndarray) -> np.ndarray:
    """Return S = M_ff - m_fh m_hf / m_hh: the flexible joints' mass with the hub free.

    Of mass matrices (..., n+1, n+1) whose first coordinate is the hub, kg m^2; shape
    (..., n, n).
    """
    m_hh = M[..., 0, 0]
    m_fh = M[..., 1:, 0]
    S = M[..., 1:, 1:] - m_fh[..., :, None] * m_fh[..., None, :] / m_hh[..., None, None]
    return 0.5 * (S + np.swapaxes(S, -1, -2))


def hub_frequencies(M: np.ndarray, stiffness_Nm_per_rad: np.ndarray,
                    squared: bool = False) -> np.ndarray:
    """Return the frequencies of hub chains, rad/s ascending (omega^2 if ``squared``).

    The rigid mode's exact 0 first, then the n flexible ones; ``M`` (n+1, n+1) or
    (m, n+1, n+1), kg m^2; springs (n,) or (m, n), N m/rad.
    """
    s = 1.0 / np.sqrt(np.asarray(stiffness_Nm_per_rad, dtype=float))
    flex = eig_scaled(schur_mass(M), s, squared)
    return np.concatenate([np.zeros(flex.shape[:-1] + (1,)), flex], axis=-1)


def hub_modes(M: np.ndarray, stiffness_Nm_per_rad: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
    """Return the frequencies and mass-normalised modes of one hub chain.

    Frequencies in rad/s, the rigid 0 first; modes as columns, shape (n+1, n+1); the chain has
    mass matrix ``M`` (kg m^2) and springs (n,), N m/rad.
    """
    M = np.asarray(M, dtype=float)
    omega_f, Phi_f = modes_from_mass(schur_mass(M)[None], stiffness_Nm_per_rad)
    omega_f, Phi_f = omega_f[0], Phi_f[0]
    n1 = M.shape[0]
    Phi = np.zeros((n1, n1))
    Phi[0, 0] = 1.0 / math.sqrt(M[0, 0])
    Phi[1:, 1:] = Phi_f
    Phi[0, 1:] = -(M[0, 1:] @ Phi_f) / M[0, 0]
    return np.concatenate([[0.0], omega_f]), Phi
