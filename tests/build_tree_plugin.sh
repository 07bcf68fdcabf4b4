#!/usr/bin/env bash
# A plugin built against salsa's build tree, not an installation (CMAKE_PREFIX_PATH=<build>): find_package
# finds <build>/lib/cmake/salsa, whose salsaConfig.cmake includes the SDK's SalsaPlugin.cmake from the
# source tree; `salsa new-plugin behavior` and `metric` configure, build, pass their ctest (the plugin's
# own fixture test and the <name>_loads smoke test, which runs the build's salsa) and load.
set -euo pipefail
build_dir=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
salsa=$build_dir/bin/salsa
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
sanitize=()
flags=$(sed -n 's/^CMAKE_CXX_FLAGS:STRING=//p' "$build_dir/CMakeCache.txt")
if [[ $flags == *-fsanitize* ]]; then
  sanitize=("-DCMAKE_CXX_FLAGS=$flags" "-DCMAKE_EXE_LINKER_FLAGS=$flags" "-DCMAKE_SHARED_LINKER_FLAGS=$flags"
            "-DCMAKE_MODULE_LINKER_FLAGS=$flags")
fi
test -f "$build_dir/lib/cmake/salsa/salsaConfig.cmake" || { echo "FAIL: no salsaConfig.cmake in $build_dir/lib/cmake/salsa"; exit 1; }
for kind in behavior metric; do
  name=bt_$kind
  "$salsa" new-plugin "$kind" "$name" --dir "$work" >/dev/null
  src=$work/$name bin=$work/$name/build
  cmake -S "$src" -B "$bin" -G Ninja -DCMAKE_PREFIX_PATH="$build_dir" -DSALSA_USER_PLUGIN_DIR="$work/user" "${launcher[@]}" "${sanitize[@]}" \
    >"$bin.log" 2>&1 || { cat "$bin.log"; echo "FAIL: configure $name against the build tree"; exit 1; }
  # The build tree's package, not an installed salsa elsewhere on this machine.
  grep -q "^salsa_DIR:PATH=$build_dir/lib/cmake/salsa$" "$bin/CMakeCache.txt" ||
    { grep salsa_DIR "$bin/CMakeCache.txt"; echo "FAIL: $name found another salsa"; exit 1; }
  cmake --build "$bin" -j2 >>"$bin.log" 2>&1 || { cat "$bin.log"; echo "FAIL: build $name against the build tree"; exit 1; }
  out=$(ctest --test-dir "$bin" --output-on-failure 2>&1) || { echo "$out"; echo "FAIL: ctest of $name"; exit 1; }
  grep -q "${name}_test .*Passed" <<<"$out" && grep -q "${name}_loads .*Passed" <<<"$out" ||
    { echo "$out"; echo "FAIL: $name: expected ${name}_test and ${name}_loads to pass"; exit 1; }
  # Read whole before grep: grep -q stops at the first match, and under pipefail the SIGPIPE of a listing
  # longer than one write would fail the pipeline.
  listing=$("$salsa" plugins --plugin-dir "$bin")
  grep -q "$name" <<<"$listing" || { echo "FAIL: salsa plugins does not list $name"; exit 1; }
  echo "ok: new-plugin $kind $name built and tested against the build tree"
done
