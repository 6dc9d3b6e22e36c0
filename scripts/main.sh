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
cmake --build "$build" -j"$jobs" --target msmcl_cli msmcl-scene msmcl-rasterize msmcl-preview msmcl-scatter-scene
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

# Single scattering: light shafts through the openings of two sample scenes, from the
# prefiltered 4- and 6-moment maps, and 128-sample ray marching of the hard shadow map.
for entry in hall:0.3 pergola:1.5; do
  IFS=: read -r name white <<<"$entry"
  "$tools/msmcl-scatter-scene" "$root/data/scatter/$name.json" --map-size 1024 --camera-width 640 --camera-height 480 \
    --rectified-size 1024 --write-scene "$out/${name}_scene.json" --shadow-map "$out/${name}_shadow.exr" \
    --camera-depth "$out/${name}_camera.exr"
  for moments in 4 6; do
    "$msmcl" scatter "$out/${name}_scene.json" "$out/${name}_shadow.exr" "$out/${name}_camera.exr" \
      "$out/${name}_scatter${moments}.exr" --moments "$moments"
    "$tools/msmcl-preview" "$out/${name}_scatter${moments}.exr" "$out/${name}_scatter${moments}.png" --white "$white"
  done
  "$msmcl" scatter "$out/${name}_scene.json" "$out/${name}_shadow.exr" "$out/${name}_camera.exr" \
    "$out/${name}_marched128.exr" --ray-march 128
  "$tools/msmcl-preview" "$out/${name}_marched128.exr" "$out/${name}_marched128.png" --white "$white"
done

echo "main job: textures, shadows and previews in $out"
ls "$out"/*.png | sed 's/^/  /'
