"""Run the ``prbdm`` command line as ``python -m prbdm_pin``."""

from .cli import main

raise SystemExit(main())
