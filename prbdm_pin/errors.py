"""Exceptions raised by prbdm_pin.

They subclass builtins so that callers who catch ``ValueError``, ``TypeError`` or
``RuntimeError`` keep working.
"""


class BeamInputError(ValueError):
    """Invalid user input; the message names the offending field and its value.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> pp.Material(E_Pa=-1.0)
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: material.E = -1.0: must be a finite number > 0 (Pa)
    >>> issubclass(pp.BeamInputError, ValueError)
    True
    """


class InputTypeError(BeamInputError, TypeError):
    """An argument or field of the wrong type; the message names it and the type it needs.

    A ``TypeError``, and a :class:`BeamInputError` too, so that the command line and every
    handler of bad input report it alike (one line, exit code 2).

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> pp.Material(E_Pa="205e9")
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.InputTypeError: material.E = '205e9': must be a finite number > 0 (Pa)
    >>> issubclass(pp.InputTypeError, TypeError), issubclass(pp.InputTypeError, ValueError)
    (True, True)
    """


class SolveError(RuntimeError):
    """A numerical solve did not converge or produced a result that cannot be trusted.

    Examples
    --------
    A load far beyond what double precision resolves, on a 2R chain of a 1 m steel strip:

    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> pp.statics(model, tip_force_N=[0.0, 0.0, -1e12])
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.SolveError: tip_force = [0.0, 0.0, -1000000000000.0] N: load index ...
    >>> issubclass(pp.SolveError, RuntimeError)
    True
    """


class TruthError(RuntimeError):
    """The finite-element truth refused to return results it cannot trust.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> issubclass(pp.TruthError, RuntimeError)
    True
    """
