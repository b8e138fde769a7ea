#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# strata-view's --no-fill-classes: listed in --help, bad lists refused with exit 2 and
# a message naming the option and the value (before any file is opened).
# usage: check_view_no_fill.sh BUILD_DIR
set -euo pipefail
view="$1/src/strata-view"
# Read all of --help first: grep -q stops at the first match and, under pipefail, the
# viewer's SIGPIPE would fail the line (it did in the sanitizer build).
help=$("$view" --help)
grep -q -- '--no-fill-classes LIST' <<<"$help" || { echo "not in --help" >&2; exit 1; }
for bad in '3,x' '300' '5-3' ''; do
    set +e
    msg=$("$view" /nonexistent.strata --headless --out /dev/null --no-fill-classes "$bad" 2>&1)
    rc=$?
    set -e
    [ $rc = 2 ] || { echo "'$bad': exit $rc, want 2" >&2; exit 1; }
    grep -q -- "--no-fill-classes.*'$bad'" <<<"$msg" || { echo "'$bad': $msg" >&2; exit 1; }
done
echo "ok"
