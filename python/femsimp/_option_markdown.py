"""Reads the engine's option table as `femsimp options --markdown` prints it (the README's table)
into rows the Python option table is generated from, and renders each row's range back in the
C++ words (common/flags.cc RangeWords) so a row that was not understood is caught.
"""
import math
import re

_RANGE = re.compile(
    r"^(?:in (?P<lo_br>[\[(])(?P<lo>\S+), (?P<hi>\S+)(?P<hi_br>[\])])"
    r"|(?P<op>>=|>|<=|<) (?P<bound>\S+))"
    r"(?: (?P<unit>(?!\(0:).*?))?(?: \(0: (?P<zero>[^)]*)\))?$")


def format_number(v):
    """common/range.cc FormatNumber: integers plainly, others with 10 significant digits."""
    if math.isfinite(v) and v == math.floor(v) and abs(v) < 1e15:
        return "%.0f" % v
    return "%.10g" % v


def range_words(row):
    """The C++ RangeWords of a numeric row: 'in [0, 60) degrees', '>= 0 model units (0: off)'."""
    lo, hi = row["lo"], row["hi"]
    if lo is not None and hi is not None:
        s = "in %s%s, %s%s" % ("[" if row["lo_closed"] else "(", format_number(lo),
                               format_number(hi), "]" if row["hi_closed"] else ")")
    elif lo is not None:
        s = "%s %s" % (">=" if row["lo_closed"] else ">", format_number(lo))
    elif hi is not None:
        s = "%s %s" % ("<=" if row["hi_closed"] else "<", format_number(hi))
    else:
        s = ""
    if row["unit"]:
        s += " " + row["unit"]
    if row["zero_means"]:
        s += " (0: %s)" % row["zero_means"]
    return s


def _cells(line):
    """A markdown row's cells, with '\\|' kept inside a cell."""
    parts = re.split(r"(?<!\\)\|", line.strip())
    return [p.strip().replace("\\|", "|") for p in parts[1:-1]]


def _parse_range(text, where):
    m = _RANGE.match(text)
    if not m:
        raise ValueError(f"{where}: range '{text}' is not in the table's words")
    row = {"lo": None, "hi": None, "lo_closed": False, "hi_closed": False,
           "unit": m.group("unit") or "", "zero_means": m.group("zero") or ""}
    if m.group("lo") is not None:
        row.update(lo=float(m.group("lo")), hi=float(m.group("hi")),
                   lo_closed=m.group("lo_br") == "[", hi_closed=m.group("hi_br") == "]")
    else:
        op, bound = m.group("op"), float(m.group("bound"))
        if op.startswith(">"):
            row.update(lo=bound, lo_closed=op == ">=")
        else:
            row.update(hi=bound, hi_closed=op == "<=")
    return row


def parse(markdown):
    """Rows of the table: path, flag, metavar, choices, range, default text, help, in order.

    The kind (real, int, bool, enum) is left to the caller, who knows the proto field types."""
    lines = [l for l in markdown.splitlines() if l.startswith("|")]
    if len(lines) < 3 or not lines[0].startswith("| option"):
        raise ValueError("not the option table: no '| option ...' header")
    rows = []
    for n, line in enumerate(lines[2:], start=3):
        cells = _cells(line)
        if len(cells) != 5:
            raise ValueError(f"table line {n}: {len(cells)} cells, expected 5: {line}")
        path, flag_cell, range_cell, default_text, help_text = cells
        path = path.strip("`")
        where = f"option {path}"
        row = {"path": path, "flag": None, "metavar": "", "choices": [], "lo": None, "hi": None,
               "lo_closed": False, "hi_closed": False, "unit": "", "zero_means": "",
               "default_text": default_text, "help": help_text}
        if flag_cell != "—":
            flag, _, metavar = flag_cell.strip("`").partition(" ")
            row.update(flag=flag, metavar=metavar)
        if range_cell.startswith("`"):  # enum: the proto/JSON choice names
            names = [c.strip().strip("`") for c in range_cell.split(",")]
            cli = row["metavar"].split("|") if row["metavar"] else names
            if len(cli) != len(names):
                raise ValueError(f"{where}: flag choices {cli} do not match {names}")
            row["choices"] = [[a, b] for a, b in zip(names, cli)]
            row["metavar"] = ""
        elif range_cell:
            row.update(_parse_range(range_cell, where))
            if range_words(row) != range_cell:
                raise ValueError(f"{where}: range '{range_cell}' renders back as "
                                 f"'{range_words(row)}'")
        rows.append(row)
    return rows
