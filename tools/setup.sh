#!/usr/bin/env bash
# Installs everything PointGauss needs to build and test, from Debian 12's packages.
set -euo pipefail
pkgs=(build-essential cmake ninja-build pkg-config
      libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools spirv-tools
      libglfw3-dev libglm-dev libimgui-dev catch2 libstb-dev nlohmann-json3-dev
      libcli11-dev libeigen3-dev zlib1g-dev libwebp-dev libzip-dev xvfb xauth)
missing=()
for p in "${pkgs[@]}"; do dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p"); done
if ((${#missing[@]})); then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
