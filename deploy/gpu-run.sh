#!/usr/bin/env bash
# Runs on the GPU host, in the repository root, after deploy/gpu-bundle.sh was carried there
# (.devcarry/) with the Vulkan loader package (.gl/). Sets up the loader and the NVIDIA ICD,
# unpacks the carried scenes and points ../shared/scenes at them, then runs the given command
# with the bundle's binaries first on PATH. Usage: deploy/gpu-run.sh COMMAND...
set -euo pipefail
cd "$(dirname "$0")/.."
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
if [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
# The scenes travel packed (deploy/gpu-bundle.sh --scenes). ../shared/scenes is pointed at them
# unless it is a real folder (a checkout's own scenes, as here on a developer's machine).
if [ -f .devcarry/scenes.tar.xz ] && [ ! -d .devcarry/scenes ]; then
  tar xJf .devcarry/scenes.tar.xz -C .devcarry
fi
if [ -d .devcarry/scenes ] && { [ -L ../shared/scenes ] || [ ! -e ../shared/scenes ]; }; then
  mkdir -p ../shared && ln -sfn "$PWD/.devcarry/scenes" ../shared/scenes
fi
export PATH="$PWD/.devcarry/bin:$PATH"
export LD_LIBRARY_PATH="$PWD/.devcarry/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export DDGI_PLOT_FONT="$PWD/.devcarry/fonts/DejaVuSans.ttf"
exec "$@"
