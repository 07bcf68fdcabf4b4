#!/usr/bin/env bash
# Installs the Debian 12 packages salsa needs, only those that are missing.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  ccache  # another clone or preset of the same sources compiles only what differs
  dpkg-dev  # dpkg-shlibdeps: the .deb's dependencies (cpack -G DEB, test package_deb)
  libbox2d-dev
  libboost-dev libboost-program-options-dev libboost-filesystem-dev
  nlohmann-json3-dev libtbb-dev libssl-dev
  zlib1g-dev  # salsa export --mcap's checksums
  qt6-base-dev qt6-charts-dev libqt6opengl6-dev libgl-dev
  libopenmpi-dev openmpi-bin
  libpagmo-dev libnlopt-cxx-dev  # salsa tune's algorithms (pagmo2, NLopt)
  libbenchmark-dev
  clang libclang-rt-14-dev
  python3-dev pybind11-dev python3-numpy python3-pandas python3-pytest python3-matplotlib python3-scipy  # the Python package and its examples (docs/python.md)
  libnetcdf-dev python3-h5py python3-xarray python3-netcdf4  # the trajectory archive (netCDF-4 on HDF5) and reading it from Python (docs/replay.md)
  ffmpeg chromium nodejs  # salsa export --video; the web page's and the MCAP reader's tests; this machine's nodejs brings npm (docs/replay.md)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=(); [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
# Debian's nodejs comes without npm (package npm); a NodeSource nodejs has it and conflicts with that package.
if ! command -v npm > /dev/null; then
  sudo_cmd=(); [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends npm
fi
# The independent MCAP reader the tests read salsa export --mcap's files with (@mcap/core, the version in
# its package-lock.json): installed again only when the lock file changed.
reader="$(cd "$(dirname "$0")/.." && pwd)/tests/mcap-reader"
if [ "$reader/package-lock.json" -nt "$reader/node_modules/.package-lock.json" ]; then
  echo "setup: installing @mcap/core into $reader/node_modules"
  npm ci --prefix "$reader" --no-audit --no-fund
fi
