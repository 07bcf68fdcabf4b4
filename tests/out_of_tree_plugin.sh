#!/usr/bin/env bash
# The plugin author's path, against an installed salsa only:
# 1. `cmake --install` salsa into a temporary prefix;
# 2. `salsa new-plugin` of every kind; each folder configures against that prefix alone
#    (CMAKE_PREFIX_PATH), builds, passes its ctest (its own test + the <name>_loads smoke test) and
#    `cmake --install`s into a user plugin folder;
# 3. the installed example plugins build the same way, pass their tests and run a queue; every C++
#    block of plugins.md is one of them;
# 4. `salsa plugins` loads them all, from their build folders and from the user folder;
# 5. new-plugin refuses an existing folder, a bad name and an unknown kind in one line each.
set -euo pipefail
build_dir=$1 source_dir=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
prefix=$work/prefix
cmake --install "$build_dir" --prefix "$prefix" >/dev/null
salsa=$prefix/bin/salsa
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
user=$work/user-plugins

# configure_build_test SOURCE BUILD: the author's three commands, against $prefix only.
# A sanitized salsa (the asan-ubsan preset) needs sanitized authors' programs: a test linking an
# instrumented libsalsa must load the sanitizer runtime first.
sanitize=()
flags=$(sed -n 's/^CMAKE_CXX_FLAGS:STRING=//p' "$build_dir/CMakeCache.txt")
if [[ $flags == *-fsanitize* ]]; then
  sanitize=("-DCMAKE_CXX_FLAGS=$flags" "-DCMAKE_EXE_LINKER_FLAGS=$flags" "-DCMAKE_SHARED_LINKER_FLAGS=$flags"
            "-DCMAKE_MODULE_LINKER_FLAGS=$flags")
fi
configure_build_test() {
  cmake -S "$1" -B "$2" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" -DSALSA_USER_PLUGIN_DIR="$user" "${launcher[@]}" "${sanitize[@]}" >"$2.log" 2>&1 ||
    { cat "$2.log"; echo "FAIL: configure $1"; exit 1; }
  # find_package found the temporary prefix, not another salsa on this machine.
  grep -q "^salsa_DIR:PATH=$prefix/" "$2/CMakeCache.txt" || { grep salsa_DIR "$2/CMakeCache.txt"; echo "FAIL: $1 found another salsa"; exit 1; }
  cmake --build "$2" -j2 >>"$2.log" 2>&1 || { cat "$2.log"; echo "FAIL: build $1"; exit 1; }
}

kinds=(behavior target map contact-handler metric wind)
dirs=()
for kind in "${kinds[@]}"; do
  name=my_${kind//-/_}
  "$salsa" new-plugin "$kind" "$name" --dir "$work/new" >/dev/null
  configure_build_test "$work/new/$name" "$work/new/$name/build"
  # Optimised by default: no build type was given.
  grep -q -- "-O2" "$work/new/$name/build/build.ninja" || { echo "FAIL: $name is not built with -O2"; exit 1; }
  out=$(ctest --test-dir "$work/new/$name/build" --output-on-failure 2>&1) || { echo "$out"; echo "FAIL: ctest of $name"; exit 1; }
  grep -q "${name}_test .*Passed" <<<"$out" && grep -q "${name}_loads .*Passed" <<<"$out" ||
    { echo "$out"; echo "FAIL: $name: expected ${name}_test and ${name}_loads to pass"; exit 1; }
  cmake --install "$work/new/$name/build" >/dev/null
  test -f "$user/lib$name.so" || { echo "FAIL: cmake --install did not put lib$name.so in $user"; exit 1; }
  dirs+=(--plugin-dir "$work/new/$name/build")
  echo "ok: new-plugin $kind $name: built, tested, installed"
done

# The smoke test of the behavior ran it: a test folder with its data.
test -s "$work/new/my_behavior/build/my_behavior_loads/out/smoke-behavior-my_behavior/summary.csv" ||
  { echo "FAIL: the smoke test did not run my_behavior"; exit 1; }

# The smoke test fails a plugin that loads but cannot run: a map whose defaults it refuses.
"$salsa" new-plugin map bad_map --dir "$work/new" >/dev/null
sed -i 's/"pillar", 8.0,/"pillar", 80.0,/' "$work/new/bad_map/bad_map.cpp"
configure_build_test "$work/new/bad_map" "$work/new/bad_map/build"
if out=$(ctest --test-dir "$work/new/bad_map/build" --output-on-failure -R bad_map_loads 2>&1); then
  echo "$out"; echo "FAIL: bad_map_loads passed"; exit 1
fi
grep -q "pillar: must be smaller than spacing" <<<"$(tr -d '\n' <<<"$out" | tr -s ' ')" ||
  { echo "$out"; echo "FAIL: bad_map_loads failed without naming the map's error"; exit 1; }
echo "ok: the smoke test fails bad_map"

# The example plugins as installed (share/doc/salsa/examples/plugin): behaviors, a target kind with
# its contact handler, a map and a metric; their fixture tests (salsa_add_plugin_test) and smoke tests.
examples=$prefix/share/doc/salsa/examples/plugin
configure_build_test "$examples" "$work/example"
out=$(ctest --test-dir "$work/example" --output-on-failure 2>&1) || { echo "$out"; echo "FAIL: ctest of examples/plugin"; exit 1; }
for t in wander_test dwell_test rings_test return_to_base_test flocking_plus_test vortex_test gossip_test wander_loads dwell_loads rings_loads \
         return_to_base_loads in_zone_loads flocking_plus_loads vortex_loads gossip_loads; do
  grep -q "$t .*Passed" <<<"$out" || { echo "$out"; echo "FAIL: $t did not pass"; exit 1; }
done
# A queue that uses them, from a fresh folder holding only the built files.
mkdir -p "$work/shared-plugins" && cp "$work/example"/lib*.so "$work/shared-plugins/"
(cd "$work" && "$salsa" run "$examples/queue.json" --plugin-dir "$work/shared-plugins" --out "$work/queue-out" -q --no-plots)
grep -q "longest_in_zone" "$work/queue-out/wander-rings/outcome.csv" || { echo "FAIL: in_zone's column missing"; exit 1; }
grep -q '"dwell_detect"' "$work/queue-out/wander-rings/config.json" && grep -q '"dwell": *2' "$work/queue-out/wander-rings/config.json" ||
  { cat "$work/queue-out/wander-rings/config.json"; echo "FAIL: config.json lacks dwell_detect's parameter"; exit 1; }
grep -q "^id,group,status,since,energy_used_Wh,battery_left$" "$work/queue-out/return-home/fleet.csv" ||
  { echo "FAIL: return-home has no fleet.csv"; exit 1; }
echo "ok: the installed example plugins build, pass their tests and run a queue"

# Every C++ block of the installed plugins.md is one of these example files, verbatim (its first line
# names the file), so every block was just compiled and tested.
mkdir -p "$work/doc-blocks"
awk -v dir="$work/doc-blocks" '/^```cpp$/ { inside = 1; file = dir "/" ++n ".cpp"; next } /^```$/ { inside = 0; next }
     inside { print > file }' "$prefix/share/doc/salsa/plugins.md"
blocks=0
for block in "$work"/doc-blocks/*.cpp; do
  name=$(head -1 "$block" | sed -n 's|^// \([a-z_]*\.cpp\):.*|\1|p')
  [ -n "$name" ] && cmp -s "$block" "$examples/$name" ||
    { echo "FAIL: plugins.md block $(basename "$block") is not an example file verbatim (first line: $(head -1 "$block"))"; exit 1; }
  blocks=$((blocks + 1))
done
[ "$blocks" -ge 6 ] || { echo "FAIL: only $blocks C++ blocks in plugins.md"; exit 1; }
echo "ok: all $blocks C++ blocks of plugins.md are compiled example files"
dirs+=(--plugin-dir "$work/example")
# A build type the author chose is kept (only configured: the flags are in build.ninja).
cmake -S "$source_dir/examples/plugin" -B "$work/example-debug" -G Ninja -DCMAKE_BUILD_TYPE=Debug \
      -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
flags=$(grep -A3 "^build CMakeFiles/wander.dir/wander.cpp.o" "$work/example-debug/build.ninja" | grep FLAGS)
grep -q -- "-g" <<<"$flags" && ! grep -q -- "-O2" <<<"$flags" || { echo "$flags"; echo "FAIL: Debug build of the example got -O2"; exit 1; }

listing=$("$salsa" plugins "${dirs[@]}")
echo "$listing"
grep -q "Refused" <<<"$listing" && { echo "FAIL: refusals"; exit 1; }
grep -E "^  behavior +my_behavior " <<<"$listing"
grep -E "^  target +my_target " <<<"$listing"
grep -E "^  map +my_map " <<<"$listing"
grep -E "^  contact handler +my_contact_handler " <<<"$listing"
grep -E "^  metric +my_metric " <<<"$listing"
grep -E "^  wind +my_wind " <<<"$listing"
grep -E "^  wind +vortex +1\.0\.0" <<<"$listing"
"$salsa" describe vortex --plugin-dir "$work/example" | grep centre_x
grep -E "behavior +wander +1\.0\.0" <<<"$listing"
grep -E "behavior +flocking_plus +1\.0\.0" <<<"$listing"
"$salsa" describe wander --plugin-dir "$work/example" | grep turn_interval
# The derived behavior declares the built-in's parameters and its own.
"$salsa" describe flocking_plus --plugin-dir "$work/example" | grep separation_distance
"$salsa" describe flocking_plus --plugin-dir "$work/example" | grep migration_weight
# The installed salsa finds its own built-in plugins in <prefix>/lib/salsa/plugins.
grep -E "behavior +flocking" <<<"$listing"
# cmake --install put them in the user folder; salsa finds them there (HOME set by the test).
SALSA_PLUGIN_PATH=$user "$salsa" plugins | grep -E "^  metric +my_metric .*$user/libmy_metric.so"

# Refusals: one line each, exit status 2, nothing written.
refuse() {
  local expected=$1; shift
  set +e; said=$("$salsa" new-plugin "$@" --dir "$work/new" 2>&1); status=$?; set -e
  [ "$status" -eq 2 ] && [ "$(wc -l <<<"$said")" -eq 1 ] && grep -q -- "$expected" <<<"$said" ||
    { echo "FAIL: new-plugin $* said ($status): $said"; exit 1; }
  echo "refused: $said"
}
refuse "already exists" behavior my_behavior
refuse "not a C identifier" behavior my-behavior
refuse "not a C identifier" metric 2fast
refuse "starts with '_'" map _hidden
refuse "unknown kind 'robot'" robot r2d2
refuse "missing NAME" target
test ! -e "$work/new/my-behavior" && test ! -e "$work/new/r2d2"
echo "out_of_tree_plugin: ok"
