"""``python -m fricgen.cli``: the fricgen command."""
import sys

from . import main

sys.exit(main())
