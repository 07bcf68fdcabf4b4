#!/usr/bin/env bash
# `cpack -G DEB` of the build makes a salsa .deb with the programs, libsalsa, the built-in plugins, the
# plugin SDK (headers, CMake package), the docs and the examples, and dependencies (dpkg-shlibdeps).
set -euo pipefail
build_dir=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
cpack --config "$build_dir/CPackConfig.cmake" -G DEB -B "$work" >"$work/cpack.log" 2>&1 || { cat "$work/cpack.log"; exit 1; }
deb=$(ls "$work"/salsa_*.deb)
contents=$(dpkg-deb -c "$deb" | awk '{print $NF}')
for pattern in '/usr/bin/salsa$' '/usr/bin/salsa-gui$' '/usr/lib[^/]*/libsalsa\.so' \
               '/usr/lib[^/]*/salsa/plugins/libflocking\.so$' '/usr/lib[^/]*/salsa/plugins/librandom_walk\.so$' \
               '/usr/lib[^/]*/salsa/plugins/libtree\.so$' '/usr/lib[^/]*/salsa/plugins/libbasic_maps\.so$' \
               '/usr/lib[^/]*/salsa/plugins/libcontact_handlers\.so$' '/usr/lib[^/]*/salsa/plugins/libmetrics\.so$' \
               '/usr/include/salsa/sdk\.hpp$' '/usr/include/salsa/testing\.hpp$' \
               '/usr/lib[^/]*/cmake/salsa/salsaConfig\.cmake$' '/usr/lib[^/]*/cmake/salsa/SalsaSmokeTest\.cmake$' \
               '/usr/share/doc/salsa/plugins\.md$' '/usr/share/doc/salsa/img/' \
               '/usr/share/doc/salsa/examples/plugin/wander\.cpp$' '/usr/share/doc/salsa/examples/plugin/CMakeLists\.txt$' \
               '/usr/share/doc/salsa/examples/flocking-forest\.json$' '/usr/share/doc/salsa/examples/maps/warehouse\.json$'; do
  grep -qE "$pattern" <<<"$contents" || { echo "$contents"; echo "FAIL: the .deb has no $pattern"; exit 1; }
done
outside=$(grep -vE '^\./(usr(/.*)?)?$' <<<"$contents" || true)
[ -z "$outside" ] || { echo "$outside"; echo "FAIL: the .deb installs outside /usr"; exit 1; }
fields=$(dpkg-deb -f "$deb" Package Version Depends)
echo "$fields"
grep -qx "Package: salsa" <<<"$fields" || { echo "FAIL: package name"; exit 1; }
depends=$(dpkg-deb -f "$deb" Depends)
[ -n "$depends" ] || { echo "FAIL: empty Depends"; exit 1; }
# Computed by dpkg-shlibdeps (Box2D, TBB, Qt), and the plugin author's tools added by hand.
for d in libbox2d libtbb libqt6widgets6 cmake g++; do
  grep -q "$d" <<<"$depends" || { echo "FAIL: Depends lacks $d"; exit 1; }
done
echo "package_deb: ok ($(basename "$deb"), $(wc -l <<<"$contents") entries)"
