"""The Python option table is the engine's, and options are checked before any upload."""
import os
import subprocess
import sys

import pytest

from conftest import REPO, required_env
import femsimp
from femsimp import options


def test_table_is_the_engines():
    """The committed table is what `femsimp options --markdown` and the proto generate."""
    cli = required_env("FEMSIMP_CLI_BIN")
    done = subprocess.run([sys.executable, os.path.join(REPO, "scripts", "gen_python_options.py"),
                           cli, "--check"], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": os.path.join(REPO, "python")})
    assert done.returncode == 0, done.stderr


def test_names_defaults_ranges():
    o = femsimp.OPTIONS
    assert o["tolerance_relative"].default == 0.005
    assert o["tolerance_relative"].flag == "--tolerance-relative"
    assert o["min_angle_deg"].range_text() == "in [0, 60) degrees"
    assert o["cell.spes"].keyword == "cell_spes" and o["cell.spes"].kind == "int"
    assert o["cost"].default == "deviation"


def test_unknown_option_raises_before_any_connection():
    # Nothing listens on port 1: an upload would end UNAVAILABLE, not OptionError.
    with femsimp.Client("127.0.0.1:1", max_attempts=1) as c:
        with pytest.raises(femsimp.OptionError, match="unknown option 'tolerance_rel'.*"
                           "tolerance_relative"):
            c.simplify(([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]), tolerance_rel=0.01)


@pytest.mark.parametrize("name,value,message", [
    ("min_angle_deg", 75, "min_angle_deg = 75 is out of range: must be in [0, 60) degrees"),
    ("tolerance_relative", "200%", "tolerance_relative = 2 is out of range"),
    ("cost", "fast", "cost: 'fast' is not one of gaussian, quadric"),
    ("max_passes", 2.5, "max_passes: '2.5' is not an integer"),
    ("threads", 0, "threads = 0 is out of range: must be in [1, 1024]"),
])
def test_bad_values(name, value, message):
    with pytest.raises(femsimp.OptionError) as e:
        options.check({name: value})
    assert message in str(e.value)


def test_both_targets_refused():
    with pytest.raises(femsimp.OptionError, match="one target"):
        options.check({"ratio": 0.5, "target_vertices": 10})


def test_every_option_reaches_its_proto_field():
    pb2, _ = femsimp.stubs()
    for o in femsimp.OPTIONS.values():
        if o.kind == "enum":
            value = o.choices[-1][1]
        elif o.kind == "bool":
            value = not o.default
        elif o.hi is not None and o.lo is not None:
            value = o.hi if o.hi_closed else (o.lo + o.hi) / 2
            value = int(value) if o.kind == "int" else value
        else:
            value = (o.lo or 0) + 1
        msg = options.to_proto(options.check({o.path: value}), pb2.EngineOptions())
        *groups, name = o.path.split(".")
        for g in groups:
            msg = getattr(msg, g)
        got = getattr(msg, name)
        if o.kind == "enum":
            enum = msg.DESCRIPTOR.fields_by_name[name].enum_type
            assert enum.values_by_number[got].name == o.choices[-1][2], o.path
        else:
            assert got == value, o.path
