"""Checks of command-line options, run before any work starts.

Each command's ``run()`` starts with these: ranges of numbers (a refusal names the option, the
value and the range), and, from :mod:`prbdm_pin.io.paths` (shared with the public functions
that write), checks that an output folder or file can be written, so that a bad ``--out`` is
refused before minutes of computation rather than after, and nothing is created on refusal.
:class:`CliParser` makes argparse's own errors one line as well.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from collections.abc import Callable

from ..errors import BeamInputError, SolveError, TruthError
from ..options.validate import MAX_SEED, MAX_WORKERS  # shared with the API

__all__ = ["CliParser", "one_line", "in_range", "run_reported", "xyz_option", "MAX_SEED",
           "MAX_WORKERS"]

# Kernel and device trees: writing there fails (or, as root, does harm) after the work is done.

_ARG = re.compile(r"^argument (\S+): (.*)$", re.DOTALL)
# a value that starts like a negative number: -1:0.1, -10,0,0, -.5e3
_DASH_VALUE = re.compile(r"^-\.?\d")


def one_line(text: str) -> str:
    """``text`` with control characters (newlines of a hostile value ...) escaped: one line."""
    return "".join(c if c.isprintable() or c == " " else repr(c)[1:-1] for c in str(text))


class CliParser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line ``PROG: error: MESSAGE`` and exit code 2.

    argparse prints a usage block above the error; the rest of ``prbdm`` reports every refusal
    as one line, so scripts and logs see the same shape for all of them. ``--help`` is unchanged.
    """

    def parse_known_args(self, args=None, namespace=None):  # noqa: D102 - argparse's contract
        args = sys.argv[1:] if args is None else list(args)
        return super().parse_known_args(self._joined_dash_values(args), namespace)

    def _joined_dash_values(self, args: list[str]) -> list[str]:
        """Join ``--opt -1:0.1`` into ``--opt=-1:0.1`` for options that take one value.

        argparse reads a value starting with '-' that is not a plain negative number
        (``-1:0.1``, ``-10,0,0``) as an option and answers "expected one argument"; joined,
        the value reaches the option's own check, which names what is wrong with it.
        """
        out: list[str] = []
        i = 0
        while i < len(args):
            a = args[i]
            if a == "--":
                return out + args[i:]
            action = self._option_string_actions.get(a)
            if (action is not None and action.nargs is None and i + 1 < len(args)
                    and isinstance(args[i + 1], str) and _DASH_VALUE.match(args[i + 1])
                    and args[i + 1] not in self._option_string_actions):
                out.append(f"{a}={args[i + 1]}")
                i += 2
                continue
            out.append(a)
            i += 1
        return out

    def error(self, message: str):  # noqa: D102 - argparse's contract
        m = _ARG.match(message)
        if m:
            option, rest = m.groups()
            message = f"{option}: {rest}"
        self.exit(2, f"{self.prog}: error: {one_line(message)}\n")


def _num(x: float) -> str:
    if x == MAX_SEED:
        return "2**63 - 1"
    return str(x) if isinstance(x, int) else f"{x:g}"


def _bounds_text(lo, hi, lo_open, hi_open, integer) -> str:
    kind = "an integer" if integer else "a finite number"
    if integer and lo is not None and hi is not None and not (lo_open or hi_open):
        return f"must be {kind} in {lo}..{hi}"
    parts = []
    if lo is not None:
        parts.append(f"{'>' if lo_open else '>='} {_num(lo)}")
    if hi is not None:
        parts.append(f"{'<' if hi_open else '<='} {_num(hi)}")
    return f"must be {kind}" + (" " + " and ".join(parts) if parts else "")


def in_range(field: str, value: object, lo: float | None = None, hi: float | None = None, *,
             lo_open: bool = False, hi_open: bool = False, integer: bool = False,
             unit: str = "", why: str = "") -> None:
    """Refuse a number outside ``[lo, hi]``, a non-finite one, and a non-integer if asked.

    ``lo_open``/``hi_open`` exclude an end; None: no bound on that side; ``integer`` refuses a
    non-integer.

    Raises
    ------
    BeamInputError
        ``"--pop = 1: must be an integer >= 4"``: the option, the value, the range (``unit``
        and ``why`` appended).
    """
    want = _bounds_text(lo, hi, lo_open, hi_open, integer)
    want += f" ({unit})" if unit else ""
    want += f": {why}" if why else ""
    if value is None:
        return
    if integer:
        ok = isinstance(value, int) and not isinstance(value, bool)
    else:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool) \
            and math.isfinite(value)
    if ok and lo is not None:
        ok = value > lo if lo_open else value >= lo
    if ok and hi is not None:
        ok = value < hi if hi_open else value <= hi
    if not ok:
        raise BeamInputError(f"{field} = {value!r}: {want}")


def run_reported(prog: str, call: Callable[[], int | None]) -> int:
    """Run ``call()`` and turn the package's errors into one line on stderr and an exit code.

    Shared by ``prbdm`` and the example scripts, so that both report alike.

    Parameters
    ----------
    prog : str
        The program named in the message (``"prbdm fit"``, ``"first_fit.py"``).
    call : callable
        The work; its return value (None: 0) is the exit code.

    Returns
    -------
    int
        ``call``'s code, 2 for bad input (BeamInputError), 1 for a solve that failed
        (SolveError, TruthError), 130 on Ctrl-C.
    """
    try:
        return int(call() or 0)
    except BeamInputError as exc:
        print(f"{prog}: error: {one_line(exc)}", file=sys.stderr)
        return 2
    except (SolveError, TruthError) as exc:
        print(f"{prog}: failed: {one_line(exc)}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130



def modal_damping_option(given: float | None, source, form: str, support: bool):
    """Return the damping ratio a plant command runs with: ``given``, or the model file's.

    A model JSON that records one ratio per mode in the modal form (a calibration's, ``prbdm
    calibrate``) gives those (an array, mode 1 first) when the option was not given, the form
    is ``"modal"`` or ``"modal_fit"`` (the diagonal damping fitted to them, what an MJCF or URDF
    export of the model carries) and no support was added (a hub or bus changes the modes);
    else ``given`` (default 0.02).
    """
    z = getattr(source, "modal_damping_ratio", None)
    if given is None and z is not None and form in ("modal", "modal_fit") and not support:
        return z
    return 0.02 if given is None else given


def gravity_option(text: str | None, source, bus: bool = False) -> list[float]:
    """Return ``--gravity`` (m/s^2, world), or the gravity ``source``'s model was fitted in.

    ``text`` None (the option not given): the model file's recorded gravity (a fit in gravity
    has its springs fitted about the sag, so it runs in that gravity unless told otherwise),
    none for a model fitted without one or put on a free bus (``bus``).
    """
    if text is not None:
        return xyz_option(text, "--gravity", "m/s^2")
    g = getattr(source, "gravity_m_s2", None)
    return [0.0, 0.0, 0.0] if g is None or bus else [float(x) for x in g]


def xyz_option(text: str, option: str, unit: str) -> list[float]:
    """Return ``"X,Y,Z"`` as three finite floats; BeamInputError naming ``option`` otherwise."""
    parts = text.split(",")
    try:
        v = [float(s) for s in parts]
    except ValueError:
        v = []
    if len(v) != 3 or not all(math.isfinite(x) for x in v):
        raise BeamInputError(f"{option} = {text!r}: must be three numbers X,Y,Z ({unit})")
    return v
