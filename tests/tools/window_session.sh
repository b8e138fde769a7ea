#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Shared by the window tests (sourced, not run): a private Xvfb display, the viewer's
# window, its pixels and waiting for its picture to settle.
# The caller sets $work (a folder for screenshots) and keeps the viewer's pid in $viewer;
# functions set $win (the window id).

# Starts Xvfb on a random display in FIRST..FIRST+399 and exports DISPLAY; on exit the
# viewer (if any) and Xvfb are stopped.
window_session_start() { # FIRST
    local tool
    for tool in Xvfb xdotool xwd; do
        command -v $tool >/dev/null ||
            { echo "$tool is missing (scripts/install-deps.sh installs it)" >&2; exit 1; }
    done
    display=:$(($1 + RANDOM % 400))
    Xvfb "$display" -screen 0 1280x1024x24 -nolisten tcp >/dev/null 2>&1 &
    xvfb=$!
    viewer=
    trap window_session_stop EXIT
    export DISPLAY=$display
    sleep 1
}

window_session_stop() {
    [ -n "${viewer:-}" ] && kill "$viewer" 2>/dev/null || true
    kill "$xvfb" 2>/dev/null || true
}

# Sets $win to the window of process $viewer (waits up to 30 s).
find_window() {
    local i
    for i in $(seq 1 60); do
        win=$(xdotool search --pid "$viewer" 2>/dev/null | head -1 || true)
        [ -n "$win" ] && return 0
        sleep 0.5
    done
    echo "no window appeared" >&2
    [ -f "$work/viewer.log" ] && cat "$work/viewer.log" >&2
    exit 1
}

# The window's pixels (xwd without its header and colour map) into FILE.
window_pixels() { # FILE
    xwd -id "$win" -silent >"$work/shot.xwd"
    python3 - "$work/shot.xwd" "$1" <<'PY'
import struct, sys
d = open(sys.argv[1], "rb").read()
f = struct.unpack(">25I", d[:100])
start = f[0] + f[19] * 12  # header size + colour map entries
open(sys.argv[2], "wb").write(d[start:start + f[12] * f[5]])
PY
}

# Waits until the window's picture is the same three times in a row, 1 s apart (a busy
# machine or the sanitizers can pause the loader for a second); leaves the pixels in
# $work/now.raw.
settle() {
    local previous="" same=0 sum i
    for i in $(seq 1 180); do
        sleep 1
        window_pixels "$work/now.raw"
        sum=$(sha256sum <"$work/now.raw")
        if [ "$sum" = "$previous" ]; then
            same=$((same + 1))
            [ $same -ge 2 ] && return 0
        else
            same=0
        fi
        previous=$sum
    done
    echo "the window never settled" >&2
    exit 1
}
