#!/bin/sh
# Install the Debian packages xdyna needs, quietly, only when one is missing.
# `deps.sh check`: the packages the tests need beyond those (VTK's LS-DYNA
# reader, python3-vtk9, the independent reader of our d3plot).
set -e
pkgs="gfortran make time libhdf5-dev libopenmpi-dev openmpi-bin liblapack-dev libmetis-dev python3 python3-numpy python3-h5py python3-matplotlib python3-pytest python3-pytest-xdist python3-pytest-subtests"
[ "$1" = "check" ] && pkgs="python3-vtk9"
missing=""
for p in $pkgs; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
echo "deps: installing$missing"
sudo=""
[ "$(id -u)" -ne 0 ] && command -v sudo >/dev/null 2>&1 && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq >/dev/null
$sudo apt-get install -y -qq --no-install-recommends $missing >/dev/null
