"""Progress of long library steps, passed to a callback (the CLI's ``say``); never printed here."""
from __future__ import annotations

import time
from typing import Callable, Optional

#: A step reports its progress once it has run this long (s), and then at most this often.
PROGRESS_SECONDS = 2.0


class Progress:
    """Hands ``report`` (a callable taking one line, or None for silence) the lines of a step,
    the first once the step has run ``PROGRESS_SECONDS`` and then at most that often, so that
    quick runs stay silent. Each line ends with the seconds since the step began."""

    def __init__(self, report: Optional[Callable[[str], None]]):
        self.report = report
        self.start = self.last = time.perf_counter()

    def __call__(self, line: str) -> None:
        now = time.perf_counter()
        if self.report is not None and now - self.last >= PROGRESS_SECONDS:
            self.report(f"{line} ({now - self.start:.0f} s)")
            self.last = now
