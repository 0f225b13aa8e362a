"""`python3 -m femsimp`: the C++ CLI's flag names and exit codes."""
import os
import subprocess
import sys

import meshio
import pytest

from conftest import REPO, sphere_surface


def run(*args):
    return subprocess.run([sys.executable, "-m", "femsimp", *args], capture_output=True,
                          text=True, env={**os.environ, "PYTHONPATH": os.path.join(REPO, "python")})


@pytest.fixture
def sphere_file(tmp_path):
    path = tmp_path / "sphere.vtu"
    meshio.write(path, meshio.Mesh(*[sphere_surface(20)[0]], [("triangle", sphere_surface(20)[1])]))
    return path


def test_simplify_with_cpp_flag_names(server, sphere_file, tmp_path):
    out = tmp_path / "out.ply"
    done = run("simplify", str(sphere_file), str(out), "--server", server.address,
               "--tolerance-relative", "1%", "--ratio", "0.3", "--cost", "quadric", "--quiet",
               "--label", "cli-test")
    assert done.returncode == 0, done.stderr
    assert "stop " in done.stdout and "attempt(s)" in done.stdout
    assert len(meshio.read(out).cells[0].data) < len(sphere_surface(20)[1])
    jobs = run("jobs", "--server", server.address)
    assert jobs.returncode == 0 and "cli-test" in jobs.stdout and "SUCCEEDED" in jobs.stdout


@pytest.mark.parametrize("flags,message", [
    (["--min-angle", "75"], "--min-angle = 75 is out of range: must be in [0, 60) degrees"),
    (["--cost", "fast"], "--cost: 'fast' is not one of gaussian, quadric"),
    (["--bogus"], "unrecognized arguments: --bogus"),
])
def test_usage_errors_exit_2(server, sphere_file, tmp_path, flags, message):
    done = run("simplify", str(sphere_file), str(tmp_path / "o.vtu"), "--server", server.address,
               *flags)
    assert done.returncode == 2 and message in done.stderr


def test_unreadable_input_exits_3(server, tmp_path):
    done = run("simplify", str(tmp_path / "none.vtu"), str(tmp_path / "o.vtu"), "--server",
               server.address)
    assert done.returncode == 3, done.stderr


def test_server_down_exits_34(sphere_file, tmp_path):
    done = run("simplify", str(sphere_file), str(tmp_path / "o.vtu"), "--server", "127.0.0.1:1",
               "--max-attempts", "1")
    assert done.returncode == 34 and "UNAVAILABLE" in done.stderr


def test_options_lists_the_table():
    done = run("options")
    assert done.returncode == 0
    assert "tolerance_relative" in done.stdout and "--tolerance-relative" in done.stdout


def test_outside_text_reaches_the_terminal_escaped(server, sphere_file, tmp_path):
    # A label listed by `jobs` and a file name in an error are shown with their control
    # characters as \xNN (as the C++ CLI does), never as a raw escape sequence (issue 15, item 4).
    out = tmp_path / "out.ply"
    done = run("simplify", str(sphere_file), str(out), "--server", server.address, "--quiet",
               "--label", "evil\x1b[2Jlabel")
    assert done.returncode == 0, done.stderr
    jobs = run("jobs", "--server", server.address)
    assert jobs.returncode == 0, jobs.stderr
    assert "evil\\x1b[2Jlabel" in jobs.stdout, jobs.stdout
    assert "\x1b" not in jobs.stdout
    missing = run("simplify", str(tmp_path / "no\x1b]0;title\x07.vtu"), str(out),
                  "--server", server.address)
    assert missing.returncode == 3, missing.stderr
    assert "no\\x1b]0;title\\x07.vtu" in missing.stderr, missing.stderr
    assert "\x1b" not in missing.stderr and "\x07" not in missing.stderr
