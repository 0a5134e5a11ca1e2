"""``python -m parcover``: the command line."""

import sys

from parcover.cli import main

sys.exit(main())
