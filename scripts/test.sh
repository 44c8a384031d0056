#!/usr/bin/env bash
# Installs, builds and runs the whole test suite, then every test again under
# AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/), then the fuzz targets (clang,
# build-fuzz/): the committed corpus replayed and 60 s of fuzzing per target. Exits non-zero on
# any failure.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
# ccache: hash paths relative to the checkout, so that another clone (CI) reuses the cache.
export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
bash "$root/scripts/install-deps.sh"
bash "$root/scripts/fetch-cgal-data.sh" || echo "test: CGAL data unavailable; tests that use it are skipped"
start=$(date +%s)
bash "$root/scripts/build.sh"
echo "test: release build done in $(( $(date +%s) - start )) s"
(cd "$root/build" && ctest --output-on-failure -j 2)

# Sanitizers: every test binary and the program's malformed-input tests.
gen=()
command -v ninja >/dev/null && gen=(-G Ninja)
start=$(date +%s)
# Line tables only (-g1): enough for the sanitizers' symbolized reports, and the CGAL-heavy objects
# compile about a tenth faster and link from a third of the size (-g: 51 MB for mesh_level_set.o).
cmake -S "$root" -B "$root/build-asan" "${gen[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCDBENCH_SANITIZE=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DCDBENCH_BUILD_VALIDATION=OFF >/dev/null
cmake --build "$root/build-asan" -j "$(nproc)"  # everything (validation/ is off): no test binary left unbuilt
echo "test: sanitizer build done in $(( $(date +%s) - start )) s"
(cd "$root/build-asan" && ctest --output-on-failure -j 2)

# Fuzzing: every committed input (seeds and past findings) replayed, then 60 s per target.
bash "$root/scripts/fuzz.sh" --seconds "${CDBENCH_FUZZ_SECONDS:-60}"
