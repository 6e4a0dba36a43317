"""``python -m transplanter`` is the ``transplanter`` command."""

import sys

from transplanter.cli import main

sys.exit(main())
