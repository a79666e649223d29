#!/usr/bin/env bash
# Runs on the GPU host, in the repository root, after deploy/gpu-bundle.sh was carried there
# (.devcarry/) with the Vulkan loader package (.gl/). Sets up the loader and the NVIDIA ICD,
# points ../shared/scenes at the carried scenes, then runs the given command with the bundle's
# binaries first on PATH. Usage: deploy/gpu-run.sh COMMAND...
set -euo pipefail
cd "$(dirname "$0")/.."
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
if [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
if [ -d .devcarry/scenes ] && [ ! -e ../shared/scenes ]; then
  mkdir -p ../shared && ln -s "$PWD/.devcarry/scenes" ../shared/scenes
fi
export PATH="$PWD/.devcarry/bin:$PATH"
export LD_LIBRARY_PATH="$PWD/.devcarry/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export DDGI_PLOT_FONT="$PWD/.devcarry/fonts/DejaVuSans.ttf"
exec "$@"
