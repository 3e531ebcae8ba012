"""``python -m pfeie``: the command line (see :mod:`pfeie.cli`)."""

import sys

from .cli import main

sys.exit(main())
