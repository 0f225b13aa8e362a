"""The progress bar a terminal shows per pass (client/remote_run.cc ProgressBar, on stderr)."""
import sys


class ProgressBar:
    """One line redrawn in place: a bar toward the target, then the figures of the last pass. A
    run without a target ends when its passes stop removing, which nothing tells in advance:
    no bar."""

    WIDTH = 30

    def __init__(self, input_vertices, ratio=0.0, target_vertices=0, stream=None):
        self.input = input_vertices
        self.target = int(target_vertices or ratio * input_vertices)
        self.stream = stream or sys.stderr
        self.drawn = False

    def text(self, p):
        """The line for Pass p."""
        bar = ""
        if 0 < self.target < self.input:
            fraction = (self.input - min(self.input, p.vertices_left)) / (self.input - self.target)
            fraction = min(1.0, max(0.0, fraction))
            filled = int(fraction * self.WIDTH + 0.5)
            bar = f"[{'#' * filled}{'.' * (self.WIDTH - filled)}] {100 * fraction:3.0f}% "
        return (f"{bar}pass {p.number}: {p.vertices_left} vertices, -{p.removed}, tried {p.tried}, "
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
