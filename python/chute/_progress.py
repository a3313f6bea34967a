"""A text progress bar on sys.stderr for `chute.run(..., progress=True)`: one line redrawn
with a carriage return, so it works in a terminal and in a notebook alike."""

import sys
import time

__all__ = ["ProgressBar"]


class ProgressBar:
    """Called with the simulated time and the duration (s) while a run goes on."""

    WIDTH = 30

    def __init__(self, stream=None):
        self.stream = stream if stream is not None else sys.stderr
        self.start = time.monotonic()
        self.drawn = False

    def __call__(self, t, duration):
        frac = min(max(t / duration, 0.0), 1.0) if duration > 0 else 1.0
        filled = int(round(frac * self.WIDTH))
        elapsed = time.monotonic() - self.start
        eta = f", {elapsed * (1 - frac) / frac:.0f} s left" if frac > 0 else ""
        bar = "#" * filled + "-" * (self.WIDTH - filled)
        self.stream.write(
            f"\r[{bar}] {100 * frac:3.0f}%  t = {t:.3f} / {duration:g} s  "
            f"({elapsed:.0f} s{eta})   "
        )
        self.stream.flush()
        self.drawn = True

    def close(self):
        """End the line the bar is drawn on (if it was drawn)."""
        if self.drawn:
            self.stream.write("\n")
            self.stream.flush()
