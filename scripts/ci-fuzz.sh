#!/usr/bin/env bash
# Fuzz stage: builds the libFuzzer targets of the file readers (fuzz/; clang-15 with
# AddressSanitizer and UndefinedBehaviorSanitizer, in the sanitizer build folder), runs
# each once over its seed corpus and every kept regression input, then fuzzes each for
# MSMCL_FUZZ_SECONDS (default 30) seconds. Any crash, sanitizer finding, leak, timeout
# (10 s per input) or allocation over 2 GiB fails the stage; the input that did it is
# written to <build>/fuzz-findings/<target>/: add it to fuzz/regressions/<target>/ with
# the fix.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
build_dir=${MSMCL_SANITIZE_BUILD_DIR:-build-sanitize}
seconds=${MSMCL_FUZZ_SECONDS:-30}
targets=(depth_exr receivers_exr texture_exr ktx2 dds scene_json batch_list)

bash scripts/configure-sanitize.sh "$build_dir"
cmake --build "$build_dir" --target msmcl_fuzz -j"$(nproc 2>/dev/null || echo 2)"

# Image limits of 16 MiB: the inputs are at most 64 KiB, and every allocation stays small
# enough for thousands of runs a second.
export MSMCL_MAX_BYTES=$((16 << 20))
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
options=(-rss_limit_mb=2048 -timeout=10 -max_len=65536 -print_final_stats=0)
for target in "${targets[@]}"; do
  binary="$build_dir/fuzz/msmcl_fuzz_$target"
  findings="$build_dir/fuzz-findings/$target"
  work="$build_dir/fuzz-corpus/$target" # new inputs go here, not into the repository
  mkdir -p "$findings" "$work"
  inputs=(fuzz/corpus/"$target")
  [ -d fuzz/regressions/"$target" ] && inputs+=(fuzz/regressions/"$target")
  echo "ci-fuzz: $target: seeds and regressions"
  "$binary" "${options[@]}" -runs=0 -artifact_prefix="$findings/" "${inputs[@]}"
  echo "ci-fuzz: $target: ${seconds} s of fuzzing"
  "$binary" "${options[@]}" -max_total_time="$seconds" -artifact_prefix="$findings/" "$work" "${inputs[@]}"
done
echo "ci-fuzz: no findings"
