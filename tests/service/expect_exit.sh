#!/bin/sh
# expect_exit.sh CODE COMMAND...: runs COMMAND, passes when it exits with CODE.
want=$1
shift
"$@"
got=$?
if [ "$got" -ne "$want" ]; then
  echo "expected exit code $want, got $got: $*" >&2
  exit 1
fi
