"""Start a command-line child as a terminal would: SIGINT at its default action.

A shell's background job starts with SIGINT ignored, and an ignored signal stays ignored across
exec, so Python then installs no KeyboardInterrupt handler: a test of Ctrl-C run from such a job
would send a signal the child never sees.
"""

import signal


def sigint_default() -> None:
    """Reset SIGINT to its default action (a ``preexec_fn`` for ``subprocess.Popen``)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
