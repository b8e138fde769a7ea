#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Shared by the window tests (sourced, not run): a private Xvfb display, the viewer's
# window, its pixels and waiting for its picture to settle.
# The caller sets $work (a folder for screenshots) and keeps the viewer's pid in $viewer;
# functions set $win (the window id).

# Starts Xvfb on a free display in FIRST..FIRST+399 and exports DISPLAY; on exit the
# viewer (if any) and Xvfb are stopped. A display whose lock file exists is skipped, and
# the server must answer within 20 s (a loaded machine, other window tests starting at
# the same time): otherwise another display is tried, up to five times.
window_session_start() { # FIRST
    local tool i
    for tool in Xvfb xdotool xwd; do
        command -v $tool >/dev/null ||
            { echo "$tool is missing (scripts/install-deps.sh installs it)" >&2; exit 1; }
    done
    viewer=
    xvfb=
    trap window_session_stop EXIT
    for _ in 1 2 3 4 5; do
        local n=$(($1 + RANDOM % 400))
        [ -e "/tmp/.X$n-lock" ] && continue
        display=:$n
        # -noreset: the server would reset when the last client (a viewer the test closed)
        # goes, and a viewer opening the display during that reset fails (seen under load).
        Xvfb "$display" -screen 0 1280x1024x24 -nolisten tcp -noreset >/dev/null 2>&1 &
        xvfb=$!
        for i in $(seq 1 40); do
            if DISPLAY=$display xdotool getdisplaygeometry >/dev/null 2>&1; then
                export DISPLAY=$display
                return 0
            fi
            kill -0 "$xvfb" 2>/dev/null || break # it exited: the display was taken
            sleep 0.5
        done
        kill "$xvfb" 2>/dev/null || true
        wait "$xvfb" 2>/dev/null || true
        xvfb=
    done
    echo "could not start Xvfb on a free display (tried 5)" >&2
    exit 1
}

# A synth scene converted for the viewer: $work/NAME.strata (needs $bin, the build folder).
window_scene() { # NAME "SYNTH ARGUMENTS" [CONVERTER OPTIONS...]
    local name=$1 synth_args=$2
    shift 2
    # shellcheck disable=SC2086 # the synth's arguments are several words
    "${bin:?}/src/strata-synth" $synth_args -o "${work:?}/$name.las" --quiet
    "$bin/preprocess/strata-convert" "$work/$name.las" -o "$work/$name.strata" --force -q "$@"
}

window_session_stop() {
    [ -n "${viewer:-}" ] && kill "$viewer" 2>/dev/null || true
    [ -n "${xvfb:-}" ] && kill "$xvfb" 2>/dev/null || true
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
