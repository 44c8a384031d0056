#!/usr/bin/env bash
# cdbench from outside: install it into a fresh prefix; build examples/consumer (the C++ library
# through find_package(cdbench)) and run it; build examples/fcl_plugin against the same prefix, time
# it with `cdbench bench --impl plugin:...` on a certified pose set, and check that its verdicts and
# BV-test counts equal the built-in fcl-obbrss ones; a file that is not a plugin is refused.
. "$(dirname "$0")/common.sh"
build=$1
src=$2
meshes=$3
# A failed build prints its log, then its error lines again last (CI keeps only the tail).
build_failed() {
  cat "$1"
  echo "--- error lines of $1:"
  grep -n -E "error|Error|undefined reference|No space" "$1" | head -n 30 || true
  fail "$2"
}

cmake --install "$build" --prefix "$work/prefix" > /dev/null || fail "cmake --install"
cdbench="$work/prefix/bin/cdbench"
[ -f "$work/prefix/include/cdbench/plugin.h" ] || fail "plugin.h not installed"
# The float pipeline's OpenVDB module is installed and found next to the installed program
# (lib/floatpipe/grid_module.h), not in the build tree.
LD_DEBUG=files "$cdbench" poses "$meshes/sphere.off" --pipeline float --levels=0 --directions 2 --orientations 1 --grid 32 \
  -o "$work/float" > "$work/float.txt" 2>&1 || { tail -n 20 "$work/float.txt"; fail "float pipeline of the installed program"; }
grep -q "file=$work/prefix/bin/.*libcdbench_grid_vdb.so .*dynamically loaded" "$work/float.txt" ||
  { grep grid_vdb "$work/float.txt"; fail "the installed program must load the installed grid module"; }
! ldd "$cdbench" | grep -q openvdb || fail "the program must not link OpenVDB (it is loaded with the float pipeline)"
# The library: no compile flags of ours leak into the consumer (only link options).
cmake -S "$src/examples/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_EXPORT_COMPILE_COMMANDS=ON > "$work/configure.log" 2>&1 || { cat "$work/configure.log"; fail "configure the consumer"; }
cmake --build "$work/consumer" > "$work/build.log" 2>&1 || build_failed "$work/build.log" "build the consumer"
! grep -q -- "-frounding-math" "$work/consumer/compile_commands.json" || fail "our flags leak into consumers"
"$work/consumer/consumer" "$meshes/torus.off" "$meshes/sphere.off" > "$work/consumer.txt" || fail "run the consumer"
grep -q "t = (0, 0, 0): clearance in \[0.498198940110.*answer collides: false-positive" "$work/consumer.txt" \
  || { cat "$work/consumer.txt"; fail "consumer output"; }
grep -q "t = (5, 0, 0): .*answer free: ok" "$work/consumer.txt" || fail "consumer output (separated)"

logged "$work/configure.log" "configure the example plugin" \
  cmake -S "$src/examples/fcl_plugin" -B "$work/plugin" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release
cmake --build "$work/plugin" > "$work/build.log" 2>&1 || build_failed "$work/build.log" "build the example plugin"
plugin="$work/plugin/libcdbench_fcl_obbrss.so"
[ -f "$plugin" ] || fail "no plugin library"

# A small certified pose set: the box at random poses around the sphere.
python3 "$src/tests/cli/random_poses.py" "$work/poses.csv" 30 11 0.5,1.3,1.5,2.2
"$cdbench" certify "$meshes/sphere.off" "$work/poses.csv" --mover "$meshes/box.off" --tolerance 1e-4 -o "$work/set" \
  > /dev/null || fail "certify"
# FCL's and Bullet's implementations: the installed module (lib/collide/peer_module.h), found next to
# the installed program; the program itself links neither.
LD_DEBUG=files "$cdbench" bench "$work/set" --impl "fcl-obbrss,plugin:$plugin" --repeat 1 -o "$work/bench" > "$work/bench.txt" \
  2> "$work/bench_ld.txt" || { cat "$work/bench.txt"; tail -n 20 "$work/bench_ld.txt"; fail "bench with the plugin"; }
grep -q "file=$work/prefix/bin/.*libcdbench_peers.so .*dynamically loaded" "$work/bench_ld.txt" ||
  { grep peers "$work/bench_ld.txt"; fail "the installed program must load the installed peer module"; }
! ldd "$cdbench" | grep -q -E "libfcl|Bullet" || fail "the program must not link FCL or Bullet (they are loaded by bench)"
grep -q "fcl-obbrss-plugin" "$work/bench.txt" || fail "plugin not in the table"
python3 - "$work/bench/results.csv" <<'PY' || fail "plugin verdicts differ from the built-in fcl-obbrss"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
a = {r["pose"]: (r["collides"], r["verdict"], r["bv_tests"]) for r in rows if r["impl"] == "fcl-obbrss"}
b = {r["pose"]: (r["collides"], r["verdict"], r["bv_tests"]) for r in rows if r["impl"] == "fcl-obbrss-plugin"}
assert len(a) == 30 and a == b, (a, b)
PY
set +e
"$cdbench" bench "$work/set" --impl "plugin:$work/prefix/include/cdbench/plugin.h" -o "$work/x" > "$work/x.txt" 2>&1
rc=$?
set -e
[ "$rc" -eq 2 ] && grep -q "cannot be loaded" "$work/x.txt" || { cat "$work/x.txt"; fail "a non-library must be refused"; }
echo "install, consumer and plugin: all checks passed"
