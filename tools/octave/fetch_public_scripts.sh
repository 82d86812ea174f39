#!/bin/sh
# Clones the public SPACAR scripts that tools/octave/tests/test_spacarlight.m runs unchanged into
# tools/octave/public/ (git-ignored: their code is not part of flexmb), at the commit the test was
# written against. Needs network (or FLEXMB_SPALIGHT_URL naming a mirror); without a copy the test
# reports itself skipped.
#   precision-utwente/spalight  SPACAR Light (spacarlight.m), version 1.38 of 2024-06-07
set -eu
here=$(cd "$(dirname "$0")" && pwd)
dest="$here/public/spalight"
url=${FLEXMB_SPALIGHT_URL:-https://github.com/precision-utwente/spalight.git}  # a mirror may stand in
commit=1c9e30bf431280e0e9a33cc25290914cae32caf1
mkdir -p "$here/public"
if [ ! -d "$dest/.git" ]; then
  git clone --quiet "$url" "$dest"
fi
git -C "$dest" fetch --quiet origin 2>/dev/null || true
git -C "$dest" -c advice.detachedHead=false checkout --quiet "$commit"
echo "spalight at $(git -C "$dest" rev-parse HEAD) in $dest"
echo "run: ctest --test-dir build -L public_script   (or set FLEXMB_SPALIGHT_DIR to another copy)"
