#!/bin/sh
# Compiles the C++ side of the umat's exact law (the cell's text file, the law with its member
# table and its bond rule, the dense QP, the file hash, the C interface; Eigen only, no other library of the
# project) into DIR/dualcell_cell.a, which a code's own build links after the C umat (src/umat/dualcell_umat.c)
# with libstdc++. The one list of those sources: build_ccx_umat.sh uses it, and ctest links a C
# program against an archive of the build's own objects of these sources (tests/umat/
# archive_links.sh), so a source the law comes to need cannot be missing here unnoticed.
#
#   umat_archive.sh DIR [CXXFLAGS]
#   umat_archive.sh --list       (the sources, one per line, under src/ without .cpp)
set -eu
sources="umat/cell_umat core/hash core/text law/condensed law/condensed_members law/bond law/cell_text qp/dense_qp qp/dense_kkt"
if [ "${1:-}" = "--list" ]; then
  printf '%s\n' $sources
  exit 0
fi
dir=$1
flags=${2:--O2 -DNDEBUG}
src_root=$(cd "$(dirname "$0")/../.." && pwd)/src
mkdir -p "$dir"
objects=""
for f in $sources; do
  # shellcheck disable=SC2086
  g++ -std=c++20 $flags -I"$src_root" -I/usr/include/eigen3 -c "$src_root/$f.cpp" -o "$dir/dualcell_$(basename $f).o"
  objects="$objects $dir/dualcell_$(basename $f).o"
done
rm -f "$dir/dualcell_cell.a"
# shellcheck disable=SC2086
ar rcs "$dir/dualcell_cell.a" $objects
