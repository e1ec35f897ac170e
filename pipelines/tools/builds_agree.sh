#!/bin/sh
# The build with MPI (started without a launcher: one rank) and the build without MPI write the
# same files: one sweep and one solve of a scene with each, compared by h5diff. Only measured
# quantities may differ (seconds, peak memory); anything else is printed and fails.
#
# usage: builds_agree.sh MPI_BIN SERIAL_BIN SCENE.toml STRESS OUTDIR
set -eu
[ $# -eq 5 ] || { echo "usage: $0 MPI_BIN SERIAL_BIN SCENE.toml STRESS OUTDIR" >&2; exit 2; }
mpi=$1 serial=$2 scene=$3 stress=$4 out=$5
rm -rf "$out"
mkdir -p "$out"
"$mpi/dualcell-mesh" --quiet --config "$scene" --out "$out/mesh.h5"
for build in mpi serial; do
  eval bin=\$$build
  "$bin/dualcell-sweep" --quiet --config "$scene" --mesh "$out/mesh.h5" --out "$out/sweep-$build.h5"
  "$bin/dualcell-solve" --quiet --config "$scene" --mesh "$out/mesh.h5" --stress "$stress" \
    --out "$out/solve-$build.h5"
done
status=0
for kind in sweep solve; do
  # h5diff exits 1 when the files differ, 2 when it cannot compare them.
  report=$(h5diff "$out/$kind-mpi.h5" "$out/$kind-serial.h5") || [ $? -eq 1 ] || {
    echo "builds_agree.sh: h5diff could not compare the $kind files" >&2
    exit 1
  }
  others=$(printf '%s\n' "$report" | grep -E '^(dataset|attribute):|not comparable' |
    grep -vE 'seconds|peak_rss_bytes' || true)
  if [ -n "$others" ]; then
    echo "builds_agree.sh: the $kind of $scene differs between the builds with and without MPI:" >&2
    printf '%s\n' "$others" >&2
    status=1
  else
    echo "builds_agree.sh: $kind of $(basename "$scene"): the same with and without MPI (but measured seconds)"
  fi
done
exit $status
