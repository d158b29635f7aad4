"""``python -m pyrosgen``: the same as the ``pyrosgen`` command."""

import sys

from pyrosgen.cli import main

sys.exit(main())
