#!/bin/sh
# The umat as another code links it: the C user material (src/umat/dualcell_umat.c) and an
# archive of the exact law's sources as pipelines/tools/umat_archive.sh lists them, into a C
# program, with libstdc++ and nothing else of the project. Fails when a source the law needs is
# missing from that list (an undefined reference), which no other test sees: dualcell-tests links
# the whole library. The archive takes the build's own objects of those sources (compiling them
# again took 60–70 s of every suite); `umat_archive.sh DIR` compiles the same list for a code's
# own build.
#
#   archive_links.sh OBJECT_DIR [LINK_FLAGS]   (OBJECT_DIR: the library's objects, src/... .cpp.o)
set -eu
objects=$1
link_flags=${2:-}
root=$(cd "$(dirname "$0")/../.." && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
members=""
for f in $("$root/pipelines/tools/umat_archive.sh" --list); do
  [ -f "$objects/src/$f.cpp.o" ] || { echo "archive_links.sh: no object $objects/src/$f.cpp.o" >&2; exit 1; }
  members="$members $objects/src/$f.cpp.o"
done
# shellcheck disable=SC2086
ar rcs "$dir/dualcell_cell.a" $members
cat > "$dir/main.c" <<'C'
void umat_();
/* Never called: the link must resolve every symbol the umat reaches. */
int main(int argc, char** argv) {
  (void)argv;
  if (argc < 0) umat_();
  return 0;
}
C
# shellcheck disable=SC2086
gcc $link_flags -c -I"$root/src/umat" "$root/src/umat/dualcell_umat.c" -o "$dir/umat.o"
# shellcheck disable=SC2086
gcc $link_flags -c "$dir/main.c" -o "$dir/main.o"
# shellcheck disable=SC2086
g++ $link_flags "$dir/main.o" "$dir/umat.o" "$dir/dualcell_cell.a" -lm -o "$dir/linked"
echo "archive_links.sh: the umat links against an archive of umat_archive.sh's sources alone"
