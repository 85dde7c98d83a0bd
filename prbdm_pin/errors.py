"""Exceptions raised by prbdm_pin.

They subclass builtins so that callers who catch ``ValueError``, ``TypeError`` or
``RuntimeError`` keep working.
"""


class BeamInputError(ValueError):
    """Invalid user input; the message names the offending field and its value."""


class InputTypeError(BeamInputError, TypeError):
    """An argument or field of the wrong type; the message names it and the type it needs.

    A ``TypeError``, and a :class:`BeamInputError` too, so that the command line and every
    handler of bad input report it alike (one line, exit code 2).
    """


class SolveError(RuntimeError):
    """A numerical solve did not converge or produced a result that cannot be trusted."""


class TruthError(RuntimeError):
    """The finite-element truth refused to return results it cannot trust."""
