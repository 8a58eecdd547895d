"""Progress on stderr: on a terminal, one line redrawn with carriage returns per phase
("summary   3/6 [#####.....] 2.1 s"); otherwise one line per completed phase; nothing with
--quiet."""

import sys
import time

BAR_WIDTH = 24


class Progress:
    def __init__(self, quiet, stream=None):
        self.stream = stream or sys.stderr
        self.enabled = not quiet
        try:
            self.tty = self.enabled and self.stream.isatty()
        except (AttributeError, ValueError):
            self.tty = False
        self.phase = None
        self.total = 0
        self.done = 0
        self.started = 0.0
        self.width = 0

    def start(self, phase, total):
        self.phase, self.total, self.done = phase, total, 0
        self.started = time.monotonic()
        self._draw()

    def advance(self, note=""):
        self.done += 1
        self._draw(note)

    def _line(self, note=""):
        filled = BAR_WIDTH * self.done // max(self.total, 1)
        bar = "#" * filled + "." * (BAR_WIDTH - filled)
        elapsed = time.monotonic() - self.started
        text = f"{self.phase:<11} {self.done}/{self.total} [{bar}] {elapsed:.1f} s"
        return text + (f"  {note}" if note else "")

    def _draw(self, note=""):
        if not self.tty:
            return
        line = self._line(note)
        padding = " " * max(self.width - len(line), 0)
        self.width = len(line)
        self.stream.write("\r" + line + padding)
        self.stream.flush()

    def finish(self, summary=""):
        """Ends the phase: the bar's last state stays on its line (terminal), or one line."""
        if not self.enabled or self.phase is None:
            return
        if self.tty:
            self._draw(summary)
            self.stream.write("\n")
        else:
            elapsed = time.monotonic() - self.started
            text = f"{self.phase} {self.done}/{self.total} done in {elapsed:.1f} s"
            self.stream.write(text + (f" ({summary})" if summary else "") + "\n")
        self.stream.flush()
        self.phase = None
        self.width = 0

    def abandon(self):
        """Ends a bar left mid-line (before an error message)."""
        if self.tty and self.phase is not None:
            self.stream.write("\n")
            self.stream.flush()
        self.phase = None
        self.width = 0

    def message(self, text):
        if self.enabled:
            self.abandon()
            self.stream.write(text + "\n")
            self.stream.flush()
