#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) in build-fuzz/ and runs each for SECONDS
# (default 60) on a copy of its seed corpus, all three side by side. Exits non-zero if the build
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

# run_one READER: one fuzzer for $seconds on a copy of its seed corpus; its log in build-fuzz/.
run_one() {
  local reader="$1" corpus="$build/corpus/$1" dict=()
  mkdir -p "$corpus"
  cp -n "$repo/tests/fuzz/corpus/$reader/"* "$corpus/" 2>/dev/null || true
  [[ -f "$repo/tests/fuzz/$reader.dict" ]] && dict=("-dict=$repo/tests/fuzz/$reader.dict")
  OMP_NUM_THREADS=1 nice -n "$niceness" "$build/tests/fuzz/fuzz_$reader" "$corpus" \
    "${dict[@]}" -max_total_time="$seconds" -max_len=8192 -rss_limit_mb=2048 -timeout=10 \
    -print_final_stats=1 -artifact_prefix="$build/artifacts/$reader-" 2>"$build/fuzz_$reader.log"
}

# The fuzzers run side by side (CURVEDSLICER_FUZZ_JOBS at most at once, default all three), each
# for the full $seconds of wall time: the run takes $seconds, not three times as long.
readers=(mesh_io plan_io cell)
slots="${CURVEDSLICER_FUZZ_JOBS:-${#readers[@]}}"
declare -A pid_of=()
status=0
report() {  # report READER EXIT-CODE
  echo "=== fuzz_$1: ${seconds} s, exit $2 ==="
  if (($2 != 0)); then
    status=1
    tail -n 40 "$build/fuzz_$1.log"
  fi
  grep -E "^stat::number_of_executed_units|^Done|^#[0-9]+ *DONE" "$build/fuzz_$1.log" || true
}
for reader in "${readers[@]}"; do
  while ((${#pid_of[@]} >= slots)); do
    wait -n || true
    for r in "${!pid_of[@]}"; do
      if ! kill -0 "${pid_of[$r]}" 2>/dev/null; then
        rc=0; wait "${pid_of[$r]}" || rc=$?
        report "$r" "$rc"; unset "pid_of[$r]"
      fi
    done
  done
  run_one "$reader" &
  pid_of[$reader]=$!
done
for r in "${!pid_of[@]}"; do
  rc=0; wait "${pid_of[$r]}" || rc=$?
  report "$r" "$rc"
done
exit "$status"
