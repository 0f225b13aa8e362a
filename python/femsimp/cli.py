"""`python3 -m femsimp simplify IN OUT --server HOST:PORT [options]`, with the C++ CLI's flag
names (`--tolerance-relative 0.005`), for any format meshio reads and writes; `jobs`, `cancel`,
`options`. Exit codes are the C++ CLI's (client/exit_codes.h): 2 usage, 3 input unreadable,
4 input invalid, 5 output failed, 20 + the gRPC code for a failed call.
"""
import argparse
import sys
import warnings

from . import options as opts
from .errors import FemsimpError, FemsimpWarning, MeshError, OptionError

EXIT_USAGE, EXIT_INPUT_UNREADABLE, EXIT_INPUT_INVALID, EXIT_OUTPUT_FAILED = 2, 3, 4, 5


# Control characters (but newline and tab) as \xNN, as the C++ CLI shows them (common/escape.h).
_CONTROL = {c: f"\\x{c:02x}" for c in [*range(0x20), 0x7f] if chr(c) not in "\n\t"}


def _say(text, file=None):
    """print, with control characters escaped: a label, a file name or a server message (which
    may quote a client's strings) never reaches the terminal as an escape sequence."""
    print(str(text).translate(_CONTROL), file=file or sys.stdout)


def _add_server_flags(p):
    p.add_argument("--server", required=True, metavar="HOST:PORT", help="the femsimp-server")
    p.add_argument("--token", help="sent as 'authorization: Bearer TOKEN'")
    p.add_argument("--tls", nargs="?", const=True, metavar="CA_PEM",
                   help="TLS, with the system's roots or the given root certificate")


def _parser():
    p = argparse.ArgumentParser(prog="python3 -m femsimp",
                                description="femsimp's Python client (femsimp-server via gRPC).")
    sub = p.add_subparsers(dest="command", required=True)
    s = sub.add_parser("simplify", help="simplify IN into OUT on a server",
                       description="Simplifies the surface triangles of IN on a femsimp-server "
                       "and writes OUT (any format meshio reads/writes), groups and fields kept.")
    s.add_argument("input", metavar="IN")
    s.add_argument("output", metavar="OUT")
    _add_server_flags(s)
    engine = s.add_argument_group("engine options (femsimp options: ranges and defaults)")
    for o in opts.OPTIONS.values():
        if not o.flag:
            continue
        text = o.help + (f"; {o.range_text()}" if o.range_text() else "") + \
            f"; default {o.default_text}"
        text = text.replace("%", "%%")
        if o.kind == "bool":
            engine.add_argument(o.flag, dest=o.path, action="store_true", default=None, help=text)
        else:
            metavar = "|".join(c[1] for c in o.choices) if o.kind == "enum" else o.metavar
            engine.add_argument(o.flag, dest=o.path, metavar=metavar, help=text)
    s.add_argument("--strict", action="store_true",
                   help="refuse cells and data femsimp does not simplify (lines, points, volume "
                   "cells...) instead of leaving them out with a warning")
    s.add_argument("--deadline", type=float, metavar="SECONDS", help="give up after SECONDS")
    s.add_argument("--label", help="a label for the job in the server's list and logs")
    s.add_argument("--max-attempts", type=int, default=5, metavar="N",
                   help="calls per job: UNAVAILABLE and RESOURCE_EXHAUSTED with a pushback are "
                   "retried (default 5)")
    s.add_argument("--quiet", action="store_true", help="no progress, summary only")
    j = sub.add_parser("jobs", help="list the server's jobs")
    _add_server_flags(j)
    c = sub.add_parser("cancel", help="cancel a job")
    c.add_argument("job_id")
    _add_server_flags(c)
    sub.add_parser("options", help="every engine option: keyword, flag, range, default")
    return p


def _client(a, **kw):
    from .client import Client
    return Client(a.server, token=a.token, tls=a.tls, **kw)


def _simplify(a):
    given = {o.path: getattr(a, o.path) for o in opts.OPTIONS.values()
             if o.flag and getattr(a, o.path) is not None}
    try:
        for path, value in given.items():
            opts.OPTIONS[path].check(value, opts.OPTIONS[path].flag)
        checked = opts.check(given)
    except OptionError as e:
        _say(f"femsimp: {e}", file=sys.stderr)
        return EXIT_USAGE
    if a.deadline is not None and not a.deadline > 0:
        _say(f"femsimp: --deadline = {a.deadline} is out of range: must be > 0 seconds",
              file=sys.stderr)
        return EXIT_USAGE
    if a.max_attempts < 1 or a.max_attempts > 100:
        _say(f"femsimp: --max-attempts = {a.max_attempts} is out of range: must be in [1, 100]",
              file=sys.stderr)
        return EXIT_USAGE
    client = _client(a, max_attempts=a.max_attempts, progress_bar=False if a.quiet else None)
    with warnings.catch_warnings():
        warnings.simplefilter("always", FemsimpWarning)
        warnings.showwarning = lambda m, *r: _say(f"femsimp: warning: {m}", file=sys.stderr)
        try:
            out = client.run(a.input, output=a.output, strict=a.strict, deadline=a.deadline,
                             label=a.label, **checked)
        except FileNotFoundError as e:
            _say(f"femsimp: {e}", file=sys.stderr)
            return EXIT_INPUT_UNREADABLE
        except MeshError as e:
            unreadable = "cannot read it" in str(e)
            _say(f"femsimp: {a.input}: {e}" if not unreadable else f"femsimp: {e}",
                  file=sys.stderr)
            return EXIT_INPUT_UNREADABLE if unreadable else EXIT_INPUT_INVALID
        except FemsimpError as e:
            _say(f"femsimp: {e}", file=sys.stderr)
            if e.pushback_ms is not None and e.pushback_ms >= 0:
                _say(f"femsimp: the server suggests retrying after {e.pushback_ms} ms",
                      file=sys.stderr)
            return e.exit_code
        except OSError as e:
            _say(f"femsimp: {a.output}: cannot write it: {e}", file=sys.stderr)
            return EXIT_OUTPUT_FAILED
        except KeyboardInterrupt:  # the call was cancelled, so the server stops the job
            _say("femsimp: interrupted; the job was cancelled", file=sys.stderr)
            return 20 + 1  # CANCELLED, as the C++ client
        finally:
            client.close()
    r = out.result
    _say(f"{a.input} -> {a.output}: {r.input_vertices} -> {r.output_vertices} vertices, "
          f"{r.input_faces} -> {r.output_faces} faces in {r.passes} passes, stop {r.stop_reason}"
          + (f" ({r.limiting_rule})" if r.limiting_rule else "")
          + f"; engine {r.engine_seconds:.3f} s, job {out.job_id}, {out.attempts} attempt(s)")
    return 0


def main(argv=None):
    """Runs the command line; returns the exit code."""
    p = _parser()
    try:
        a = p.parse_args(argv)
    except SystemExit as e:
        return e.code if isinstance(e.code, int) else EXIT_USAGE
    if a.command == "options":
        _say(opts.table_text())
        return 0
    if a.command == "simplify":
        return _simplify(a)
    try:
        with _client(a) as client:
            if a.command == "jobs":
                for j in client.jobs():
                    _say(f"{j.job_id} {j.state:9} {j.passes_done:4} passes {j.input_faces:>10} "
                          f"faces {j.status_code:12} {j.label}")
            else:
                _say(f"{a.job_id}: was {client.cancel(a.job_id)}")
    except FemsimpError as e:
        _say(f"femsimp: {e}", file=sys.stderr)
        return e.exit_code
    return 0
