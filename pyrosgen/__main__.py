"""``python -m pyrosgen``: the same as the ``pyrosgen`` command."""

import sys

from .cli import main

sys.exit(main())
