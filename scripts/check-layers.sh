#!/usr/bin/env bash
# The layers' include rules the include roots do not enforce (CMakeLists.txt, "Layers"): a
# layer includes only layers above it, and the modes do not include each other.
# Usage: scripts/check-layers.sh [SOURCE_DIR]; exits 1 naming every include that crosses.
set -euo pipefail
root="${1:-$(cd "$(dirname "$0")/.." && pwd)}"
status=0

# forbid DIR PATTERN...: no file under DIR may include a header under any of the named folders.
forbid() {
  local dir="$1"
  shift
  local alternatives
  alternatives="$(IFS='|'; echo "$*")"
  local hits
  hits="$(grep -rnE "#include \"(${alternatives})/" "$root/$dir" --include='*.cpp' --include='*.hpp' --include='*.ipp' || true)"
  if [[ -n "$hits" ]]; then
    echo "layer rule broken: $dir/ must not include $*:"
    echo "$hits" | sed "s|$root/||"
    status=1
  fi
}

forbid lib/engine scene io run jam shear asteroid magnetics design
forbid geometry scene io run jam shear asteroid magnetics design
forbid lib/scene jam shear asteroid magnetics design
forbid lib/io jam shear asteroid magnetics design
forbid lib/run jam shear asteroid magnetics design
forbid lib/jam shear asteroid magnetics design
forbid lib/shear jam asteroid magnetics design
forbid lib/asteroid jam shear magnetics design
forbid magnetics jam shear asteroid design
forbid design shear asteroid
forbid lib/sweep jam shear asteroid magnetics design
exit $status
