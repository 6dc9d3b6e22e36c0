#!/usr/bin/env bash
# Regenerates shaders/msm.hlsl from shaders/msm.glsl (tests/shaders_test.cpp checks that the
# checked-in file is what this produces).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -DINPUT=shaders/msm.glsl -DOUTPUT=shaders/msm.hlsl -P cmake/glsl_to_hlsl.cmake
