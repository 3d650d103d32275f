#!/usr/bin/env bash
# Configures and builds arcs in build/ (Release). Extra arguments go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=${ARCS_BUILD_JOBS:-$(nproc)}
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j "$JOBS"
# The Python module: make `python3 -c "import arcs"` find build/python (a .pth
# file in the user site directory of the python3 first on PATH and of
# /usr/bin/python3; same-version interpreters share it). The module adds
# Debian's numpy itself when the importing python3 has none (e.g. pyenv).
if [ -d build/python/arcs ] && [ "${ARCS_NO_PTH:-0}" != 1 ]; then
  for py in python3 /usr/bin/python3; do
    command -v "$py" >/dev/null || continue
    site=$("$py" -c 'import site; print(site.getusersitepackages() if site.ENABLE_USER_SITE else "")' 2>/dev/null) || continue
    [ -n "$site" ] || continue
    mkdir -p "$site" && echo "$PWD/build/python" > "$site/arcs.pth" && echo "build: arcs Python module: $site/arcs.pth -> $PWD/build/python"
  done | sort -u
fi
