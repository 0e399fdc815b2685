#!/bin/sh
# The whole test suite, as CI runs it:
#  1. g++-12, -Werror: build, then every test (unit, integration, interop with third-party peers,
#     install layout and .deb contents), then the .deb installed with dpkg, used and removed.
#  2. clang++-14, -Werror, AddressSanitizer + UndefinedBehaviorSanitizer: the unit tests and the
#     fuzz corpora again (every layer's code in memory and on loopback, without the mblab binary).
#  3. the libFuzzer targets of the same build, each run for MBLAB_FUZZ_SECONDS (default 10) on
#     its corpus.
#  4. clang-format check of every source file.
# Build trees go to build/ (the normal one, which leaves build/mblab) and build-asan/.
# The whole run is kept under 45 minutes on two cores: the builds keep line tables only (-g1:
# backtraces still name file and line), one clang build serves steps 2 and 3 (its code carries
# libFuzzer's coverage hooks, which the sanitizer runtime answers in the test binaries), and the
# sanitizer stage leaves the integration tests, which start the mblab binary and time real peers,
# to step 1.
set -eu
cd "$(dirname "$0")/.."
jobs="${MBLAB_JOBS:-$(nproc)}"
fuzz_seconds="${MBLAB_FUZZ_SECONDS:-10}"
step() { printf '\n=== %s\n' "$*"; }

step "g++-12 build (-Werror)"
CC=gcc CXX=g++ cmake -S . -B build -G Ninja -DMBLAB_WERROR=ON \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
    >/dev/null
cmake --build build -j "$jobs"
step "all tests (g++-12 build)"
ctest --test-dir build --output-on-failure -j "$jobs" --timeout 600

step ".deb from the g++-12 build: install, conform from /, remove"
if [ "$(id -u)" = 0 ]; then
    tests/install/test_install.sh build --deb-install
else
    echo "skipped: installing the .deb needs root (the layout and the package were checked above)"
fi

step "clang++-14 build with ASan+UBSan (-Werror): unit tests and libFuzzer targets"
# Unoptimised: -O0 compiles in a third of -O2's time under the sanitizers; ten seconds per fuzz
# target is a smoke run (a long campaign builds its own tree with the default RelWithDebInfo).
CC=clang-14 CXX=clang++-14 cmake -S . -B build-asan -G Ninja -DMBLAB_WERROR=ON \
    -DMBLAB_SANITIZE=ON -DMBLAB_FUZZ=ON -DMBLAB_BENCH=OFF -DCMAKE_BUILD_TYPE=Debug \
    -DCMAKE_CXX_FLAGS_DEBUG=-g1 -DCMAKE_C_FLAGS_DEBUG=-g1 >/dev/null
cmake --build build-asan -j "$jobs" --target mblab_unit_tests fuzz_all
step "unit tests and fuzz corpora under ASan+UBSan"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-asan --output-on-failure -j "$jobs" --timeout 600 \
    -L '^(mblab_[a-z]+_tests|corpus)$' -LE '^mblab_integration_tests$'

step "libFuzzer targets, ${fuzz_seconds}s each"
for target in build-asan/fuzz/fuzz_*; do
    [ -x "$target" ] || continue
    name=$(basename "$target")
    work="build-asan/corpus-work/$name"
    mkdir -p "$work"
    printf '%s: ' "$name"
    "$target" -max_total_time="$fuzz_seconds" -print_final_stats=1 "$work" "fuzz/corpus/$name" \
        >"build-asan/$name.log" 2>&1 || { cat "build-asan/$name.log"; echo "FAIL: $name"; exit 1; }
    grep -E 'stat::number_of_executed_units' "build-asan/$name.log" | awk '{print $2 " executions"}'
done

step "clang-format"
files=$(git ls-files '*.cpp' '*.hpp' '*.c' '*.h')
clang-format-14 --dry-run --Werror $files
echo
echo "all checks passed"
