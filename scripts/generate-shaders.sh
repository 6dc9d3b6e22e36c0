#!/usr/bin/env bash
# Writes msm.glsl and msm.hlsl into FOLDER without building
# msmcl, for engines that copy the shaders into their own tree: the texture-fetch wrappers of
# shaders/msm.glsl.in around the device functions of kernels/*.clh (needs python3, cpp and
# cmake; the build does the same into <build>/shaders, and installs them).
# Usage: scripts/generate-shaders.sh FOLDER
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: scripts/generate-shaders.sh FOLDER" >&2; exit 2; }
root="$(cd "$(dirname "$0")/.." && pwd)"
out="$(mkdir -p "$1" && cd "$1" && pwd)"
python3 "$root/shaders/generate_glsl.py" --kernels "$root/kernels" --template "$root/shaders/msm.glsl.in" \
  --output "$out/msm.glsl"
cmake -DINPUT="$out/msm.glsl" -DOUTPUT="$out/msm.hlsl" -P "$root/cmake/glsl_to_hlsl.cmake"
echo "generate-shaders: wrote $out/msm.glsl and $out/msm.hlsl"
