#!/usr/bin/env bash
# The main job: builds msmcl, then filters the sample shadow maps into every format and
# shades the sample views with them, writing EXR textures, shadow EXRs and PNG previews
# into out/ (or $MSMCL_OUT). Uses the default OpenCL device (PoCL on a CPU-only machine).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
bash scripts/install-deps.sh
build=${MSMCL_BUILD_DIR:-build}
out=${MSMCL_OUT:-$root/out}
jobs=$(nproc 2>/dev/null || echo 2)

# Build the CLI and the sample-data tools; generate the larger sample scenes (1024^2).
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" -j"$jobs" --target msmcl_cli msmcl-scene msmcl-rasterize msmcl-preview
cmake --build "$build" --target msmcl_sample_data
msmcl=$build/msmcl
tools=$build/data
mkdir -p "$out"
"$msmcl" devices

# Shipped 256^2 maps and the generated 1024^2 ones, each with its view's receivers.
scenes=(
  "railing_256:$root/data/railing_256x256_4x.exr:$root/data/railing_view_160x120.exr:"
  "wuson_256:$root/data/wuson_256x256_4x.exr:$root/data/wuson_view_160x120.exr:"
  "railing_1024:$tools/railing_1024x1024_8x.exr:$tools/railing_view_640x480.exr:$tools/railing_view_640x480_lighting.exr"
  "wuson_1024:$tools/wuson_1024x1024_4x.exr:$tools/wuson_view_640x480.exr:$tools/wuson_view_640x480_lighting.exr"
)
for entry in "${scenes[@]}"; do
  IFS=: read -r name depth receivers lighting <<<"$entry"
  for format in moments128 msm64 nlq64 nlq32; do
    "$msmcl" filter "$depth" "$out/${name}_${format}.exr" --format "$format"
    for lookup in bilinear nearest; do
      shadow=$out/${name}_${format}_${lookup}_shadow.exr
      "$msmcl" shade "$out/${name}_${format}.exr" "$receivers" "$shadow" --lookup "$lookup"
      # Preview: the shadow intensity, lit by the view's shading where the scene provides it.
      if [ -n "$lighting" ]; then
        "$tools/msmcl-preview" "$shadow" "${shadow%_shadow.exr}.png" --lighting "$lighting"
      else
        "$tools/msmcl-preview" "$shadow" "${shadow%_shadow.exr}.png" --black 1 --white 0
      fi
    done
  done
done
# Soft shadows: a summed-area table of the moments, then moment soft shadow mapping with a
# directional light of finite size (contact hardening at the railing posts, at Wuson's feet).
for entry in "${scenes[@]}"; do
  IFS=: read -r name depth receivers lighting <<<"$entry"
  case $name in
    *_256) max_kernel=729; light_size=40 ;;
    *) max_kernel=4096; light_size=60 ;;
  esac
  "$msmcl" sat "$depth" "$out/${name}_sat.exr" --max-kernel "$max_kernel"
  "$msmcl" soft "$out/${name}_sat.exr" "$receivers" "$out/${name}_soft_shadow.exr" --light-size "$light_size" --depth-bias 0.02
  if [ -n "$lighting" ]; then
    "$tools/msmcl-preview" "$out/${name}_soft_shadow.exr" "$out/${name}_soft.png" --lighting "$lighting"
  else
    "$tools/msmcl-preview" "$out/${name}_soft_shadow.exr" "$out/${name}_soft.png" --black 1 --white 0
  fi
done

echo "main job: textures, shadows and previews in $out"
ls "$out"/*.png | sed 's/^/  /'
