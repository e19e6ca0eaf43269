"""``python -m prp3``: the command line."""

import sys

from prp3.cli import main

sys.exit(main())
