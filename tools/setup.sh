#!/usr/bin/env bash
# Installs everything manylights needs on a fresh Debian 12 (bookworm) machine, as root.
# Mesa 25 lavapipe (Vulkan 1.4 with VK_EXT_mesh_shader) comes from bookworm-backports: bookworm's own
# Mesa 22 has no mesh shaders. Every other dependency is a bookworm package. Idempotent: a second run
# only checks.
set -euo pipefail

need_sudo=""
if [ "$(id -u)" != 0 ]; then
  if command -v sudo >/dev/null; then need_sudo=sudo; else
    echo "setup: must run as root (or with sudo) to install packages" >&2; exit 1
  fi
fi

. /etc/os-release
if [ "${VERSION_CODENAME:-}" != bookworm ]; then
  echo "setup: warning: written for Debian 12 (bookworm), this is ${PRETTY_NAME:-unknown}" >&2
fi

PKGS=(build-essential cmake pkg-config git
      libvulkan-dev vulkan-validationlayers mesa-vulkan-drivers vulkan-tools
      glslang-tools spirv-tools
      libglfw3-dev libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libmeshoptimizer-dev
      libgtest-dev libgmock-dev libembree-dev
      xvfb xauth xdotool gnuplot-nox clang-format python3)

BACKPORTS=/etc/apt/sources.list.d/manylights-bookworm-backports.list
stamp=/var/lib/manylights-setup.ok
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "${PKGS[*]}" ]; then
  echo "setup: packages already installed (remove $stamp to force)"
  exit 0
fi

if [ ! -f "$BACKPORTS" ] && ! grep -rqs 'bookworm-backports' /etc/apt/sources.list /etc/apt/sources.list.d/; then
  echo "setup: adding bookworm-backports"
  echo "deb http://deb.debian.org/debian bookworm-backports main" | $need_sudo tee "$BACKPORTS" >/dev/null
fi
export DEBIAN_FRONTEND=noninteractive
echo "setup: apt-get update"
$need_sudo apt-get update -qq
# Mesa (lavapipe) from backports; the rest (loader 1.3.239, layers, glslang 12) from bookworm.
# Only Mesa is newer there; -t lets apt pull the backported libdrm/LLVM it depends on.
BP=(mesa-vulkan-drivers)
echo "setup: installing from bookworm-backports: ${BP[*]}"
$need_sudo apt-get install -y -qq -t bookworm-backports "${BP[@]}" >/dev/null
echo "setup: installing: ${PKGS[*]}"
$need_sudo apt-get install -y -qq "${PKGS[@]}" >/dev/null
echo "${PKGS[*]}" | $need_sudo tee "$stamp" >/dev/null
echo "setup: done"
