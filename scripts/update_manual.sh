#!/usr/bin/env bash
# Regenerates the key tables of the user manual from the executables' option tables
# (`<Exe> --help-markdown`), between the markers <!-- keys:Exe --> and <!-- /keys:Exe -->.
# Run after changing an option; Test/Unit/ManualTest.cpp fails until the manual matches.
set -euo pipefail
cd "$(dirname "$0")/.."
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
