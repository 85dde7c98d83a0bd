"""The tip error of a run against scipy's DOP853 at rtol 1e-11 on the same scene, for the
integrator tests. Imported as ``from dop853_tip_error import tip_error``; not a test module."""

from __future__ import annotations

import numpy as np

from prbdm_pin.simulation import ScipyIVP, simulate

REFERENCE = ScipyIVP("DOP853", rtol=1e-11)


def tip_error(model, duration_s, integrator, **scene):
    """Max tip deviation from DOP853 (rtol 1e-11) over the peak tip deflection, and the run."""
    ref = simulate(model, duration_s, integrator=REFERENCE, output_dt_s=1e-3, **scene)
    tr = simulate(model, duration_s, integrator=integrator, output_dt_s=1e-3, **scene)
    peak = np.abs(ref.tip_displacement_m).max()
    return float(np.abs(tr.tip_position_m - ref.tip_position_m).max() / peak), tr
