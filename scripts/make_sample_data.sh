#!/bin/sh
# Regenerates the small sample data committed in data/ and, with --previews, shaded PNG
# previews of them (needs an OpenCL device). Usage:
#   scripts/make_sample_data.sh [BUILD_DIR] [--previews]
# BUILD_DIR (default: build) must hold the built msmcl and tools/msmcl-* tools.
# Larger data sets: cmake --build BUILD_DIR --target msmcl_sample_data
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
previews=${2:-}
tools=$build/tools
data=$root/data

# Railing scene and Wuson: 256^2 shadow maps with 4x MSAA, 160x120 views.
"$tools/msmcl-scene" --width 256 --samples 4 --depth "$data/railing_256x256_4x.exr" \
  --view-width 160 --view-height 120 --receivers "$data/railing_view_160x120.exr"
"$tools/msmcl-rasterize" --width 256 --samples 4 --depth "$data/wuson_256x256_4x.exr" \
  --view-width 160 --view-height 120 --receivers "$data/wuson_view_160x120.exr"
ls -l "$data"/*.exr

if [ "$previews" = "--previews" ]; then
  out=$build/data/previews
  mkdir -p "$out"
  for scene in railing wuson; do
    if [ $scene = railing ]; then tool=msmcl-scene; else tool=msmcl-rasterize; fi
    "$tools/$tool" --width 256 --samples 4 --depth "$out/${scene}_depth.exr" \
      --view-width 160 --view-height 120 --lighting "$out/${scene}_lighting.exr" \
      --hard-preview "$out/${scene}_hard.png"
    for format in moments128 msm64 nlq64 nlq32; do
      "$build/msmcl" filter "$data/${scene}_256x256_4x.exr" "$out/${scene}_$format.exr" --format $format
      "$build/msmcl" shade "$out/${scene}_$format.exr" "$data/${scene}_view_160x120.exr" "$out/${scene}_${format}_y.exr"
      "$tools/msmcl-preview" "$out/${scene}_${format}_y.exr" "$out/${scene}_$format.png" \
        --lighting "$out/${scene}_lighting.exr"
    done
  done
  echo "previews in $out"
fi
