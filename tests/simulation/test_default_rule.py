"""The stated integrator rule (``simulation.default_rule``): the stiffness ratio it reads against
scipy's generalized eigensolver (the clamped chain) and the hub's closed-form rigid mode
elimination (``hub_frequencies``), and its choice in each of its three branches."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from kernel_models import hub, planar
from tolerances import eig_rtol

import prbdm_pin as pp
from prbdm_pin.model.hub import hub_frequencies
from prbdm_pin.simulation.default_rule import (
    STIFFNESS_RATIO_MAX,
    default_integrator,
    stiffness_ratio,
)
from prbdm_pin.simulation.system import assemble_system, force_function, mass_matrix


def _system(m, tip_force=None, inputs=None, xi=0.0):
    n = m.pin_model.nv
    force, constant = force_function(tip_force)
    return assemble_system(m, np.zeros(n), damping_ratios=np.full(n, xi), damping="modal",
                           schedule=None, tip_force_N=force, constant_force=constant,
                           damping_pose=None, inputs=inputs)


@pytest.mark.parametrize("n", [1, 3, 5, 8])
def test_the_stiffness_ratio_is_the_pencils(narrow, n):
    m = planar(narrow, n)
    w2 = scipy.linalg.eigh(m.stiffness_matrix(), m.mass_matrix(), eigvals_only=True)
    ref = float(np.sqrt(w2[-1] / w2[0]))
    # two solves of one pencil, one ill-conditioned at an end of the spectrum
    assert abs(stiffness_ratio(_system(m), np.zeros(n)) - ref) <= eig_rtol(np.sqrt(w2)) * ref


def test_the_hubs_rigid_mode_is_left_out(narrow):
    m = hub(narrow, "y")
    sy = _system(m)
    # the beam's three springs; the hub's coordinate has none
    w = hub_frequencies(mass_matrix(sy.pin_model, sy.data, np.zeros(4)), m.stiffness_Nm_per_rad)
    ref = float(w[-1] / w[1])
    assert abs(stiffness_ratio(sy, np.zeros(4)) - ref) <= eig_rtol(w[1:]) * ref


def test_the_rule_picks_by_scene(narrow):
    small, large = planar(narrow, 3), planar(narrow, 8)
    z3, z8 = np.zeros(6), np.zeros(16)
    assert stiffness_ratio(_system(small), z3[:3]) <= STIFFNESS_RATIO_MAX
    assert stiffness_ratio(_system(large), z8[:8]) > STIFFNESS_RATIO_MAX
    step = [0.0, 0.0, -0.5]
    # from rest: by the stiffness ratio
    assert isinstance(default_integrator(_system(small, step), z3), pp.Compiled)
    assert isinstance(default_integrator(_system(large, step), z8), pp.Exponential)
    # a release: compiled whatever the ratio
    release = np.concatenate([np.full(8, 0.1), np.zeros(8)])
    assert isinstance(default_integrator(_system(large), release), pp.Compiled)
    # what the kernel cannot serve: the exponential integrator
    assert isinstance(default_integrator(_system(small, lambda t: step), z3), pp.Exponential)
