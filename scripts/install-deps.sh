#!/usr/bin/env bash
# Installs the Debian 12 packages msmcl builds, tests and runs with (sudo when not root).
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  ocl-icd-opencl-dev opencl-c-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  libopenexr-dev libpng-dev
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev
  # Boost.Asio's thread pool (header-only) for the batch form of the CLI.
  libboost-dev
  glslang-tools
  oclgrind
  mesa-vulkan-drivers libvulkan-dev spirv-tools
  # Mesa's rusticl (RUSTICL_ENABLE=llvmpipe): the second OpenCL implementation of the ctest label `rusticl`.
  mesa-opencl-icd
  strace
  # The man page msmcl(1), generated from the CLI's --help at build time.
  help2man man-db
  # Sanitizer builds and libFuzzer (scripts/ci-sanitize.sh, scripts/ci-fuzz.sh): clang-15 below.
  libclang-common-15-dev
  assimp-testmodels
  # Plots of the bench's JSON (scripts/plot_bench.py).
  python3-matplotlib
  # The JSON Schema test of `msmcl info --json` and batch summaries (tests/json_schema_test.py);
  # the main job's page opened in a headless browser (tests/out_index_test.py).
  python3-jsonschema chromium
  # The Python module (python/, docs/python.md): pybind11 over the library, numpy arrays, pytest.
  python3-dev pybind11-dev python3-numpy python3-pytest
  # Offline GPU compiles (scripts/gpu_compile_report.py): AMDGPU and NVPTX through clang and
  # libclc; libllvm14 and libclang-cpp14 for Intel's ocloc, unpacked below.
  python3 clang-15 llvm-15 libclc-15 libclc-15-dev libllvm14 libclang-cpp14
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
    sudo_cmd=(sudo)
  fi
  echo "install-deps: installing ${missing[*]}"
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# Intel's offline compiler (ocloc, from intel-opencl-icd) unpacked into a cache folder, not
# installed: installing would register an Intel OpenCL ICD on the machine. Needs no root.
ocloc_dir=${MSMCL_OCLOC_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/msmcl/ocloc}
if [ ! -x "$ocloc_dir/usr/bin/ocloc" ]; then
  echo "install-deps: unpacking ocloc into $ocloc_dir"
  download=$(mktemp -d)
  trap 'rm -rf "$download"' EXIT
  ocloc_packages=(intel-opencl-icd libigc1 libigdfcl1 libigdgmm12 libllvmspirvlib14 libopencl-clang14)
  if ! (cd "$download" && apt-get download -qq "${ocloc_packages[@]}" 2>/dev/null); then
    # No package lists yet on this machine.
    if [ "$(id -u)" -eq 0 ]; then apt-get update -qq; else sudo apt-get update -qq; fi
    (cd "$download" && apt-get download -qq "${ocloc_packages[@]}" 2>/dev/null)
  fi
  rm -rf "$ocloc_dir.partial"
  mkdir -p "$ocloc_dir.partial"
  for deb in "$download"/*.deb; do dpkg -x "$deb" "$ocloc_dir.partial"; done
  rm -rf "$ocloc_dir"
  mv "$ocloc_dir.partial" "$ocloc_dir"
fi
