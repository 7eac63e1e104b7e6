"""Allow ``python -m whipple``."""

import sys

from whipple.cli import main

sys.exit(main())
