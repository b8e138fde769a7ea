#!/usr/bin/env bash
# Installs the Debian 12 packages Strata needs to build and test, and nothing else.
# Safe to run again: it only asks apt-get for packages that are missing.
set -euo pipefail

packages=(
    build-essential cmake pkg-config clang libclang-rt-14-dev  # compilers, sanitizers, libFuzzer
    libcmocka-dev                                              # unit tests
    libzstd-dev libxxhash-dev                                  # .strata payloads and checksums
    libglfw3-dev libepoxy-dev libegl-dev libgl-dev             # viewer, headless EGL
    libegl-mesa0 libgl1-mesa-dri                               # Mesa llvmpipe (GL 4.5 without a GPU)
    libopenexr-dev libpng-dev                                  # image output
    libqhull-dev libcglm-dev liblapacke-dev                    # Katz HPR, maths, test references
    libcjson-dev                                               # camera paths, truth sidecars
    libstb-dev fonts-dejavu-core                               # on-screen text (stb_truetype, DejaVu)
    clang-format-14 python3                                    # format check, test helpers
    python3-numpy python3-pil                                  # bench/screen_classes.py (per-pixel error classes)
    glslang-tools                                              # checks shaders llvmpipe cannot build
    xvfb xdotool x11-apps                                      # window tests (Xvfb, xwd)
)

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
    echo "install-deps: all ${#packages[@]} packages already installed"
    exit 0
fi

echo "install-deps: installing with apt-get: ${missing[*]}"
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
echo "install-deps: done"
