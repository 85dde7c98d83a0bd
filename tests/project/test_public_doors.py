"""Every public door checked: a wrong type, a non-finite, out-of-range or implausible value is
refused where it enters, by a ValueError or TypeError subclass whose message names the argument
or field, never a traceback from inside numpy, Pinocchio, pathlib or the OS.

References: the ranges the command line documents and refuses (``--starts``, ``--pop``,
``--damping``, ``--eps``), the SI magnitudes of solids and members, and the joint stations
computed here from the link lengths."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from paths import ROOT

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError, InputTypeError
from prbdm_pin.fitting.calibration_data import ring_down

BEAM = pp.load_beam(ROOT / "examples" / "beams" / "uniform-narrow.json")
LENGTHS = np.array([0.2, 0.3, 0.3, 0.2])  # joints at 0.2, 0.5, 0.8 m
SPRINGS = np.array([1000.0, 800.0, 500.0])
CASES = settings(max_examples=25, deadline=None)


def _refused(exc_type, names, fn, *args, **kwargs):
    """Call ``fn``; it must raise ``exc_type`` naming one of ``names``; return the message.

    A BeamInputError that is not a type error must not pass as a TypeError and vice versa.
    """
    with pytest.raises(exc_type) as info:
        fn(*args, **kwargs)
    msg = str(info.value)
    if exc_type is InputTypeError:
        assert isinstance(info.value, TypeError), msg
    else:
        assert not isinstance(info.value, TypeError), msg
    names = (names,) if isinstance(names, str) else names
    assert any(n in msg for n in names), (names, msg)
    assert "\n" not in msg
    return msg


# --------------------------------------------------------------------------------------------
# the public dataclasses: every field, random wrong types, non-finite and out-of-range values

WRONG_TYPES = ["1.0", b"1", {"v": 1.0}, [1.0], object(), 1j, True]
NON_FINITE = [math.nan, math.inf, -math.inf, 10**400]


# (class, keyword arguments that make a valid object, field, name in the message, kind,
#  values below the range, values above it)
FIELDS = [
    (pp.Material, {}, "E_Pa", "material.E", "real", [-1.0, 0.0, 205.0, 2.05e5], [1e14]),
    (pp.Material, {}, "rho_kg_m3", "material.rho", "real", [-7850.0, 0.0], []),
    (pp.Material, {}, "nu", "material.nu", "real", [-1.0, -3.0], [0.5, 10.0]),
    (pp.Hub, {"inertia_kg_m2": 1.0}, "inertia_kg_m2", "Hub inertia_kg_m2", "real",
     [0.0, -5.0], [1e21, 1e300]),
    (pp.Hub, {"inertia_kg_m2": 1.0}, "radius_m", "Hub radius_m", "real", [-0.1], [1e4, 1e300]),
    (pp.FreeBus, {"mass_kg": 1.0, "inertia_kg_m2": [1.0, 1.0, 1.0]}, "mass_kg",
     "FreeBus mass_kg", "real", [0.0, -5.0], []),
    (pp.StrainActuator, {"x_start_m": 0.1, "x_end_m": 0.5}, "x_start_m", "x_start_m", "real",
     [-0.1, -1e-9], [0.5, 2e3]),
    (pp.StrainActuator, {"x_start_m": 0.0, "x_end_m": 0.5}, "x_end_m", "x_end_m", "real",
     [0.0, -1.0], [1e4]),
    (pp.DistributedLoad, {"x_start_m": 0.1, "x_end_m": 0.5}, "x_start_m", "x_start_m", "real",
     [-0.1, -1e-9], [0.5, 2e3]),
    (pp.DistributedLoad, {"x_start_m": 0.0, "x_end_m": 0.5}, "x_end_m", "x_end_m", "real",
     [0.0, -1.0], [1e4]),
    (pp.DistributedLoad, {"x_start_m": 0.0, "x_end_m": 0.5}, "start_weight", "start_weight",
     "real", [], []),
    (pp.DistributedLoad, {"x_start_m": 0.0, "x_end_m": 0.5}, "end_weight", "end_weight",
     "real", [], []),
    (pp.FitOptions, {}, "starts", "starts", "int", [0, -1], [100_001, 10**12]),
    (pp.FitOptions, {}, "seed", "seed", "int", [-1], [2**63, 2**70]),
    (pp.FitOptions, {}, "polish", "polish", "int", [-1], [100_001]),
    (pp.FitOptions, {}, "max_nfev", "max_nfev", "int", [0], [100_001]),
    (pp.FitOptions, {}, "explore_nfev", "explore_nfev", "int", [0], [100_001]),
    (pp.FitOptions, {}, "refine_starts", "refine_starts", "int", [-1], [100_001]),
    (pp.FitOptions, {}, "xi_rad", "xi_rad", "real", [-0.1], [1.6, 1e300]),
    (pp.FitOptions, {}, "eps_rad", "eps_rad", "real", [0.0, -0.1], [1.6, 1e300]),
    (pp.FitOptions, {}, "min_fraction", "min_fraction", "real", [0.0, -0.1], [0.5, 2.0]),
    (pp.FitOptions, {}, "loss_tol_pct", "loss_tol_pct", "real", [-1.0], []),
    (pp.ParetoOptions, {}, "pop", "pop", "int", [1, 3, 0], [100_001]),
    (pp.ParetoOptions, {}, "generations", "generations", "int", [0], [1_000_001]),
    (pp.ParetoOptions, {}, "seed_starts", "seed_starts", "int", [0], [100_001]),
    (pp.SimulationOptions, {}, "damping_ratio", "damping_ratio", "real", [-0.1],
     [1.0, 2.0]),
    (pp.SimulationOptions, {}, "dt_s", "dt_s", "real", [0.0, -1e-3], []),
    (pp.SimulationOptions, {}, "rtol", "rtol", "real", [0.0], []),
    (pp.SimulationOptions, {}, "refresh_rad", "refresh_rad", "real", [-0.1], []),
    (pp.SimulationOptions, {}, "max_steps", "max_steps", "int", [0], []),
    (pp.QuadraticCost, {}, "tip_weight_per_m2", "QuadraticCost tip_weight_per_m2", "real",
     [-1.0, -1e-9], []),
    (pp.QuadraticCost, {}, "terminal_tip_weight_per_m2",
     "QuadraticCost terminal_tip_weight_per_m2", "real", [-1.0], []),
    # the compiled DOP853's tolerance: (1e-14, 0.1), the issue's range
    (pp.Compiled, {}, "rtol", "rtol", "real", [0.0, -1.0, 1e-15, 1e-14], [0.1, 0.5]),
    (pp.Compiled, {}, "atol", "atol", "real", [0.0, -1e-9], []),
    # the accuracy the default's rule is asked for: the same range as a tolerance
    (pp.Auto, {}, "tolerance", "tolerance", "real", [0.0, -1.0, 1e-15, 1e-14], [0.1, 0.5]),
    (pp.FitSettings, {}, "joints", "joints", "int", [0, -1], [65, 1000]),
    (pp.BatchSpec, {"seed": 0, "settings": pp.FitSettings(joints=3), "n_beams": 5}, "seed",
     "seed", "int", [-1], [2**63]),
    (pp.BatchSpec, {"seed": 0, "settings": pp.FitSettings(joints=3), "n_beams": 5}, "n_beams",
     "beams", "int", [0, -5], [10**7]),  # prbdm batch: at most 1e6 beams in one shard
]
FIELD_IDS = [f"{c.__name__}.{f}" for c, _, f, *_ in FIELDS]


@pytest.mark.parametrize("case", FIELDS, ids=FIELD_IDS)
@CASES
@given(data=st.data())
def test_a_dataclass_field_of_the_wrong_type_is_a_type_error_naming_it(case, data):
    cls, base, field, shown, kind, _, _ = case
    wrong = WRONG_TYPES + ([2.5, "3"] if kind == "int" else [])
    if field == "damping_ratio":  # one ratio per mode is a list
        wrong = [v for v in wrong if not isinstance(v, list)]
    value = data.draw(st.sampled_from(wrong))
    _refused(InputTypeError, shown, cls, **{**base, field: value})


@pytest.mark.parametrize("case", FIELDS, ids=FIELD_IDS)
@CASES
@given(data=st.data())
def test_a_dataclass_field_out_of_range_or_not_finite_is_a_value_error_naming_it(case, data):
    cls, base, field, shown, kind, below, above = case
    bad = below + above + (NON_FINITE if kind == "real" else [])
    value = data.draw(st.sampled_from(bad))
    _refused(BeamInputError, shown, cls, **{**base, field: value})


@pytest.mark.parametrize("cls,field", [(pp.FitOptions, "starts"), (pp.FitOptions, "max_nfev"),
                                       (pp.ParetoOptions, "pop"),
                                       (pp.ParetoOptions, "generations")])
def test_the_api_caps_are_the_command_lines(cls, field):
    # prbdm fit/pareto refuse --starts, --max-nfev, --pop, --generations outside 1..100000,
    # 1..100000, 4..100000 and 1..1000000 (docs/cli.md); the options objects take the same
    low, high = {"starts": (1, 100_000), "max_nfev": (1, 100_000), "pop": (4, 100_000),
                 "generations": (1, 1_000_000)}[field]
    assert getattr(cls(**{field: low}), field) == low
    assert getattr(cls(**{field: high}), field) == high
    for v in (low - 1, high + 1):
        _refused(BeamInputError, f"{field} = {v}", cls, **{field: v})


def test_the_damping_ratio_range_is_the_command_lines_in_every_door(tmp_path):
    # prbdm simulate/linearize/export refuse --damping 1.0 and take 0.999 (0 <= zeta < 1)
    assert pp.SimulationOptions(damping_ratio=0.999).damping_ratio == 0.999
    assert pp.SimulationOptions(damping_ratio=(0.0, 0.5)).damping_ratio == (0.0, 0.5)
    for bad in (1.0, 2.0, math.nan, (0.1, 1.0)):
        _refused(BeamInputError, "damping_ratio", pp.SimulationOptions, damping_ratio=bad)
    model = pp.build_model(BEAM, LENGTHS, SPRINGS)
    _refused(BeamInputError, "damping_ratio", pp.linearize, model, damping_ratio=2.0)
    _refused(BeamInputError, "damping_ratio", pp.simulate, model, 0.01, damping_ratio=1.0)
    _refused(BeamInputError, "damping_ratio", pp.export_model, model, tmp_path / "m.urdf",
             "urdf", damping_ratio=1.5)
    assert not list(tmp_path.iterdir())


def test_feedback_and_controller_fields_are_checked():
    _refused(InputTypeError, "StateFeedback gain", pp.StateFeedback, [1.0, 2.0])
    _refused(InputTypeError, "StateFeedback gain", pp.StateFeedback, "K")
    _refused(BeamInputError, "StateFeedback gain[0, 1]", pp.StateFeedback, [[1.0, math.nan]])
    _refused(BeamInputError, "StateFeedback x_ref[1]", pp.StateFeedback, [[1.0, 2.0]],
             x_ref=[0.0, math.inf])
    _refused(InputTypeError, "StateFeedback u_ref", pp.StateFeedback, [[1.0, 2.0]], u_ref="u")
    _refused(InputTypeError, "Controller function", pp.Controller, 3.0)
    _refused(InputTypeError, "settings", pp.BatchSpec, 0, None, n_beams=3)
    pp.StateFeedback([[1.0, 2.0]], x_ref=[0.1, 0.0], u_ref=lambda t: [0.0])


def test_vector_fields_refuse_nan_complex_and_wrong_sizes():
    F = BEAM.tip_force_N
    tip, disp = [0.94, 0.0, -0.3], [-0.06, 0.0, -0.3]
    _refused(BeamInputError, "tip_position_m[0]", pp.FitTarget, [10.0], F, [math.nan, 0, 0],
             disp)
    _refused(BeamInputError, "tip_force_N[2]", pp.FitTarget, [10.0], [0.0, 0.0, math.inf])
    _refused(BeamInputError, "tip_displacement_m", pp.FitTarget, [10.0], F, tip, [0.0, 0.0])
    _refused(InputTypeError, "omega_truth_rad_s", pp.FitTarget, [10.0 + 1j], F)
    _refused(InputTypeError, "tip_force_N", pp.FitTarget, [10.0], "down")
    _refused(BeamInputError, "tip_position_m[1]", pp.LoadCase, F, [1.0, math.nan, 0.0], disp)
    _refused(InputTypeError, "extra_loads[0]", pp.FitTarget, [10.0], F, tip, disp,
             extra_loads=(2.0,))


# --------------------------------------------------------------------------------------------
# every public function: a wrong type for its object or path argument is a TypeError naming it

def _lin():
    return pp.build_model(BEAM, LENGTHS, SPRINGS)


# a ring-down of one mode, 2 s at 100 Hz (the data a calibrate door check passes)
_T = np.arange(200) / 100.0
RING = ring_down(_T, np.exp(-_T) * np.cos(50 * _T), ["tip_z"])

# public function -> (argument, call with the bad value in that argument's place)
DOORS = {
    "load_beam": ("path", lambda v: pp.load_beam(v)),
    "save_beam": ("beam", lambda v: pp.save_beam(v, "never.json")),
    "load_schema": ("name", lambda v: pp.load_schema(v)),
    "random_beam": ("rng", lambda v: pp.random_beam(v)),
    "beam_from_dict": ("beam", lambda v: pp.beam_from_dict(v)),
    "round_beam": ("outer_diameter", lambda v: pp.round_beam([0.0, 1.0], v)),
    "table_beam": ("section", lambda v: pp.table_beam([0.0, 1.0], v)),
    "section_properties": ("beam", lambda v: pp.section_properties(v, 0.5)),
    "link_sections": ("beam", lambda v: pp.link_sections(v, LENGTHS)),
    "validate_lengths": ("beam", lambda v: pp.validate_lengths(v, LENGTHS)),
    "sample_lengths": ("rng", lambda v: pp.sample_lengths(v, 1.0, 3, 2)),
    "repair_lengths": ("lengths", lambda v: pp.repair_lengths(v, 1.0)),
    "pose_sweep": ("n_joints", lambda v: pp.pose_sweep(v)),
    "paper_stiffness": ("sections", lambda v: pp.paper_stiffness(v, 205e9, 1.0)),
    "finite_segment_stiffness": ("beam", lambda v: pp.finite_segment_stiffness(v, LENGTHS)),
    "spatial_stiffness": ("beam", lambda v: pp.spatial_stiffness(v, LENGTHS, "xy")),
    "corner_static": ("beam", lambda v: pp.corner_static(v)),
    "with_point_gains": ("target", lambda v: pp.with_point_gains(v, None, BEAM)),
    "spatial_load_target": ("target", lambda v: pp.spatial_load_target(v, None)),
    "model_gradient": ("beam", lambda v: pp.model_gradient(v, LENGTHS, SPRINGS)),
    "build_model": ("beam", lambda v: pp.build_model(v, LENGTHS, SPRINGS)),
    "load_urdf": ("path", lambda v: pp.load_urdf(v)),
    "fit_strain_actuators": ("model", lambda v: pp.fit_strain_actuators(v, None, BEAM, [])),
    "linearize": ("model", lambda v: pp.linearize(v)),
    "statics": ("model", lambda v: pp.statics(v)),
    "spinning_frequencies": ("model", lambda v: pp.spinning_frequencies(v, 1.0)),
    "gyroscopic_frequencies": ("lin", lambda v: pp.gyroscopic_frequencies(v)),
    "compare_plant": ("prbdm", lambda v: pp.compare_plant(v, None)),
    "compare_truth": ("model", lambda v: pp.compare_truth(v)),
    "compare_truth_plant": ("lin", lambda v: pp.compare_truth_plant(v, None, None)),
    "load_model": ("path", lambda v: pp.load_model(v)),
    "compute_truth": ("beam", lambda v: pp.compute_truth(v)),
    "beam_gravity_modal": ("beam", lambda v: pp.beam_gravity_modal(v, [9.81, 0.0, 0.0])),
    "beam_gravity_static": ("beam", lambda v: pp.beam_gravity_static(v, [0.0, 0.0, -9.81])),
    "beam_self_weight_buckling": ("beam", lambda v: pp.beam_self_weight_buckling(v)),
    "elastica_gravity_modes": ("beam", lambda v: pp.elastica_gravity_modes(v, [0, 0, -9.81])),
    "timoshenko_criterion": ("beam", lambda v: pp.timoshenko_criterion(v)),
    "timoshenko_modal": ("sections", lambda v: pp.timoshenko_modal(v, 1.0)),
    "timoshenko_static": ("sections", lambda v: pp.timoshenko_static(v, 1.0, 1.0)),
    "beam_timoshenko_modal": ("beam", lambda v: pp.beam_timoshenko_modal(v)),
    "beam_timoshenko_static": ("beam", lambda v: pp.beam_timoshenko_static(v)),
    "rectangle_section_laws": ("beam", lambda v: pp.rectangle_section_laws(v)),
    "shear_coefficient": ("kind", lambda v: pp.shear_coefficient(v, 0.3)),
    "round_solid_modes": ("beam", lambda v: pp.round_solid_modes(v)),
    "tube_solid_modes": ("material", lambda v: pp.tube_solid_modes([0.0, 1.0], [0.02, 0.02],
                                                                   None, v)),
    "truth_gradient": ("beam", lambda v: pp.truth_gradient(v, ("thickness",))),
    "elastica_gradient": ("beam", lambda v: pp.elastica_gradient(v, ("thickness",))),
    "target_from_truth": ("truth", lambda v: pp.target_from_truth(v, [0.0, 0.0, -1.0])),
    "gravity_target": ("beam", lambda v: pp.gravity_target(v, [0.0, 0.0, -9.81])),
    "fit": ("beam", lambda v: pp.fit(v, None, 3)),
    "fit_pareto": ("beam", lambda v: pp.fit_pareto(v, None, 2)),
    "fit_sweep": ("designs", lambda v: pp.fit_sweep(v, [], 2)),
    "fit_derivative": ("result", lambda v: pp.fit_derivative(v, lambda p: BEAM, 0.0,
                                                             lambda b: None)),
    "fit_design_gradient": ("result", lambda v: pp.fit_design_gradient(v, None, None, None)),
    "codesign_point": ("design", lambda v: pp.codesign_point(v, [0.01])),
    "load_fit": ("path", lambda v: pp.load_fit(v)),
    "save_fit": ("result", lambda v: pp.save_fit(v, "never.json")),
    "simulate": ("model", lambda v: pp.simulate(v, 0.01)),
    "trajectory_gradient": ("model", lambda v: pp.trajectory_gradient(v, 0.01,
                                                                      pp.QuadraticCost())),
    "chain_kernel": ("pin_model", lambda v: pp.chain_kernel(v, 0)),
    "simulate_batch": ("models", lambda v: pp.simulate_batch(v, 0.01)),
    "frequencies_batch": ("models", lambda v: pp.frequencies_batch(v)),
    "linearize_batch": ("models", lambda v: pp.linearize_batch(v)),
    "dynamic_accuracy": ("model", lambda v: pp.dynamic_accuracy(v, None)),
    "export_model": ("model", lambda v: pp.export_model(v, "never.urdf", "urdf")),
    "fit_joint_damping": ("model", lambda v: pp.fit_joint_damping(v, 0.02)),
    "read_model_json": ("path", lambda v: pp.read_model_json(v)),
    "read_plant_json": ("path", lambda v: pp.read_plant_json(v)),
    "link_meshes": ("model", lambda v: pp.link_meshes(v)),
    "planform_link_mesh": ("beam", lambda v: pp.planform_link_mesh(v, 0.0, 0.1)),
    "round_link_mesh": ("length_m", lambda v: pp.round_link_mesh(v, 0.02, 0.02)),
    "run_batch": ("spec", lambda v: pp.run_batch(v, "never-batch")),
    "calibrate": ("model", lambda v: pp.calibrate(v, RING, "E")),
    "read_ring_down": ("path", lambda v: pp.read_ring_down(v)),
    "read_calibration_data": ("path", lambda v: pp.read_calibration_data(v)),
    "plot_calibration": ("result", lambda v: pp.plot_calibration(v)),
    "write_calibration": ("result", lambda v: pp.write_calibration(v, "never-calibration")),
    "chain_modes": ("model", lambda v: pp.chain_modes(v)),
    "plot_mode_shapes": ("model", lambda v: pp.plot_mode_shapes(v, path="never.png")),
    "animate_response": ("model", lambda v: pp.animate_response(v, None, "never.gif")),
    "write_model_modes_vtu": ("model", lambda v: pp.write_model_modes_vtu(v, "never.vtu")),
    "write_trajectory_vtu": ("model", lambda v: pp.write_trajectory_vtu(v, None, "never")),
    "open_meshcat": ("model", lambda v: pp.open_meshcat(v)),
}
# a path argument takes a str: the other wrong types are for it
PATH_WRONG = [None, 3, 2.5, [1.0], {"p": 1}, b"beam.json", object()]
OBJECT_WRONG = PATH_WRONG + ["beam", "model.urdf"]


def test_every_public_function_has_a_door_check():
    functions = {n for n in pp.__all__ if n != "__version__"
                 and callable(getattr(pp, n)) and not isinstance(getattr(pp, n), type)}
    assert functions == set(DOORS), sorted(functions ^ set(DOORS))


@pytest.mark.parametrize("name", sorted(DOORS))
@settings(max_examples=6, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_a_wrong_type_at_a_public_door_is_a_type_error_naming_the_argument(
        name, data, tmp_path_factory, monkeypatch):
    monkeypatch.chdir(tmp_path_factory.mktemp("doors"))
    arg, call = DOORS[name]
    wrong = PATH_WRONG if arg == "path" else OBJECT_WRONG
    # values of the right type that fail on their content (a count, a list of one link, a
    # mapping with unknown keys) are not this test's
    if name == "pose_sweep":
        wrong = [v for v in wrong if v != 3]
    if name in ("repair_lengths", "fit_sweep", "round_beam"):
        wrong = [v for v in wrong if v != [1.0]] + [["a", "b"]]
    if name == "beam_from_dict":
        wrong = [v for v in wrong if not isinstance(v, dict)]
    # a section kind or a schema name is a str: an unknown one is a value error
    if name in ("shear_coefficient", "load_schema"):
        wrong = [v for v in wrong if not isinstance(v, str)]
    if name == "round_link_mesh":  # 3 and 2.5 are valid lengths (m)
        wrong = [v for v in wrong if not isinstance(v, (int, float))]
    value = data.draw(st.sampled_from(wrong))
    _refused(InputTypeError, f"{arg}", call, value)
    assert os.listdir(".") == []  # nothing written


def test_the_reported_probes_are_refused_by_name(tmp_path):
    # springs of 1e300: no joint of this strip holds them (E I / L = 854 N m)
    _refused(BeamInputError, "stiffness[0] = 1e+300", pp.build_model, BEAM, LENGTHS,
             [1e300, 800.0, 500.0])
    # complex link lengths: the imaginary part would be dropped with a warning
    _refused(InputTypeError, "lengths", pp.build_model, BEAM, LENGTHS + 0j, SPRINGS)
    _refused(BeamInputError, "eps_rad = 1e+300", pp.FitOptions, eps_rad=1e300)
    _refused(BeamInputError, "Hub radius_m = 1e+300", pp.Hub, 5.0, 1e300)
    _refused(BeamInputError, "StrainActuator x_start_m = -0.1", pp.StrainActuator, -0.1, 0.3)
    _refused(BeamInputError, "material.nu", pp.Material, nu=10**400)
    _refused(InputTypeError, "path", pp.load_beam, None)
    _refused(InputTypeError, "beam", pp.fit, None, None, 3)
    target = pp.FitTarget([10.0, 60.0, 170.0], BEAM.tip_force_N)
    _refused(InputTypeError, "target", pp.fit, BEAM, "target", 3)
    _refused(BeamInputError, "joints = 0", pp.fit, BEAM, target, 0)
    _refused(InputTypeError, "workers", pp.fit, BEAM, target, 3, workers=1.5)
    # export onto an existing folder: refused before anything is written
    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "mine.txt").write_text("kept")
    model = pp.build_model(BEAM, LENGTHS, SPRINGS)
    _refused(BeamInputError, "path", pp.export_model, model, folder, "urdf")
    _refused(BeamInputError, "path", pp.export_model, model, folder / "mine.txt" / "m.urdf",
             "urdf")
    _refused(BeamInputError, "path", pp.export_model, model, "/proc/prbdm.urdf", "urdf")
    _refused(BeamInputError, "path", pp.save_beam, BEAM, folder)
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["mine.txt", "out"]


# --------------------------------------------------------------------------------------------
# plausibility of units

@pytest.mark.parametrize("E, slip", [(205.0, "GPa"), (70.0, "GPa"), (205e3, "MPa")])
def test_a_modulus_in_gpa_mpa_or_kpa_is_named_with_the_slip(E, slip, tmp_path):
    msg = _refused(BeamInputError, "material.E", pp.Material, E_Pa=E)
    assert f"given in {slip}?" in msg and "Pa" in msg
    # the same from a beam file, before any solver sees it
    d = pp.beam_from_dict({"x": [0.0, 1.0], "half_width": [0.02, 0.02], "thickness": 0.01})
    path = tmp_path / "b.json"
    pp.save_beam(d, path)
    text = path.read_text().replace("205000000000.0", repr(E))
    path.write_text(text)
    assert slip in _refused(BeamInputError, "material.E", pp.load_beam, path)


@pytest.mark.parametrize("kw, field, slip", [
    ({"thickness_m": 5000.0}, "thickness", "mm"),  # 5 m thick, in mm
    ({"thickness_m": 2e-6}, "thickness", ""),  # 2 um: thinner than a foil
    ({"half_width_m": [2e3, 2e3]}, "half_width", "mm"),
    ({"x_m": [0.0, 1e4]}, "length", "mm"),  # 10 km long, in mm
])
def test_sizes_outside_10um_to_1km_are_named(kw, field, slip):
    base = {"x_m": [0.0, 1.0], "half_width_m": [0.02, 0.02], "thickness_m": 0.01}
    msg = _refused(BeamInputError, field, pp.Beam, **{**base, **kw})
    assert "1e-05 ... 1000 m" in msg and (f"given in {slip}?" in msg if slip else True)


def test_a_panel_hundreds_of_times_wider_than_long_is_refused_before_its_truth():
    # 300 mm wide read as 300 m: the plate truth would mesh the whole width (126 s)
    msg = _refused(BeamInputError, "half_width", pp.Beam, [0.0, 1.0], [150.0, 150.0], 0.01)
    assert "300 m wide" in msg and "300 times its length" in msg
    # the shipped square plate (as wide as long) and a 20:1 panel are members
    pp.Beam([0.0, 1.0], [10.0, 10.0], 0.01)


def test_the_plausible_ranges_end_where_documented():
    # E in [1e6, 1e13] Pa, sizes in [1e-5, 1e3] m: both ends accepted
    for E in (1e6, 1e13):
        pp.Material(E_Pa=E)
    pp.Beam([0.0, 1e-3], [1e-5, 1e-5], 1e-5)
    pp.Beam([0.0, 1e3], [1e3, 1e3], 1e3)


# --------------------------------------------------------------------------------------------
# the joint cap and the strain patch

def test_build_model_caps_joints_as_the_command_line_does(monkeypatch):
    n = 65  # one over the default cap (PRBDM_MAX_JOINTS, 64)
    lengths = np.full(n + 1, 1.0 / (n + 1))
    springs = np.full(n, 1e4)
    msg = _refused(BeamInputError, "joints = 65", pp.build_model, BEAM, lengths, springs,
                   min_fraction=1e-3)
    assert "PRBDM_MAX_JOINTS" in msg
    _refused(BeamInputError, "joints = 65", pp.fit, BEAM, pp.FitTarget([1.0], [0, 0, 1]), 65)
    monkeypatch.setenv("PRBDM_MAX_JOINTS", "100")
    assert pp.build_model(BEAM, lengths, springs, min_fraction=1e-3).n_joints == n


@pytest.mark.parametrize("patch", [(0.0, 0.05), (0.55, 0.75), (0.85, 1.0)])
def test_a_patch_between_joints_is_refused_naming_the_nearest_joints(patch):
    model = pp.build_model(BEAM, LENGTHS, SPRINGS)
    x = np.cumsum(LENGTHS)[:-1]  # 0.2, 0.5, 0.8 m
    below, above = x[x < patch[0]], x[x > patch[1]]
    msg = _refused(BeamInputError, "holds no joint", pp.linearize, model,
                   inputs=("strain[0]",), actuators=(pp.StrainActuator(*patch),))
    for station in (*below[-1:], *above[:1]):
        assert f"{station:g} m" in msg
    # a patch over a joint, and one with weights, are taken
    lin = pp.linearize(model, inputs=("strain[0]",), actuators=(pp.StrainActuator(0.1, 0.3),))
    np.testing.assert_array_equal(lin.input_map[:, 0], [1.0, 0.0, 0.0])
    w = pp.StrainActuator(*patch, joint_weights=(0.3, 0.1, 0.0))
    lin = pp.linearize(model, inputs=("strain[0]",), actuators=(w,))
    np.testing.assert_array_equal(lin.input_map[:, 0], [0.3, 0.1, 0.0])
