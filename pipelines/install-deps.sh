#!/bin/sh
# Checks that every Debian package dualcell needs is installed; installs the missing ones when
# run as root, otherwise prints the exact command and fails. Does nothing when all are present.
set -eu
packages="cmake make gcc g++ binutils git
libeigen3-dev libsuitesparse-dev libgsl-dev libhdf5-dev libcli11-dev libtomlplusplus-dev
libgmsh-dev libmetis-dev
libgtest-dev libblas3 liblapack3 libopenblas0-pthread
hdf5-tools python3 python3-numpy python3-h5py python3-meshio gnuplot-nox calculix-ccx
clang clang-format libclang-rt-14-dev
gfortran dpkg-dev libspooles-dev libarpack2-dev liblapack-dev
openmpi-bin libopenmpi-dev"
missing=""
for p in $packages; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing="$missing $p"
  fi
done
[ -z "$missing" ] && exit 0
if [ "$(id -u)" -eq 0 ]; then
  echo "dualcell: installing missing Debian packages:$missing" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  # shellcheck disable=SC2086
  apt-get install -y -qq --no-install-recommends $missing >&2
else
  echo "dualcell: missing Debian packages:$missing" >&2
  echo "dualcell: install them with:  sudo apt-get install -y$missing" >&2
  exit 1
fi
