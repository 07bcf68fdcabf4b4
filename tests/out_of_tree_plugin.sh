#!/usr/bin/env bash
# The plugin author's path: install salsa, build examples/plugin against it with find_package(salsa)
# + salsa_add_plugin, and load the result with `salsa plugins --plugin-dir`.
set -euo pipefail
build_dir=$1 source_dir=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
cmake --install "$build_dir" --prefix "$work/prefix" >/dev/null
cmake -S "$source_dir/examples/plugin" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/build" >/dev/null
# Its test, on the installed stepping fixture (salsa::fixture).
(cd "$work/build" && ctest --output-on-failure >/dev/null)
listing=$("$work/prefix/bin/salsa" plugins --plugin-dir "$work/build")
echo "$listing"
grep -E "behavior +wander +1\.0\.0" <<<"$listing"
"$work/prefix/bin/salsa" describe wander --plugin-dir "$work/build" | grep turn_interval
# The installed salsa finds its own built-in plugins in <prefix>/lib/salsa/plugins.
grep -E "behavior +flocking" <<<"$listing"
