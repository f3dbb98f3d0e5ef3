#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) in build-fuzz/ and runs each for SECONDS
# (default 60) on a copy of its seed corpus, one after the other. Exits non-zero if the build
# fails or any fuzzer finds a crash (the reproducer is left in build-fuzz/artifacts/).
# Usage: tests/fuzz/run_fuzzers.sh [SECONDS]   (CURVEDSLICER_FUZZ_BUILD_DIR overrides the folder;
# CURVEDSLICER_FUZZ_NICE=10 runs them at lower priority.)
set -euo pipefail

seconds="${1:-60}"
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${CURVEDSLICER_FUZZ_BUILD_DIR:-$repo/build-fuzz}"
niceness="${CURVEDSLICER_FUZZ_NICE:-0}"

launcher=()
command -v ccache >/dev/null 2>&1 && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
CC=clang CXX=clang++ cmake -S "$repo" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "${launcher[@]}" \
  -DCURVEDSLICER_BUILD_FUZZ=ON -DCURVEDSLICER_BUILD_TESTS=OFF -DCURVEDSLICER_BUILD_BENCH=OFF \
  -DCURVEDSLICER_BUILD_PYTHON=OFF -DCURVEDSLICER_BUILD_OCC=OFF >/dev/null
cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)" --target fuzz_mesh_io fuzz_plan_io fuzz_cell

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
mkdir -p "$build/artifacts"
status=0
for reader in mesh_io plan_io cell; do
  corpus="$build/corpus/$reader"
  mkdir -p "$corpus"
  cp -n "$repo/tests/fuzz/corpus/$reader/"* "$corpus/" 2>/dev/null || true
  dict=()
  [[ -f "$repo/tests/fuzz/$reader.dict" ]] && dict=("-dict=$repo/tests/fuzz/$reader.dict")
  echo "=== fuzz_$reader: ${seconds} s ==="
  if ! OMP_NUM_THREADS=1 nice -n "$niceness" "$build/tests/fuzz/fuzz_$reader" "$corpus" \
      "${dict[@]}" -max_total_time="$seconds" -max_len=8192 -rss_limit_mb=2048 -timeout=10 \
      -print_final_stats=1 -artifact_prefix="$build/artifacts/$reader-" 2>"$build/fuzz_$reader.log"; then
    status=1
    tail -n 40 "$build/fuzz_$reader.log"
  fi
  grep -E "^stat::number_of_executed_units|^Done|^#[0-9]+ *DONE" "$build/fuzz_$reader.log" || true
done
exit "$status"
