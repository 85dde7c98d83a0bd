"""Exceptions raised by prbdm_pin.

They subclass builtins so that callers who catch ``ValueError`` or ``RuntimeError`` keep working.
"""


class BeamInputError(ValueError):
    """Invalid user input; the message names the offending field and its value."""


class SolveError(RuntimeError):
    """A numerical solve did not converge or produced a result that cannot be trusted."""


class TruthError(RuntimeError):
    """The finite-element truth refused to return results it cannot trust."""
