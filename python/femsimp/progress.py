"""The progress bar a terminal shows per pass (client/remote_run.cc ProgressBar, on stderr)."""
import sys


class ProgressBar:
    """One line redrawn in place: a bar toward the target (or the pass limit), then the figures
    of the last pass."""

    WIDTH = 30

    def __init__(self, input_vertices, ratio=0.0, target_vertices=0, max_passes=100,
                 stream=None):
        self.input = input_vertices
        self.target = int(target_vertices or ratio * input_vertices)
        self.max_passes = max_passes
        self.stream = stream or sys.stderr
        self.drawn = False

    def text(self, p):
        """The line for Pass p."""
        if 0 < self.target < self.input:
            fraction = (self.input - min(self.input, p.vertices_left)) / (self.input - self.target)
        else:
            fraction = p.number / self.max_passes
        fraction = min(1.0, max(0.0, fraction))
        filled = int(fraction * self.WIDTH + 0.5)
        return (f"[{'#' * filled}{'.' * (self.WIDTH - filled)}] {100 * fraction:3.0f}% "
                f"pass {p.number}: {p.vertices_left} vertices, -{p.removed}, tried {p.tried}, "
                f"rejected {sum(p.rejections.values())}, {p.seconds:.3f} s")

    def update(self, p):
        """Redraws the line for Pass p."""
        self.stream.write("\r" + self.text(p) + "\x1b[K")
        self.stream.flush()
        self.drawn = True

    def note(self, line):
        """A line of its own (queue position, a retry) without breaking the bar."""
        self.close()
        self.stream.write(line + "\n")
        self.stream.flush()

    def close(self):
        """Ends the line, if one was drawn."""
        if self.drawn:
            self.stream.write("\n")
            self.stream.flush()
            self.drawn = False
