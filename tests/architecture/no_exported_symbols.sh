#!/bin/bash
# Each executable given exports no symbol of ours and no Eigen template instance (hidden
# visibility, CMakeLists.txt): libgmsh carries its own Eigen and would bind to ours, which under
# AddressSanitizer allocate differently (docs/architecture.md, the rules of the layers).
# Usage: no_exported_symbols.sh NM EXECUTABLE...
set -u
nm=$1
shift
status=0
for exe in "$@"; do
  symbols=$("$nm" -DC "$exe") || { echo "$exe: $nm -D failed" >&2; exit 2; }
  exported=$(grep -E ' [TWVBDRu] .*(Eigen::|dualcell::)' <<<"$symbols")
  if [ -n "$exported" ]; then
    echo "$exe exports $(wc -l <<<"$exported") symbols of ours or Eigen's, e.g.:" >&2
    head -3 <<<"$exported" >&2
    status=1
  fi
done
exit $status
