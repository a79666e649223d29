#!/usr/bin/env bash
# Builds what runs on a GPU host without our libraries (the lent H100/H200, a lean container):
# Release binaries, their SPIR-V, and the non-glibc part of their shared-library closure,
# into .devcarry/ (ignored by git). With --scenes, also packs ../shared/scenes beside it
# (.devcarry/scenes.tar.xz), since only the repository travels. Usage: deploy/gpu-bundle.sh [--scenes] [targets...]
set -euo pipefail
cd "$(dirname "$0")/.."
with_scenes=0
if [ "${1:-}" = "--scenes" ]; then with_scenes=1; shift; fi
targets=("${@:-ddgi-render ddgi-bench}")
# Client tools are configured too, so ddgi-client-lean (no OpenImageIO) can be bundled.
cmake -S . -B build-rel -G Ninja -DCMAKE_BUILD_TYPE=Release -DDDGI_BUILD_TESTS=OFF \
  -DDDGI_BUILD_CLIENT=ON >/dev/null
# shellcheck disable=SC2068
ninja -C build-rel ${targets[@]}
rm -rf .devcarry/bin .devcarry/lib
mkdir -p .devcarry/bin .devcarry/lib
# shellcheck disable=SC2068
for t in ${targets[@]}; do cp build-rel/"$t" .devcarry/bin/; done
strip .devcarry/bin/ddgi-*
cp -r build-rel/spirv .devcarry/bin/spirv
rm -f .devcarry/bin/spirv/*.d
# glibc itself comes from the host (newer there); everything else travels.
for bin in .devcarry/bin/ddgi-*; do
  ldd "$bin" | awk '/=> \//{print $3}'
done | sort -u | grep -vE '/(libc|libm|libpthread|libdl|librt|ld-linux-x86-64|libresolv)\.so' |
  while read -r lib; do cp -L "$lib" .devcarry/lib/; done
# The plots' font (server/tools/plot_raster.h): the GPU host may have none.
mkdir -p .devcarry/fonts && cp /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf .devcarry/fonts/
if [ "$with_scenes" = 1 ]; then
  # Packed: what a device call carries must stay under 64 MiB. deploy/gpu-run.sh unpacks it.
  rm -rf .devcarry/scenes .devcarry/scenes.tar.xz
  tar cJf .devcarry/scenes.tar.xz -C ../shared scenes
fi
du -sh .devcarry/bin .devcarry/lib .devcarry/scenes.tar.xz 2>/dev/null || true
