#!/usr/bin/env bash
# Installs Foxglove's MCAP and ROS 2 libraries, at the versions package-lock.json pins (npm ci),
# with the reference script beside them, into DEST in the build folder: nothing is written into
# the source tree. Needs Node and npm (tools/deps.sh) and the npm registry, and fails (never
# skips) without them: the ros2 reference tests depend on this one.
# Usage: install.sh SOURCE_DIR DEST
set -euo pipefail
src="$1"
dest="$2"
for tool in node npm; do
  command -v "$tool" >/dev/null || { echo "FAIL: $tool not found (tools/deps.sh installs nodejs and npm)"; exit 1; }
done
mkdir -p "$dest"
cp "$src/package.json" "$src/package-lock.json" "$src/foxglove_reference.mjs" "$dest/"
# Installed already from this very lockfile: nothing to do.
if [[ -f "$dest/node_modules/.canopy-package-lock.json" ]] &&
  cmp -s "$src/package-lock.json" "$dest/node_modules/.canopy-package-lock.json"; then
  echo "Foxglove reference libraries installed (node $(node --version))"
  exit 0
fi
# --ignore-scripts: the libraries are plain JavaScript and WebAssembly; no install step runs.
if ! npm ci --prefix "$dest" --ignore-scripts --no-audit --no-fund; then
  echo "FAIL: npm ci of the Foxglove reference libraries (needs the npm registry)"
  exit 1
fi
cp "$src/package-lock.json" "$dest/node_modules/.canopy-package-lock.json"
echo "Foxglove reference libraries installed (node $(node --version), npm $(npm --version))"
