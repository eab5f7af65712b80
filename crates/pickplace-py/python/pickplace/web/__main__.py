"""`python -m pickplace.web`: the same as `pickplace-view-web`."""

import sys

from . import main

sys.exit(main())
