"""`python -m btnav.cli ...`: the same command line as `btnav ...`."""

import sys

from . import main

if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
