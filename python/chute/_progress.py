"""A text progress bar on sys.stderr for `chute.run(..., progress=True)` and
`chute.study(..., progress=True)`: one line redrawn
with a carriage return, so it works in a terminal and in a notebook alike."""

import sys
import time

__all__ = ["ProgressBar", "cases_label", "time_label"]


def time_label(t, duration):
    """A run's progress: simulated time of the duration (s)."""
    return f"t = {t:.3f} / {duration:g} s"


def cases_label(finished, total):
    """A study's progress: cases ended of those to run."""
    return f"{finished} / {total} cases"


class ProgressBar:
    """Called with how far the work is and where it ends (by default the simulated time and
    the duration of a run, in s) while it goes on; ``label`` words the two numbers."""

    WIDTH = 30

    def __init__(self, stream=None, label=time_label):
        self.stream = stream if stream is not None else sys.stderr
        self.label = label
        self.start = time.monotonic()
        self.drawn = False

    def __call__(self, done, total):
        frac = min(max(done / total, 0.0), 1.0) if total > 0 else 1.0
        filled = int(round(frac * self.WIDTH))
        elapsed = time.monotonic() - self.start
        eta = f", {elapsed * (1 - frac) / frac:.0f} s left" if frac > 0 else ""
        bar = "#" * filled + "-" * (self.WIDTH - filled)
        self.stream.write(
            f"\r[{bar}] {100 * frac:3.0f}%  {self.label(done, total)}  "
            f"({elapsed:.0f} s{eta})   "
        )
        self.stream.flush()
        self.drawn = True

    def close(self):
        """End the line the bar is drawn on (if it was drawn)."""
        if self.drawn:
            self.stream.write("\n")
            self.stream.flush()
