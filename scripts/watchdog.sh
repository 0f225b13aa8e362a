#!/usr/bin/env bash
# watchdog.sh SECONDS COMMAND [ARGS...]: runs COMMAND; if it is still running after SECONDS,
# prints every thread's stack (gdb, when installed) to stderr, kills it and exits 124. The
# engine and cellsim tests run under it (tests/engine/CMakeLists.txt), so that a hang in CI
# leaves the evidence needed to find it instead of only a timeout.
set -u
limit=$1
shift
"$@" &
pid=$!
tenths=0
while kill -0 "$pid" 2>/dev/null; do
  if [ "$tenths" -ge "$((limit * 10))" ]; then
    echo "watchdog: '$*' still running after ${limit} s; its threads:" >&2
    if command -v gdb > /dev/null; then
      gdb -batch -p "$pid" -ex "thread apply all bt" 2>&1 | grep -E "^(Thread|#)" >&2
    else
      echo "watchdog: (no gdb to print the stacks)" >&2
    fi
    kill -9 "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    exit 124
  fi
  sleep 0.1
  tenths=$((tenths + 1))
done
wait "$pid"
