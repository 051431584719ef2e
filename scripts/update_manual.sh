#!/usr/bin/env bash
# Regenerates the key tables of the user manual from the executables' option tables
# (`<Exe> --help-markdown`), between the markers <!-- keys:Exe --> and <!-- /keys:Exe -->.
# Then rewrites the key templates cfg/ViewSyn.cfg.template and cfg/MeshRender.cfg.template from the
# same tables (through the unit test that compares them, VS_UPDATE_TEMPLATES=1; build dir: $1 or build).
# Run after changing an option; Test/Unit/ManualTest.cpp and ConfigTemplateTest.cpp fail until they match.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${1:-build}"
for pair in "ViewSyn doc/manual.md" "MeshRender doc/meshrender.md" "SceneGen doc/scenegen.md"; do
  set -- $pair
  exe=$1 doc=$2
  [ -x "Bin/$exe" ] && [ -f "$doc" ] && grep -q "<!-- keys:$exe -->" "$doc" || continue
  "Bin/$exe" --help-markdown > /tmp/keys.$$
  python3 - "$doc" "$exe" /tmp/keys.$$ <<'PY'
import sys
doc, exe, keys = sys.argv[1], sys.argv[2], open(sys.argv[3]).read()
text = open(doc).read()
begin, end = f"<!-- keys:{exe} -->", f"<!-- /keys:{exe} -->"
a, b = text.index(begin) + len(begin), text.index(end)
open(doc, "w").write(text[:a] + "\n" + keys.strip("\n") + "\n" + text[b:])
PY
  rm -f /tmp/keys.$$
  echo "updated $doc"
done
unit_tests="$build_dir/Test/UnitTests"
if [ -x "$unit_tests" ]; then
  VS_UPDATE_TEMPLATES=1 "$unit_tests" --gtest_filter='ConfigTemplate.*EqualsTheOptionTable' | grep '^updated' || true
else
  echo "$unit_tests not built: cfg/*.cfg.template not checked" >&2
fi
