"""The progress line (python/femsimp/progress.py): a bar toward a target, none without one (a
tolerance run ends when its passes stop removing, which nothing tells in advance)."""
import io
from types import SimpleNamespace

from femsimp.progress import ProgressBar


def _pass(number, vertices_left):
    return SimpleNamespace(number=number, vertices_left=vertices_left, removed=10, tried=20,
                           rejections={"min_angle": 4}, seconds=0.5)


def test_bar_measures_the_way_to_the_target():
    bar = ProgressBar(1000, ratio=0.1)
    half = bar.text(_pass(3, 550))  # 450 of the 900 to remove
    assert half.startswith("[" + "#" * 15 + "." * 15 + "]  50% pass 3: 550 vertices"), half
    assert bar.text(_pass(9, 80)).startswith("[" + "#" * 30 + "] 100% "), "clamped at the end"


def test_no_bar_without_a_target():
    for bar in (ProgressBar(1000), ProgressBar(1000, target_vertices=1000)):
        line = bar.text(_pass(250, 400))
        assert line.startswith("pass 250: 400 vertices, -10, tried 20, rejected 4"), line
        assert "%" not in line and "[" not in line


def test_update_redraws_one_line():
    out = io.StringIO()
    bar = ProgressBar(1000, target_vertices=100, stream=out)
    bar.update(_pass(1, 900))
    bar.update(_pass(2, 100))
    assert out.getvalue().count("\r") == 2 and "\n" not in out.getvalue()
