#!/usr/bin/env bash
# The default mission (default world and settings, seed 1) of each method gives the same
# views.csv, byte for byte, as when these hashes were recorded (golden_views.sha256, taken
# before the house was rearranged): a change that should not change behaviour must not change
# what the robot does. A change that means to change behaviour updates the hashes and says so.
set -euo pipefail
canopy="$1"
here="$(cd "$(dirname "$0")" && pwd)"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
while read -r hash method; do
  "$canopy" mission --method "$method" --out "$tmp/$method" --no-plots > "$tmp/$method.log" 2>&1 \
    || { echo "$method: mission failed"; tail -3 "$tmp/$method.log"; fail=1; continue; }
  got=$(sha256sum "$tmp/$method/views.csv" | cut -d' ' -f1)
  if [[ "$got" == "$hash" ]]; then
    echo "$method: views.csv unchanged ($got)"
  else
    echo "$method: views.csv changed: $got, expected $hash"
    fail=1
  fi
done < "$here/golden_views.sha256"
exit $fail
