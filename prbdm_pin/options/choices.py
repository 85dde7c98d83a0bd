"""Enumerated choices of the fit, the truth and the exports, and the defaults of the fit.

Each set is written here once, as a ``str`` enumeration free of numpy and the numerics, so that
the command line lists them in ``prbdm COMMAND --help`` without loading either; the modules that
act on a choice import it from here. A member equals its string (``Objective.EIGEN == "eigen"``),
so a user may pass either.
"""

from __future__ import annotations

from enum import Enum

__all__ = [
    "Choice",
    "Objective",
    "StiffnessKind",
    "EigenNorm",
    "DeflectionNorm",
    "UniqueRule",
    "OBJECTIVES",
    "STIFFNESS_KINDS",
    "EIGEN_NORMS",
    "DEFLECTION_NORMS",
    "DEFAULT_EIGEN_NORM",
    "TRUTH_MODELS",
    "FORMATS",
    "EXPORT_DAMPING_FORMS",
    "DAMPING_FORMS",
    "FIXED_STEP_METHODS",
    "IVP_METHODS",
    "AXES",
    "Axes",
    "POINT_NAMES",
    "XI_RAD",
    "EPS_RAD",
    "PARETO_EPS_RAD",
    "MIN_FRACTION",
    "LINK_FLOOR_FRACTION",
]


class Choice(str, Enum):
    """A named choice that is also its string (JSON and f-strings see the value)."""

    def __str__(self) -> str:
        """Return the choice's string, as the command line and the JSON files spell it."""
        return str(self.value)

    @classmethod
    def values(cls) -> tuple[str, ...]:
        """Return the allowed strings, in declaration order."""
        return tuple(m.value for m in cls)


class Objective(Choice):
    """What a fit minimises: equation 17, equation 19 or equation 27.

    The fit asks an objective which terms it has (:attr:`has_eigen_term`,
    :attr:`has_deflection_term`) instead of testing its name.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> pp.Objective.values()
    ('eigen', 'deflection', 'combined')
    >>> pp.Objective("combined").has_eigen_term, pp.Objective("combined").has_deflection_term
    (True, True)
    """

    EIGEN = "eigen"
    DEFLECTION = "deflection"
    COMBINED = "combined"

    @property
    def has_eigen_term(self) -> bool:
        """Whether the loss has the frequency term (equation 17): ``eigen`` and ``combined``."""
        return self is not Objective.DEFLECTION

    @property
    def has_deflection_term(self) -> bool:
        """Whether the loss has the tip term (equation 19): ``deflection`` and ``combined``."""
        return self is not Objective.EIGEN


class StiffnessKind(Choice):
    """One SCF per pose on equation 14 (``paper``), or one factor per joint (``joint``).

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> pp.StiffnessKind.values()
    ('paper', 'joint')
    >>> str(pp.StiffnessKind.JOINT)
    'joint'
    """

    PAPER = "paper"
    JOINT = "joint"


class EigenNorm(Choice):
    """The eigen error per pose: equation 16's l2 norm, or the rms of per-mode relative errors.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> pp.EigenNorm.values()
    ('paper', 'relative')
    """

    PAPER = "paper"
    RELATIVE = "relative"


class DeflectionNorm(Choice):
    """What a tip error is divided by: the truth tip position (equation 19) or its displacement.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> pp.DeflectionNorm.values()
    ('position', 'displacement')
    """

    POSITION = "position"
    DISPLACEMENT = "displacement"


class Axes(Choice):
    """The joint axes at each node of the chain (``--axes``).

    ``y``: bending out of the plane only (the planar chain); ``xy`` adds torsion about the link
    axis x; ``yz`` adds bending in the plane (about z); ``xyz`` all three.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> pp.Axes("xyz").joint_order
    ('y', 'z', 'x')
    >>> pp.Axes.Y.spatial, pp.Axes.XY.spatial
    (False, True)
    """

    Y = "y"
    XY = "xy"
    YZ = "yz"
    XYZ = "xyz"

    @property
    def joint_order(self) -> tuple[str, ...]:
        """The revolute joints at one node, root side first: y, then z, then x (those present).

        Bending about y comes first so that ``y`` is the planar chain; the torsion joint comes
        last, so it turns the link about its own (bent) axis.
        """
        return tuple(a for a in ("y", "z", "x") if a in self.value)

    @property
    def spatial(self) -> bool:
        """Whether the chain has any axis beside y."""
        return self is not Axes.Y


# the named points on the tip link (chain/points.py): the tip centre and its two corners
POINT_NAMES = ("tip", "tip_corner_left", "tip_corner_right")


class UniqueRule(Choice):
    """Which model a fit returns: a multistart's best (``none``) or the rule's (``nearest``).

    ``nearest`` is one model per design, smooth in it (``fitting/unique.py`` states the rule).
    """

    NONE = "none"
    NEAREST = "nearest"


OBJECTIVES = Objective.values()
AXES = Axes.values()
STIFFNESS_KINDS = StiffnessKind.values()
EIGEN_NORMS = EigenNorm.values()
DEFLECTION_NORMS = DeflectionNorm.values()
# the eigen norm of fit and fit_pareto: the relative norm keeps every mode in view and gives
# the better model for dynamics (scripts/dynamic_accuracy.py compares the two; README)
DEFAULT_EIGEN_NORM = EigenNorm.RELATIVE.value
# finite-element truth models (``truth.compute_truth``)
TRUTH_MODELS = ("plate", "plate-morley", "solid", "beam")
# files ``export_model`` writes
FORMATS = ("urdf", "mjcf", "json")
# joint damping an export carries: C = beta K, the per-mode ratios (JSON only), or a diagonal
# joint damping fitted to the per-mode ratios (simulation/modal_fit.py)
EXPORT_DAMPING_FORMS = ("stiffness", "modal", "modal_fit")

# joint damping forms of a simulation (``prbdm_pin.simulation.damping``)
DAMPING_FORMS = ("modal", "eq5c", "stiffness", "modal_fit")
# time integrators: schemes of our own (fixed-step or step-controlled; "compiled" is scipy's
# DOP853 compiled with the chain's dynamics; "auto" picks one per problem), and scipy's
# solve_ivp methods
FIXED_STEP_METHODS = ("auto", "gauss", "exponential", "trapezoidal", "compiled")
IVP_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")

# the pose sweep of Eqs. 10-11: first pose offset and step, rad (the Pareto fit takes the
# paper's finer Pareto step)
XI_RAD = 0.05
EPS_RAD = 0.1
PARETO_EPS_RAD = 0.01
# Eq. 15's lower bound on every link length, a fraction of the beam length
MIN_FRACTION = 0.02

# Shortest link a file may hold, a fraction of the beam length: at 1e-5 L the frequencies of a
# 2R chain still solve to 1e-6 relative; at 1e-6 L cond(K^-1/2 M K^-1/2) passes 1e10.
LINK_FLOOR_FRACTION = 1e-5
