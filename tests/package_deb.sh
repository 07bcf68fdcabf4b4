#!/usr/bin/env bash
# `cpack -G DEB` of the build makes a salsa .deb with the programs, libsalsa, the built-in plugins, the
# plugin SDK (headers, CMake package), the docs and the examples, the Python package (when built), and
# dependencies (dpkg-shlibdeps). The package's files, unpacked into a folder of their own, work there:
# Debian's python3 imports salsa from them and finds the plugins and the salsa program beside it.
set -euo pipefail
build_dir=$1 work=$2
python_built=$(ls "$build_dir"/python/salsa/_core*.so 2>/dev/null || true)
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
if [ -n "$python_built" ]; then
  for pattern in '/usr/lib/python3/dist-packages/salsa/__init__\.py$' '/usr/lib/python3/dist-packages/salsa/_results\.py$' \
                 '/usr/lib/python3/dist-packages/salsa/_core\.cpython-[^/]*\.so$'; do
    grep -qE "$pattern" <<<"$contents" || { echo "$contents"; echo "FAIL: the .deb has no $pattern"; exit 1; }
  done
fi
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
if [ -n "$python_built" ]; then
  recommends=$(dpkg-deb -f "$deb" Recommends)
  for d in 'python3 (>= 3.' python3-numpy python3-pandas; do
    grep -qF "$d" <<<"$recommends" || { echo "FAIL: Recommends lacks $d: $recommends"; exit 1; }
  done
  # Installed as dpkg -i would, under a root of its own: python3 finds the package in Debian's folder for
  # it, and the package the plugins and the program of its prefix (none on PATH, none in the build tree).
  root="$work/root"
  dpkg-deb -x "$deb" "$root"
  mkdir -p "$work/home"
  env -i PATH=/usr/bin:/bin HOME="$work/home" PYTHONPATH="$root/usr/lib/python3/dist-packages" PYTHONDONTWRITEBYTECODE=1 \
    /usr/bin/python3 - "$root" "$work/out" <<'EOF' || { echo "FAIL: the installed Python package"; exit 1; }
import json, os, sys
root, out = sys.argv[1:]
import salsa
from salsa import _core, _run
assert salsa.__file__ == f"{root}/usr/lib/python3/dist-packages/salsa/__init__.py", salsa.__file__
assert _core.build_tree() is None and _core.install_prefix() == f"{root}/usr", _core.install_prefix()
folders = [f for f, origin in _core.plugin_folders() if origin == "install"]
assert len(folders) == 1 and folders[0].startswith(f"{root}/usr/lib") and folders[0].endswith("/salsa/plugins"), folders
assert _run.program() == f"{root}/usr/bin/salsa", _run.program()
example = f"{root}/usr/share/doc/salsa/examples/random-walk-forest.json"
test = {**json.load(open(example)), "time": 2}
s = salsa.Session(test)
s.run_until()
assert s.finished and s.column("position").shape == (test["drones"], 2)
assert s.render(64, 48).shape == (48, 64, 3)  # the desktop's drawing, on Qt's offscreen platform
assert salsa.validate(example) is None
r = salsa.run(test, out=out, plots=False)
assert list(r.tests) == [test["name"]] and (r.summary["status"] == "ok").all()
print(f"installed Python package: salsa {salsa.__version__}, plugins from {folders[0]}")
EOF
fi
echo "package_deb: ok ($(basename "$deb"), $(wc -l <<<"$contents") entries)"
