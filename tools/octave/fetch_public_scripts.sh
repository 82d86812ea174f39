#!/bin/sh
# Clones the public SPACAR scripts that tools/octave/tests run unchanged into tools/octave/public/
# (git-ignored: their code is not part of flexmb), at the commits the tests were written against.
# Needs network (or FLEXMB_SPALIGHT_URL / FLEXMB_FIS_URL naming a mirror); without a copy the tests
# report themselves skipped.
#   precision-utwente/spalight  SPACAR Light (spacarlight.m), version 1.38 of 2024-06-07  (test_spacarlight.m)
#   roepnaamstraat/FlexibleInstrumentSimulation  USERSIG / USERINP contact model          (test_fis.m)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$here/public"

fetch() {  # fetch <folder> <url> <commit>
  dest="$here/public/$1"
  if [ ! -d "$dest/.git" ]; then
    git clone --quiet "$2" "$dest"
  fi
  git -C "$dest" fetch --quiet origin 2>/dev/null || true
  git -C "$dest" -c advice.detachedHead=false checkout --quiet "$3"
  echo "$1 at $(git -C "$dest" rev-parse HEAD) in $dest"
}

fetch spalight "${FLEXMB_SPALIGHT_URL:-https://github.com/precision-utwente/spalight.git}" \
  1c9e30bf431280e0e9a33cc25290914cae32caf1
fetch FlexibleInstrumentSimulation \
  "${FLEXMB_FIS_URL:-https://github.com/roepnaamstraat/FlexibleInstrumentSimulation.git}" \
  5ebd1a5de93385db3aa9f6a2ccd6523d6bc85abb
echo "run: ctest --test-dir build -L public_script   (or set FLEXMB_SPALIGHT_DIR / FLEXMB_FIS_DIR to other copies)"
