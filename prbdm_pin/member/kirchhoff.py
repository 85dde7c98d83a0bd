"""Where a Kirchhoff plate misrepresents a member: transverse shear, rotary inertia, bars."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .geometry import Beam

__all__ = ["kirchhoff_warnings"]


def kirchhoff_warnings(beam: Beam, modes: int = 5, tol_pct: float = 1.0) -> tuple[str, ...]:
    """Where a Kirchhoff plate (the ``plate`` truths) misrepresents this beam, as warnings.

    Kirchhoff theory neglects transverse shear and rotary inertia. By Timoshenko (and
    Mindlin) theory they lower bending mode m of wavenumber k_m = beta_m / L by about
    (k_m r)^2 (1 + E / (kappa G)) / 2 (r^2 = t^2 / 12, kappa = 5/6): 0.60 (t/L)^2 for
    mode 1 and a factor beta_m^2 / beta_1^2 more for mode m (about 0.6 % at t = L/10 on
    mode 1, 1 % at t = L/45 on mode 4). A warning when that exceeds ``tol_pct`` (%) for the
    highest of ``modes`` modes. Across the width a Kirchhoff plate needs the width to exceed
    the thickness: a section thicker than wide is a bar whose softer, lateral bending in the
    plane of the planform a plate cannot have (at t/width = 0.2, the shipped narrow
    strips, the plate stays within a few tenths of a percent of Euler-Bernoulli theory).

    Parameters
    ----------
    beam : Beam
    modes : int
        Bending modes the truth selects.
    tol_pct : float
        Estimated shear and rotary-inertia error that triggers a warning, %.
    """
    if beam.section is not None:  # no plate of a round section: the plate refuses it
        return ()
    m = max(int(modes), 1)
    roots = (1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349)
    beta = roots[m - 1] if m <= 4 else (m - 0.5) * np.pi
    t, L = beam.thickness_m, beam.length_m
    shear = 1.0 + beam.material.E_Pa / (5.0 / 6.0 * beam.material.G_Pa)
    est = 100.0 * 0.5 * (beta * t / L) ** 2 / 12.0 * shear
    out = []
    advice = "use the 3D solid (prbdm truth --model solid, prbdm fit --truth-model solid)"
    if est > tol_pct:
        out.append(
            f"thickness = {t:g} m is {t / L:.3g} L: past Kirchhoff plate theory for "
            f"{m} mode{'s' if m > 1 else ''} (transverse shear and rotary inertia, which "
            f"it neglects, lower mode {m} by "
            f"{f'about {est:.2g} %' if est < 10 else 'far more than 10 %'}); {advice}"
        )
    b = 2.0 * float(beam.half_width_m.min())
    if t > b:
        out.append(
            f"thickness = {t:g} m exceeds the narrowest width {b:g} m: that section is a bar, "
            f"not a plate (Kirchhoff theory needs t << width; its lateral, in-plane bending "
            f"is softer than the plate's and absent from it); {advice}"
        )
    return tuple(out)
