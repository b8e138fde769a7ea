#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Command-line behaviour every Strata program must have: --help succeeds and prints
# usage; bad options and missing files fail with a message naming the problem.
# usage: check_cli.sh PROGRAM
set -u
prog=$1
name=$(basename "$prog")
fail() { echo "FAIL: $name: $*"; exit 1; }

out=$("$prog" --help) || fail "--help exited $?"
grep -qi "usage" <<<"$out" || fail "--help prints no usage line"

err=$("$prog" --no-such-option 2>&1 >/dev/null); rc=$?
[ $rc -ne 0 ] || fail "an unknown option was accepted"
grep -q -- "--no-such-option" <<<"$err" || fail "unknown option not named: $err"

if [ "$name" = strata-info ]; then
    err=$("$prog" /nonexistent/file.las 2>&1 >/dev/null); rc=$?
    [ $rc -eq 1 ] || fail "missing file: exit $rc, expected 1"
    grep -q "/nonexistent/file.las" <<<"$err" || fail "missing file not named: $err"
fi
echo "ok: $name"
