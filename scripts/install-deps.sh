#!/usr/bin/env bash
# Installs the Debian 12 packages leanfade needs, only those missing. Idempotent.
# Uses sudo only when not root. Set LEANFADE_EXTRA_PACKAGES to add more.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libglm-dev libpng-dev libtinyexr-dev libstb-dev libcli11-dev nlohmann-json3-dev
  libtinyobjloader-dev libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libgbm1
  libglfw3-dev libimgui-dev glslang-tools xvfb xauth libglx-mesa0 gnuplot-nox
  libgtest-dev libgmock-dev libbenchmark-dev
  libopenimageio-dev libtinygltf-dev spirv-cross libspirv-cross-c-shared-dev glslang-dev
  spirv-tools mesa-vulkan-drivers libvulkan-dev vulkan-validationlayers
)
# shellcheck disable=SC2206
packages+=(${LEANFADE_EXTRA_PACKAGES:-})

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
