#!/usr/bin/env bash
# Configures the sanitizer build folder shared by scripts/ci-sanitize.sh and
# scripts/ci-fuzz.sh: clang-15, AddressSanitizer + UndefinedBehaviorSanitizer on every
# target (MSMCL_SANITIZE), the libFuzzer targets (MSMCL_BUILD_FUZZ). Usage: $0 BUILD_DIR
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B "$1" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang-15 -DCMAKE_CXX_COMPILER=clang++-15 \
  -DMSMCL_SANITIZE=address,undefined -DMSMCL_BUILD_FUZZ=ON \
  -DMSMCL_BUILD_BENCH=OFF -DMSMCL_BUILD_EXAMPLES=OFF >/dev/null
