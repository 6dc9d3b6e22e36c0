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
cmake --build "$build" -j"$jobs" --target msmcl_cli msmcl-scene msmcl-rasterize msmcl-preview msmcl-lookup-preview msmcl-signed-difference msmcl-soft-truth msmcl-scatter-scene msmcl-quality msmcl-scatter-quality msmcl-vulkan
cmake --build "$build" --target msmcl_sample_data
msmcl=$build/msmcl
tools=$build/tools
generated=$build/data # the 1024^2 sample scenes msmcl_sample_data writes
mkdir -p "$out"
"$msmcl" devices

# Shipped 256^2 maps and the generated 1024^2 ones, each with its view's receivers.
scenes=(
  "railing_256:$root/data/railing_256x256_4x.exr:$root/data/railing_view_160x120.exr:"
  "wuson_256:$root/data/wuson_256x256_4x.exr:$root/data/wuson_view_160x120.exr:"
  "railing_1024:$generated/railing_1024x1024_8x.exr:$generated/railing_view_640x480.exr:$generated/railing_view_640x480_lighting.exr"
  "wuson_1024:$generated/wuson_1024x1024_4x.exr:$generated/wuson_view_640x480.exr:$generated/wuson_view_640x480_lighting.exr"
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
# The same textures in a renderer: the railing view's shadow from the nlq32 and msm64 KTX2
# files, uploaded into Vulkan images and shaded by msm.glsl (docs/shaders.md) on the Vulkan device
# (lavapipe on a CPU-only machine), beside the OpenCL PNG, and the signed difference
# Vulkan - OpenCL over a dimmed copy of the OpenCL shadow (red: Vulkan darker, blue:
# lighter; full colour at 1e-6 for nlq32, the same float32 math, and at 1e-4 for msm64,
# where the shader's float32 4MSM meets the kernel's float-float one; the labelled bar of
# tools/signed_difference.hpp below). Their figures go to vulkan_vs_opencl.txt.
vulkan=$build/examples/vulkan/msmcl-vulkan
: >"$out/vulkan_vs_opencl.txt"
for entry in nlq32:1e-6 msm64:1e-4; do
  IFS=: read -r format diff_scale <<<"$entry"
  base=$out/railing_1024_${format}_bilinear
  "$msmcl" filter "$generated/railing_1024x1024_8x.exr" "$out/railing_1024_${format}.ktx2" --format "$format"
  "$vulkan" shade "$out/railing_1024_${format}.ktx2" "$generated/railing_view_640x480.exr" "${base}_vulkan_shadow.exr" --lookup bilinear
  "$tools/msmcl-preview" "${base}_vulkan_shadow.exr" "${base}_vulkan.png" --lighting "$generated/railing_view_640x480_lighting.exr"
  echo -n "railing_1024 $format bilinear, Vulkan - OpenCL: " >>"$out/vulkan_vs_opencl.txt"
  "$vulkan" compare "${base}_shadow.exr" "${base}_vulkan_shadow.exr" --diff-png "${base}_vulkan_diff.png" \
    --diff-scale "$diff_scale" >>"$out/vulkan_vs_opencl.txt"
done
cat "$out/vulkan_vs_opencl.txt"

# Soft shadows: a summed-area table of the moments, then moment soft shadow mapping with a
# directional light of finite size (contact hardening at the railing posts, at Wuson's feet),
# with the library's refinements (<scene>_soft.png) and as published (<scene>_soft_published.png);
# beside them brute-force PCSS in double precision with the same search square, light size,
# depth bias and filter clamp (<scene>_soft_pcss.png), and the signed differences from it
# (<scene>_soft_diff_pm0.5.png, <scene>_soft_published_diff_pm0.5.png: red lighter than
# PCSS, blue darker, full colour at +-0.5; tools/signed_difference.hpp). Their statistics go
# to soft_vs_pcss.txt.
: >"$out/soft_vs_pcss.txt"
preview() { # EXR PNG LIGHTING: the shadow intensity, lit by the view's shading where there is one
  if [ -n "$3" ]; then "$tools/msmcl-preview" "$1" "$2" --lighting "$3"; else "$tools/msmcl-preview" "$1" "$2" --black 1 --white 0; fi
}
for entry in "${scenes[@]}"; do
  IFS=: read -r name depth receivers lighting <<<"$entry"
  case $name in
    *_256) max_kernel=729; light_size=40 ;;
    *) max_kernel=4096; light_size=60 ;;
  esac
  light=(--light-size "$light_size" --depth-bias 0.02)
  "$msmcl" sat "$depth" "$out/${name}_sat.exr" --max-kernel "$max_kernel"
  "$msmcl" soft "$out/${name}_sat.exr" "$receivers" "$out/${name}_soft_shadow.exr" "${light[@]}"
  "$msmcl" soft "$out/${name}_sat.exr" "$receivers" "$out/${name}_soft_published_shadow.exr" "${light[@]}" --published
  "$tools/msmcl-soft-truth" pcss "$depth" "$receivers" "$out/${name}_soft_pcss_shadow.exr" "${light[@]}" --max-kernel "$max_kernel"
  for method in soft soft_published soft_pcss; do
    preview "$out/${name}_${method}_shadow.exr" "$out/${name}_${method}.png" "$lighting"
  done
  for method in soft soft_published; do
    echo -n "$name $method vs PCSS: " >>"$out/soft_vs_pcss.txt"
    "$tools/msmcl-signed-difference" "$out/${name}_${method}_shadow.exr" "$out/${name}_soft_pcss_shadow.exr" \
      "$out/${name}_${method}_diff_pm0.5.png" --range 0.5 >>"$out/soft_vs_pcss.txt"
  done
done
cat "$out/soft_vs_pcss.txt"
# The before/after figures of docs/soft_shadows.md (matplotlib; Debian's python3).
python=python3
"$python" -c 'import matplotlib' 2>/dev/null || python=/usr/bin/python3
"$python" scripts/soft_figure.py "$out" railing_1024 "$out/railing_1024_soft_vs_pcss.png" --crop 40,150,600,400
"$python" scripts/soft_figure.py "$out" wuson_1024 "$out/wuson_1024_soft_vs_pcss.png"

# Blue-noise dithering of nlq64 seen magnified (256^2 map, 640x480 view): nearest | bilinear | dither | mean of 64 frames.
"$tools/msmcl-scene" --width 256 --samples 4 --depth "$out/railing_256_depth.exr" \
  --view-width 640 --view-height 480 --receivers "$out/railing_256_view_640x480.exr" \
  --lighting "$out/railing_256_view_640x480_lighting.exr"
"$msmcl" filter "$out/railing_256_depth.exr" "$out/railing_256_closeup_nlq64.exr" --format nlq64
"$tools/msmcl-lookup-preview" "$out/railing_256_closeup_nlq64.exr" "$out/railing_256_view_640x480.exr" \
  "$out/railing_256_nlq64_lookups.png" --lighting "$out/railing_256_view_640x480_lighting.exr" \
  --crop 200,150,240,160 --zoom 2 --frames 64
# Translucent occluders: a smoke plume (8 planes facing the light) in front of the banner.
"$tools/msmcl-scene" --width 1024 --samples 4 --smoke 8 --depth "$out/smoke_1024x1024_4x.exr" \
  --view-width 640 --view-height 480 --receivers "$out/smoke_view_640x480.exr" \
  --lighting "$out/smoke_view_640x480_lighting.exr" --hard-preview "$out/smoke_1024_hard.png"
for format in moments128 nlq64; do
  "$msmcl" filter "$out/smoke_1024x1024_4x.exr" "$out/smoke_1024_${format}.exr" --format "$format"
  "$msmcl" shade "$out/smoke_1024_${format}.exr" "$out/smoke_view_640x480.exr" "$out/smoke_1024_${format}_shadow.exr"
  "$tools/msmcl-preview" "$out/smoke_1024_${format}_shadow.exr" "$out/smoke_1024_${format}.png" \
    --lighting "$out/smoke_view_640x480_lighting.exr"
done
"$msmcl" sat "$out/smoke_1024x1024_4x.exr" "$out/smoke_1024_sat.exr" --max-kernel 4096
"$msmcl" soft "$out/smoke_1024_sat.exr" "$out/smoke_view_640x480.exr" "$out/smoke_1024_soft_shadow.exr" --light-size 60 --depth-bias 0.02
"$tools/msmcl-preview" "$out/smoke_1024_soft_shadow.exr" "$out/smoke_1024_soft.png" --lighting "$out/smoke_view_640x480_lighting.exr"

# Single scattering: light shafts through the openings of two sample scenes, from the
# prefiltered 4- and 6-moment maps, and 128-sample ray marching of the hard shadow map.
: >"$out/scatter_vs_marched.txt"
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
  # Against 1024-sample ray marching (double precision, all cores): the signed difference of
  # the lit fraction of each view ray, red lighter / blue darker than the truth, full colour
  # at +-0.1 (colour map and legend: tools/signed_difference.hpp).
  "$build/bench/msmcl-scatter-quality" compare "$out/${name}_scene.json" "$out/${name}_shadow.exr" \
    "$out/${name}_camera.exr" --steps 1024 --range 0.1 --truth "$out/${name}_marched1024.exr" \
    "$out/${name}_scatter6.exr:$out/${name}_scatter6_diff.png" "$out/${name}_scatter4.exr:$out/${name}_scatter4_diff.png" \
    | tee -a "$out/scatter_vs_marched.txt"
  "$tools/msmcl-preview" "$out/${name}_marched1024.exr" "$out/${name}_marched1024.png" --white "$white"
  # The truth, both moment counts and their differences in one figure with a numbered legend.
  "$python" scripts/scatter_figure.py "$out" "$name" "$out/${name}_scatter_vs_marched.png"
done

# The quality table on the 1024^2 scenes: every filter format (moments, VSM, EVSM, ESM; EVSM
# also with light-bleed reduction 0.15) against 128-bit moments and
# the PCF ground truth, with shadow and error images (out/quality/).
"$build/bench/msmcl-quality" --large --out "$out/quality" --json "$out/quality/quality.json" > "$out/quality.md"
# One figure per view: every representation by bits per texel, its signed difference from
# the PCF truth below, the banner leak in the titles (docs/representations.md).
for name in railing wuson; do
  "$python" scripts/quality_figure.py "$out/quality" "$out/quality/quality.json" "$name" \
    "$out/${name}_1024_representations.png"
done

# The Python module (docs/python.md): the railing map in every format against 128-bit
# moments, from a few lines of Python; built where CMake found Python 3, numpy and pybind11.
if [ -x "$build/python/python" ]; then
  cmake --build "$build" -j"$jobs" --target msmcl_python
  "$build/python/python" examples/python/compare_formats.py | tee "$out/compare_formats.txt"
fi

# The page that shows it all: every image with its caption, the quality table and the advice
# on which format to use (scripts/out_index.py), then checked in headless Chromium: every
# image decodes, every link resolves (tests/out_index_test.py; skipped without chromium).
"$python" scripts/out_index.py "$out" --check
/usr/bin/python3 tests/out_index_test.py --out "$out" || [ $? -eq 77 ]

echo "main job: textures, shadows and previews in $out, to read: $out/index.html"
ls "$out"/*.png | sed 's/^/  /'
