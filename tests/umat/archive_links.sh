#!/bin/sh
# The umat as another code links it: the C user material (src/umat/dualcell_umat.c) and the
# exact law's archive from pipelines/tools/umat_archive.sh, into a C program, with libstdc++ and
# nothing else of the project. Fails when a source the law needs is missing from the archive
# (an undefined reference), which no other test sees: dualcell-tests links the whole library.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# -O0: this checks the symbols, not the speed; it keeps the test at a few seconds.
"$root/pipelines/tools/umat_archive.sh" "$dir" "-O0"
cat > "$dir/main.c" <<'C'
void umat_();
/* Never called: the link must resolve every symbol the umat reaches. */
int main(int argc, char** argv) {
  (void)argv;
  if (argc < 0) umat_();
  return 0;
}
C
gcc -c -I"$root/src/umat" "$root/src/umat/dualcell_umat.c" -o "$dir/umat.o"
gcc -c "$dir/main.c" -o "$dir/main.o"
g++ "$dir/main.o" "$dir/umat.o" "$dir/dualcell_cell.a" -lm -o "$dir/linked"
echo "archive_links.sh: the umat links against umat_archive.sh's archive alone"
