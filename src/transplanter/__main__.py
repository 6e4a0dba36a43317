"""``python -m transplanter`` is the ``transplanter`` command."""

import sys

from transplanter.app.cli import main

sys.exit(main())
