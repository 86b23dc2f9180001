#!/usr/bin/env bash
# Runs each libFuzzer target (tests/fuzz/) for SECONDS (default 60), one
# after the other, single process (-jobs=1: 2 cores are shared), and prints
# each one's executions per second and corpus size.
#   scripts/fuzz.sh [SECONDS] [TARGET...]   targets: svo_load mesh_arrays mesh_file camera texture merl
#                                            environment material scene_file
#                                            (also: luminaire tm25 gltf vdb, by name)
# Installs what it needs (scripts/setup.sh's packages, clang and
# libclang-rt-14-dev). Builds a Clang tree with AddressSanitizer + UndefinedBehaviorSanitizer and
# coverage (-fsanitize=fuzzer) in FUZZ_DIR (default build-fuzz). The corpus
# of each target lives in FUZZ_DIR/fuzz/<target>/corpus (seeded by
# svo_fuzz_seeds, kept between runs); crashing inputs go to
# FUZZ_DIR/fuzz/<target>/artifacts/, the full log to .../log.txt. Exit 1 if
# any target found a crash, a leak, a timeout (FUZZ_TIMEOUT seconds, default 10;
# raise it on a machine loaded by other work, where an input that runs in
# 0.2 s alone can take longer), one allocation over 1.5 GiB (not vdb: see
# below) or an out-of-memory (RSS over 3 GiB).
# A finding becomes a regression test: tests/fuzz/regressions/<target>/.
# FUZZ_SKIP_BUILD=1 skips setup and build (for runs in parallel over a
# tree built already: FUZZ_SKIP_BUILD=1 scripts/fuzz.sh 1800 merl & ...).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
FUZZ_DIR="${FUZZ_DIR:-$ROOT/build-fuzz}"
SECONDS_EACH="${1:-60}"
shift || true
TARGETS=("$@")
if ((${#TARGETS[@]} == 0)); then TARGETS=(svo_load mesh_arrays mesh_file camera texture merl environment material scene_file); fi

# The libraries (scripts/setup.sh), then Clang with libFuzzer, which only
# fuzzing needs.
if [ "${FUZZ_SKIP_BUILD:-0}" != 1 ]; then
  "$ROOT/scripts/setup.sh" > /dev/null
  source "$ROOT/scripts/bench_common.sh"
  need_packages clang libclang-rt-14-dev

  if [ ! -f "$FUZZ_DIR/build.ninja" ]; then
    CC=clang CXX=clang++ cmake -S "$ROOT" -B "$FUZZ_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSVO_SANITIZE=ON \
      -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG"
  fi
  cmake --build "$FUZZ_DIR" -j2 --target svo_fuzz_seeds "${TARGETS[@]/#/svo_fuzz_}"

  "$FUZZ_DIR/tests/fuzz/svo_fuzz_seeds" "$FUZZ_DIR/fuzz/seeds" > /dev/null
fi
status=0
for t in "${TARGETS[@]}"; do
  dir="$FUZZ_DIR/fuzz/$t"
  mkdir -p "$dir/corpus" "$dir/artifacts"
  cp -n "$FUZZ_DIR/fuzz/seeds/$t/"* "$dir/corpus/" 2>/dev/null || true
  echo "fuzz: $t for ${SECONDS_EACH} s"
  rc=0
  # OpenVDB allocates a compressed block's size as the file states it
  # (io::bloscFromStream): a release build gets std::bad_alloc, which
  # load_vdb reports as one line. Under ASan malloc must return null for
  # that (tests/fuzz/allocation_cap.cpp then throws), and libFuzzer must not
  # count one large malloc as a finding.
  asan_extra="" fuzz_extra=()
  if [ "$t" = vdb ]; then asan_extra=":allocator_may_return_null=1" fuzz_extra=(-malloc_limit_mb=1048576); fi
  # An image's pixels are bounded by the budgets (at most 1 GiB of floats
  # for a texture); one allocation beyond that is a finding, which the
  # default limit (the RSS limit, 3 GiB) let pass: OpenEXR's 1.85 GB string
  # of a 358-byte map (2026-12-05) was seen only as the run's peak RSS.
  # Every other target too: no input of a few kilobytes may need 1.5 GiB
  # in one allocation under the budgets.
  if [ "$t" != vdb ]; then fuzz_extra=(-malloc_limit_mb=1536); fi
  ASAN_OPTIONS="detect_leaks=1:abort_on_error=1$asan_extra" LSAN_OPTIONS="suppressions=$ROOT/tests/lsan.supp" \
    UBSAN_OPTIONS=print_stacktrace=1 \
    "$FUZZ_DIR/tests/fuzz/svo_fuzz_$t" -max_total_time="$SECONDS_EACH" -timeout="${FUZZ_TIMEOUT:-10}" -rss_limit_mb=3072 \
    "${fuzz_extra[@]}" -print_final_stats=1 -artifact_prefix="$dir/artifacts/" "$dir/corpus" > "$dir/log.txt" 2>&1 || rc=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log.txt" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$dir/log.txt" | tail -1)
  files=$(find "$dir/corpus" -type f | wc -l)
  bytes=$(du -sb "$dir/corpus" | cut -f1)
  cov=$(grep -o 'cov: [0-9]*' "$dir/log.txt" | tail -1 || true)
  if [ "$rc" = 0 ]; then
    echo "fuzz: $t: no finding; ${runs:-?} runs, ${rate:-?} exec/s, corpus $files files ($bytes bytes), $cov"
  else
    echo "fuzz: $t: FINDING (exit $rc), input in $dir/artifacts/, log $dir/log.txt"
    grep -m3 -E 'ERROR|SUMMARY|contract broken' "$dir/log.txt" || true
    status=1
  fi
done
exit $status
