"""Which bending modes of a cantilever need Timoshenko theory: the criterion and its report.

Derivation. Timoshenko's Rayleigh quotient is
omega^2 = (int E I theta'^2 + kappa G A gamma^2) / (int rho A w^2 + rho I theta^2), gamma = w' -
theta. To first order in the section's radius of gyration r_g (r_g^2 = I / A), insert the
Euler-Bernoulli mode phi: the rotary inertia adds int rho I phi'^2 to the kinetic energy, and the
shear force V = (E I phi'')' adds int V^2 / (kappa G A) to the complementary energy of the same
bending moment. Both lower omega^2 by their ratio to the Euler-Bernoulli energies, so for a
uniform member

    omega_T / omega_EB = 1 - (1/2) c_n (r_g / L)^2 (1 + E / (kappa G)) + O((r_g / L)^4),

with c_n = L^2 int phi'^2 / int phi^2 = L^2 int phi'''^2 / int phi''^2 (equal by parts and the
mode's equation phi'''' = (beta_n / L)^4 phi). For the clamped-free modes c_n = 4.6478, 32.417,
77.299, 142.90, 228.13, 333.11 and c_n -> beta_n (beta_n + 2) (the simply supported value
beta_n^2 plus the clamp's and the free end's boundary layers); mode 1's is 1.32 beta_1^2. The
criterion: mode n needs Timoshenko when that Euler-Bernoulli error,

    e_n = 50 c_n (r_g / L)^2 (1 + E / (kappa G))  (%),

exceeds a tolerance, ``TIMOSHENKO_TOL_PCT`` = 0.1 % by default: the 0.1 % that a converged truth
is asked to hold between mesh levels (``TruthRequest.convergence_rtol``), so the theory's error
is never hidden inside the accepted discretisation error. For a steel rectangle (nu = 0.28,
kappa = 0.849: 1 + E / (kappa G) = 4.02) mode n needs it below the slenderness
L / r_g = 44.8 sqrt(c_n) (97, 255, 394, 536, 677 for modes 1-5), i.e. above t / L = 0.036,
0.014, 0.0088, 0.0065, 0.0051 for a solid rectangle (r_g = t / sqrt(12)). Against the exact
frequency equation the estimate is within 0.1 % of the error at L / r_g = 400 and 2 % at 100,
and above it at every slenderness tabulated, 10 ... 400 (scripts/bench_timoshenko.py): the
criterion errs on the safe side. For a member whose section varies, the thickest section's r_g
is used, and a taper also changes c_n (examples/beams/tapered.json, a width taper: 0.0054 %
estimated, 0.0065 % solved on mode 1), so :func:`timoshenko_criterion` also solves both 1D
theories and flags a mode when the larger of the estimate and the solved difference exceeds the
tolerance.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..member.geometry import Beam
from .timoshenko_sections import member_section_laws, shear_coefficient

__all__ = ["TIMOSHENKO_TOL_PCT", "TRUTH_WARNING_PCT", "CANTILEVER_C", "eb_error_estimate_pct",
           "TimoshenkoCriterion", "timoshenko_criterion", "timoshenko_warnings"]

TIMOSHENKO_TOL_PCT = 0.1
# the 1D truth warns past the threshold of the plate truth's Kirchhoff warning
# (Beam.kirchhoff_warnings, 1 %): the same neglected shear and rotary inertia, the same bar
TRUTH_WARNING_PCT = 1.0
# c_n = L^2 int phi'^2 / int phi^2 of the clamped-free modes 1-6 (quadrature of the closed-form
# modes: tests/timoshenko_reference.py); beyond, beta_n (beta_n + 2) is within 5e-5 of it
CANTILEVER_C = np.array([4.647778318679, 32.41739902797, 77.29889080230, 142.9018488352,
                         228.1332463527, 333.1130895932])
CANTILEVER_C.setflags(write=False)


def _c(n_modes: int) -> np.ndarray:
    n = np.arange(1, n_modes + 1)
    beta = (n - 0.5) * np.pi
    c = beta * (beta + 2.0)
    k = min(n_modes, CANTILEVER_C.size)
    c[:k] = CANTILEVER_C[:k]
    return c


def eb_error_estimate_pct(n_modes: int, rg_over_L: float, E_over_kappaG: float) -> np.ndarray:
    """First-order Euler-Bernoulli error of clamped-free bending modes 1..n_modes, in %.

    e_n = 50 c_n (r_g / L)^2 (1 + E / (kappa G)): how far the Euler-Bernoulli frequency lies
    above Timoshenko's (module docstring for the derivation).

    Parameters
    ----------
    n_modes : int
    rg_over_L : float
        Radius of gyration of the section over the length (dimensionless).
    E_over_kappaG : float
        Young's modulus over the shear coefficient times the shear modulus (dimensionless).

    Returns
    -------
    ndarray, shape (n_modes,)
    """
    if not isinstance(n_modes, (int, np.integer)) or isinstance(n_modes, bool) or n_modes < 1:
        raise BeamInputError(f"n_modes = {n_modes!r}: must be an integer >= 1")
    for name, v in (("rg_over_L", rg_over_L), ("E_over_kappaG", E_over_kappaG)):
        if not isinstance(v, (int, float, np.floating)) or isinstance(v, bool):
            raise InputTypeError(f"{name} = {v!r}: must be a number")
        if not (np.isfinite(v) and v > 0.0):
            raise BeamInputError(f"{name} = {v!r}: must be finite and > 0")
    return 50.0 * _c(int(n_modes)) * float(rg_over_L) ** 2 * (1.0 + float(E_over_kappaG))


@dataclass(frozen=True, eq=False)
class TimoshenkoCriterion:
    """Per bending mode of a beam: its estimated and its solved Euler-Bernoulli error.

    Attributes
    ----------
    estimate_pct : ndarray, shape (n,)
        The criterion's first-order estimate e_n, % (thickest section).
    gap_pct : ndarray, shape (n,) or None
        100 (omega_EB / omega_T - 1) from both 1D truths on the same mesh, %; None unsolved.
    needs_timoshenko : ndarray of bool, shape (n,)
        ``max(estimate_pct, gap_pct) > tol_pct`` (the estimate alone when unsolved).
    tol_pct : float
        The tolerance, %.
    slenderness : float
        L / r_g at the thickest section.
    kappa : float
        The shear coefficient used (Cowper's rectangle).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> crit = pp.timoshenko_criterion(beam, n_modes=2, solve=False)
    >>> isinstance(crit, pp.TimoshenkoCriterion), crit.gap_pct  # unsolved: the estimate only
    (True, None)
    >>> round(crit.slenderness, 2), round(float(np.sqrt(12)) / 0.01, 2)  # L / (t / sqrt(12))
    (346.41, 346.41)
    >>> round(crit.kappa, 4), round(10 * 1.28 / (12 + 11 * 0.28), 4)  # Cowper, nu = 0.28
    (0.8488, 0.8488)
    """

    estimate_pct: np.ndarray
    gap_pct: np.ndarray | None
    needs_timoshenko: np.ndarray
    tol_pct: float
    slenderness: float
    kappa: float

    @property
    def first_mode_needing(self) -> int | None:
        """The lowest mode (1-based) past the criterion, or None."""
        k = np.flatnonzero(self.needs_timoshenko)
        return int(k[0]) + 1 if k.size else None


def _estimate(beam: Beam, n_modes: int) -> tuple[np.ndarray, float, float]:
    if beam.section is None:
        kappa = shear_coefficient("rectangle", beam.material.nu)
        rg = beam.thickness_m / np.sqrt(12.0)  # the thickest section's (thickness_m is the max)
    else:  # a round member: r_g^2 = I / A = rho I_y / rho A, at its thickest station
        laws = member_section_laws(beam)  # refuses a section table by name
        x = beam.x_m
        r2 = np.asarray(laws.rhoI_kg_m(x), dtype=float) / np.asarray(laws.rhoA_kg_m(x))
        i = int(np.argmax(r2))
        rg = float(np.sqrt(r2[i]))
        kappa = float(np.asarray(laws.kappaGA_N(x))[i] * beam.material.rho_kg_m3
                      / (beam.material.G_Pa * np.asarray(laws.rhoA_kg_m(x))[i]))
    E_kG = beam.material.E_Pa / (kappa * beam.material.G_Pa)
    return eb_error_estimate_pct(n_modes, rg / beam.length_m, E_kG), beam.length_m / rg, kappa


def timoshenko_criterion(beam: Beam, n_modes: int = 5, tol_pct: float = TIMOSHENKO_TOL_PCT,
                         solve: bool = True, n_elements: int = 200) -> TimoshenkoCriterion:
    """Report, per bending mode, the Euler-Bernoulli error and whether Timoshenko is needed.

    Parameters
    ----------
    beam : Beam
    n_modes : int
        Bending modes 1..n_modes.
    tol_pct : float
        A mode needs Timoshenko when its estimated or solved error exceeds this, %.
    solve : bool
        Also solve both 1D truths (milliseconds) for the error itself (``gap_pct``).
    n_elements : int
        Elements of both solves (the same stations).

    Returns
    -------
    TimoshenkoCriterion

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> crit = pp.timoshenko_criterion(beam, n_modes=3, tol_pct=0.1, n_elements=50)
    >>> crit.estimate_pct.round(3), crit.gap_pct.round(3)  # %: the estimate, both 1D truths solved
    (array([0.008, 0.054, 0.129]), array([0.008, 0.054, 0.129]))
    >>> crit.needs_timoshenko  # the third mode's error passes 0.1 %
    array([False, False,  True])
    """
    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r}: must be a prbdm_pin.Beam")
    if (isinstance(tol_pct, bool) or not isinstance(tol_pct, (int, float, np.floating))
            or not (np.isfinite(tol_pct) and tol_pct > 0.0)):
        raise BeamInputError(f"tol_pct = {tol_pct!r}: must be a finite number > 0 (%)")
    est, slender, kappa = _estimate(beam, n_modes)
    gap = None
    if solve:
        from .beam import beam_modal
        from .beam_timoshenko import beam_timoshenko_modal

        eb = beam_modal(beam, n_modes=n_modes, n_elements=n_elements).omega_rad_s
        tim = beam_timoshenko_modal(beam, n_modes=n_modes, n_elements=n_elements).omega_rad_s
        gap = 100.0 * (eb / tim - 1.0)
        gap.setflags(write=False)
    est.setflags(write=False)
    needs = (est if gap is None else np.maximum(est, gap)) > tol_pct
    needs.setflags(write=False)
    return TimoshenkoCriterion(est, gap, needs, float(tol_pct), float(slender), float(kappa))


def timoshenko_warnings(beam: Beam, modes: int,
                        tol_pct: float = TRUTH_WARNING_PCT) -> tuple[str, ...]:
    """Return the 1D Euler-Bernoulli truth's warning when its highest mode is past ``tol_pct`` %.

    Closed form only (no solve), so a slender member's truth is unchanged and costs nothing more.
    A section table has no shear stiffness to estimate from: no warning.
    """
    from ..member.section_table import SectionTable

    if isinstance(beam.section, SectionTable):
        return ()
    est, slender, _ = _estimate(beam, max(int(modes), 1))
    if est[-1] <= tol_pct:
        return ()
    first = int(np.flatnonzero(est > tol_pct)[0]) + 1
    size = (f"thickness = {beam.thickness_m:g} m" if beam.section is None
            else f"outer diameter = {beam.thickness_m:g} m")  # a round member's D as thickness
    return (f"{size} (L / r_g = {slender:.3g}): the 1D "
            f"Euler-Bernoulli truth neglects shear and rotary inertia, which lower mode "
            f"{first} by about {est[first - 1]:.2g} % and mode {est.size} by about "
            f"{est[-1]:.2g} %; compare prbdm_pin.timoshenko_criterion(beam) and "
            "beam_timoshenko_modal, or use the 3D solid (--model solid)",)
