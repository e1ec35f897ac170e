#!/bin/sh
# Builds CalculiX ccx from Debian's own source package with dualcell's user material
# (src/umat/dualcell_umat.c) in place of ccx's example umat, once, into DIR/ccx. The umat's
# exact law (src/umat/cell_umat.h) is C++: its sources are compiled into
# DIR/source/dualcell_cell.a by umat_archive.sh, linked after ccx's own archive with libstdc++.
#
#   build_ccx_umat.sh DIR UMAT.c
#
# Debian's calculix-ccx binary cannot load external materials, so the umat must be linked in.
# The source comes from the same Debian archive and suite the machine installs from: a deb-src
# entry beside its deb entry (written when missing; root only), then `apt-get source`. The
# build follows debian/rules (spooles, ARPACK, LAPACK, threads). Progress on stderr; the result
# is renamed into place only when complete.
set -eu
dir=$1
umat=$(cd "$(dirname "$2")" && pwd)/$(basename "$2")
tools=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
if [ ! -d "$dir/source" ]; then
  if ! ls "$dir"/calculix-ccx-*/ccx_*/src/Makefile.inc >/dev/null 2>&1; then
    if ! apt-get source --print-uris calculix-ccx >/dev/null 2>&1; then
      [ "$(id -u)" -eq 0 ] || { echo "build_ccx_umat.sh: no deb-src entry for calculix-ccx; run as root once to add it" >&2; exit 1; }
      sources=/etc/apt/sources.list.d/debian.sources
      [ -f "$sources" ] || { echo "build_ccx_umat.sh: $sources not found: add a deb-src line for calculix-ccx by hand" >&2; exit 1; }
      # The first stanza of the machine's Debian entry, as deb-src (same URIs, suites, keyring).
      awk 'BEGIN { RS = ""; ORS = "\n\n" } NR == 1 { sub(/Types: deb/, "Types: deb-src"); print }' "$sources" \
        > /etc/apt/sources.list.d/dualcell-src.sources
      echo "build_ccx_umat.sh: added /etc/apt/sources.list.d/dualcell-src.sources (deb-src of $sources)" >&2
      apt-get update -qq
    fi
    (cd "$dir" && apt-get source -qq calculix-ccx) >&2
  fi
  src=$(ls -d "$dir"/calculix-ccx-*/ccx_*/src | head -n 1)
  rm -rf "$dir/source.tmp" && cp -r "$src" "$dir/source.tmp" && mv "$dir/source.tmp" "$dir/source"
fi
cd "$dir/source"
version=$(ls ccx_*.c | sed -n 's/^ccx_\([0-9.]*\)\.c$/\1/p' | head -n 1)
# The example umat.f out of the Fortran list, dualcell's C umat into the C list (once).
if grep -q '^umat\.f \\$' Makefile.inc; then
  sed -i -e '/^umat\.f \\$/d' -e 's/^SCCXC = \\$/SCCXC = \\\ndualcell_umat.c \\/' Makefile.inc
fi
cp "$umat" dualcell_umat.c
cp "$(dirname "$umat")/cell_umat.h" cell_umat.h
# The exact law's C++ archive (umat_archive.sh), first among ccx's libraries (once).
"$tools/umat_archive.sh" "$dir/source"
grep -q 'dualcell_cell.a' Makefile || sed -i 's/^LIBS = /LIBS = dualcell_cell.a -lstdc++ /' Makefile
grep -q 'dualcell_cell.a' Makefile || { echo "build_ccx_umat.sh: no 'LIBS = ' line in ccx's Makefile" >&2; exit 1; }
rm -f "ccx_$version"
echo "build_ccx_umat.sh: building ccx $version with dualcell's umat in $dir/source (a few minutes, once)" >&2
make -j 2 \
  CFLAGS="-Wall -O2 -I/usr/include/spooles -DARCH=\"Linux\" -DSPOOLES -DARPACK -DMATRIXSTORAGE -DUSE_MT=1" \
  FFLAGS="-O2 -fallow-argument-mismatch" "ccx_$version" > "$dir/build.log" 2>&1 \
  || { tail -n 20 "$dir/build.log" >&2; echo "build_ccx_umat.sh: build failed; log: $dir/build.log" >&2; exit 1; }
nm "ccx_$version.a" | grep -q ' T umat_$' || { echo "build_ccx_umat.sh: umat_ not in the library" >&2; exit 1; }
cp "ccx_$version" "$dir/ccx.tmp" && mv "$dir/ccx.tmp" "$dir/ccx"
echo "build_ccx_umat.sh: $dir/ccx" >&2
