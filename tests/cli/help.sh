#!/usr/bin/env bash
# Every subcommand has --help that exits 0; an unknown option exits 2 with a message.
set -eu
cdbench=$1
"$cdbench" --help | grep -q "check"
"$cdbench" check --help | grep -q -- "--tolerance"
"$cdbench" wrap --help | grep -q -- "--alpha"
set +e
"$cdbench" check --no-such-option x.off > /dev/null 2>&1
rc=$?
set -e
[ "$rc" -eq 2 ] || { echo "unknown option gave exit $rc"; exit 1; }
"$cdbench" check /nonexistent.off 2>&1 | grep -q "no such file"
"$cdbench" subdivide --help | grep -q -- "--steps"
echo "help: ok"
