#!/usr/bin/env bash
# Builds msmcl and runs the whole test suite on the default OpenCL device (PoCL in CI).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
build_dir=${MSMCL_BUILD_DIR:-build}
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j"$jobs"
# Every test, the Oclgrind label (`ctest -L oclgrind`) included.
ctest --test-dir "$build_dir" --output-on-failure -j"$jobs"
