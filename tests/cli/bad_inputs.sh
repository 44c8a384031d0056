#!/usr/bin/env bash
# Runs `cdbench check` on every file of data/bad/expected.tsv and compares exit code and message.
# A crash (signal, sanitizer report) gives an exit code above 2 and fails the row.
set -u
cdbench=$1
dir=$2
fail=0
n=0
while IFS=$'\t' read -r file code message; do
  case "$file" in "#"*|"") continue ;; esac
  n=$((n + 1))
  out=$("$cdbench" check "$dir/$file" --no-max-penetration 2>&1)
  rc=$?
  if [ "$rc" != "$code" ] || ! grep -qF -- "$message" <<<"$out"; then
    echo "FAIL $file: exit $rc (expected $code), expected message containing '$message'; got:"
    echo "$out" | head -20
    fail=$((fail + 1))
  fi
done < "$dir/expected.tsv"
echo "$((n - fail)) passed, $fail failed"
[ "$fail" -eq 0 ]
