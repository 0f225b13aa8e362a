"""The engine's options in Python: the same names, defaults and ranges as the C++ option table
(engine/option_table.cc), from the generated _option_table.py. Values are checked here, before
any upload, with the C++ messages ("min_angle_deg = 75 is out of range: must be in [0, 60)
degrees"), then set on the proto's EngineOptions by field name.
"""
import difflib
import math
from dataclasses import dataclass, field

from ._option_markdown import format_number, range_words
from ._option_table import ROWS
from .errors import OptionError


@dataclass(frozen=True)
class Option:
    """One row of the engine's option table."""
    path: str            # proto/JSON name; "cell.spes" for the CellOptions ones
    flag: str            # the CLI flag ("--tolerance-relative"), or None
    metavar: str
    kind: str            # real, int, bool or enum
    choices: list = field(default_factory=list)  # enum: [name, cli name, proto enum value]
    lo: float = None
    hi: float = None
    lo_closed: bool = False
    hi_closed: bool = False
    unit: str = ""
    zero_means: str = ""  # 0 is allowed besides the range, meaning this ("off", "none")
    default: object = None
    default_text: str = ""
    help: str = ""
    percent: bool = False  # a fraction that also takes "0.5%"

    @property
    def keyword(self):
        """The Python keyword: the path with '.' as '_' (cell.spes -> cell_spes)."""
        return self.path.replace(".", "_")

    def range_text(self):
        """The range in the table's words, e.g. 'in (0, 180] degrees'; '' for bool and enum."""
        return range_words(vars(self)) if self.kind in ("real", "int") else ""

    def check(self, value, name=None):
        """The value as its kind (an enum as its choice name), or OptionError naming it."""
        name = name or self.path
        if self.kind == "bool":
            if isinstance(value, bool):
                return value
            if isinstance(value, str) and value.lower() in ("on", "off", "true", "false"):
                return value.lower() in ("on", "true")
            raise OptionError(f"{name} = {value!r} is not a bool (True/False, on/off)")
        if self.kind == "enum":
            for choice in self.choices:
                if value in choice[:2]:
                    return choice[0]
            shown = ", ".join(c[1] for c in self.choices)
            raise OptionError(f"{name}: '{value}' is not one of {shown}")
        number = value
        if isinstance(value, str):
            text = value.strip()
            try:
                if self.percent and text.endswith("%"):
                    number = float(text[:-1]) / 100.0
                else:
                    number = float(text) if self.kind == "real" else int(text)
            except ValueError:
                what = "an integer" if self.kind == "int" else (
                    "a finite number or percentage" if self.percent else "a finite number")
                raise OptionError(f"{name}: '{value}' is not {what}") from None
        if isinstance(number, bool) or not isinstance(number, (int, float)):
            try:  # numpy scalars
                number = number.item()
            except AttributeError:
                raise OptionError(f"{name} = {value!r} is not a number") from None
        if not math.isfinite(number):
            raise OptionError(f"{name}: '{value}' is not a finite number")
        if self.kind == "int":
            if number != int(number):
                raise OptionError(f"{name}: '{value}' is not an integer")
            number = int(number)
        else:
            number = float(number)
        if not self._contains(number) and not (number == 0 and self.zero_means):
            raise OptionError(f"{name} = {format_number(number)} is out of range: must be "
                              f"{self.range_text()}")
        return number

    def _contains(self, v):
        if self.lo is not None and (v < self.lo or (v == self.lo and not self.lo_closed)):
            return False
        if self.hi is not None and (v > self.hi or (v == self.hi and not self.hi_closed)):
            return False
        return True


OPTIONS = {row["path"]: Option(**row) for row in ROWS}
_BY_KEYWORD = {o.keyword: o for o in OPTIONS.values()}


def find(name):
    """The option of a proto path ("cell.spes"), keyword ("cell_spes") or flag ("--spes")."""
    o = OPTIONS.get(name) or _BY_KEYWORD.get(name)
    if o is None and name.startswith("--"):
        o = next((x for x in OPTIONS.values() if x.flag == name), None)
    if o is None:
        close = difflib.get_close_matches(name, list(_BY_KEYWORD), n=3)
        hint = f"; did you mean {' or '.join(close)}?" if close else ""
        raise OptionError(f"unknown option '{name}'{hint} (femsimp.OPTIONS lists them)")
    return o


def check(options):
    """Checks keyword options: {path: value}, every value in its kind and range.

    Raises OptionError for an unknown name, a bad value, or both targets (ratio and
    target_vertices) given; rules between options (cell ones with the cell back end, ...) are
    the server's, which answers INVALID_ARGUMENT naming them."""
    out = {}
    for name, value in options.items():
        if value is None:
            continue
        o = find(name)
        out[o.path] = o.check(value, o.keyword)
    if out.get("ratio") and out.get("target_vertices"):
        raise OptionError("ratio and target_vertices are one target: give at most one")
    return out


def to_proto(checked, engine_options):
    """Sets the checked options ({path: value}) on a femsimp.v1.EngineOptions message."""
    for path, value in checked.items():
        o = OPTIONS[path]
        msg = engine_options
        *groups, name = path.split(".")
        for g in groups:
            msg = getattr(msg, g)
        if o.kind == "enum":
            proto_name = next(c[2] for c in o.choices if c[0] == value)
            value = msg.DESCRIPTOR.fields_by_name[name].enum_type.values_by_name[proto_name].number
        setattr(msg, name, value)
    return engine_options


def table_text():
    """Every option: keyword, flag, range and default, one a line (for `python3 -m femsimp
    options`)."""
    lines = []
    for o in OPTIONS.values():
        rng = o.range_text() or ", ".join(c[1] for c in o.choices)
        lines.append(f"{o.keyword:26} {o.flag or '-':26} {rng:50} default {o.default_text}")
    return "\n".join(lines)
