#!/usr/bin/env bash
# The documentation site (docs/develop/testing.md, "Documentation checks"): generates the pages that
# come from the program and from documents beside the code into docs/generated/ (git-ignored), runs
# every command and example the pages show against the build's flexmb (tools/check_docs.py
# commands; the pictures they draw land in docs/generated/<page>/), then builds the site strictly
# into <build>/site. Idempotent. ctest docs_site runs it.
#   bash tools/docs.sh [--no-commands] [--no-site]
#   FLEXMB_BUILD_DIR: the build folder (default build)
# Exit 0 when every command ran as its page says and the site built; 1 otherwise; 77 (skipped)
# without mkdocs or the flexmb binary.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS
commands=1
site=1
for a in "$@"; do
  case "$a" in
    --no-commands) commands=0 ;;
    --no-site) site=0 ;;
    *) echo "usage: bash tools/docs.sh [--no-commands] [--no-site]" >&2; exit 2 ;;
  esac
done
BUILD_DIR=$(realpath -m "${FLEXMB_BUILD_DIR:-build}")
flexmb="$BUILD_DIR/flexmb"
python=/usr/bin/python3
[ -x "$python" ] || python=python3

if ((site)) && ! command -v mkdocs >/dev/null; then
  echo "SKIPPED: mkdocs is not installed (apt-get install mkdocs mkdocs-material; tools/setup.sh installs them)"
  exit 77
fi
if [ ! -x "$flexmb" ]; then
  echo "SKIPPED: no $flexmb (build it first: cmake --build $BUILD_DIR --target flexmb)"
  exit 77
fi

generated=docs/generated
# Made anew with the commands (no picture of a page or command that is gone stays behind).
((commands)) && rm -rf "$generated"
mkdir -p "$generated"
# The .dat language reference, from the keyword table (as io/dat-language.md is).
"$flexmb" keywords --markdown >"$generated/dat-language.md.tmp"
mv "$generated/dat-language.md.tmp" "$generated/dat-language.md"
# Reference documents that live beside the code they describe, as docs/generated/<page>.md (a link
# from one to another is rewritten to the copy).
while read -r from page; do
  sed -e 's#](\.\./\.\./io/results\.md)#](results\.md)#g' "$from" >"$generated/$page.tmp"
  mv "$generated/$page.tmp" "$generated/$page.md"
done <<'EOF'
io/results.md results
analysis/ReducedOperators.md reduced-operators
core/elements/BEAMW.md beamw
EOF

status=0
if ((commands)); then
  "$python" tools/check_docs.py commands --flexmb "$flexmb" --build-dir "$BUILD_DIR" || status=1
fi
if ((site)); then
  if mkdocs build --strict --clean --site-dir "$BUILD_DIR/site" 2>"$BUILD_DIR/mkdocs.log"; then
    echo "docs: site built in $BUILD_DIR/site (open $BUILD_DIR/site/index.html)"
  else
    cat "$BUILD_DIR/mkdocs.log" >&2
    echo "docs: mkdocs build --strict failed" >&2
    status=1
  fi
fi
echo "docs: done in $((SECONDS - start)) s"
exit $status
