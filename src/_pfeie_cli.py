"""The ``pfeie`` console script.

A console script imports its function's package first, and ``import pfeie`` loads numpy
and scipy for about half a second before :func:`pfeie.cli.main` installs its handlers of
SIGINT and SIGTERM: Ctrl-C in that moment printed a KeyboardInterrupt traceback. This
module, outside the package, imports it under a handler that ends quietly instead.
"""

from __future__ import annotations

import sys


def main() -> int:
    """Import :mod:`pfeie.cli` and run its ``main``; Ctrl-C during the import exits 130
    with one line and nothing run."""
    try:
        from pfeie.cli import main as cli_main
    except KeyboardInterrupt:
        sys.stderr.write("pfeie: interrupted (SIGINT) while starting; nothing was run\n")
        return 130
    return cli_main()
