"""`python -m numerics SUBCOMMAND`: see ``numerics.cli``."""

import sys

from .cli import main

sys.exit(main())
