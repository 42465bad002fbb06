"""``python -m fricgen``: the fricgen command."""
import sys

from .cli import main

sys.exit(main())
