#!/usr/bin/env bash
# Installs every build and test dependency on a fresh Debian 12 (bookworm) machine.
# Mesa's lavapipe with ray queries and ray-tracing pipelines needs Mesa >= 24.1, which
# bookworm only has in its backports suite; everything else comes from bookworm itself.
set -euo pipefail

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
  echo "deb http://deb.debian.org/debian bookworm-backports main" |
    $SUDO tee /etc/apt/sources.list.d/bookworm-backports.list >/dev/null
fi

export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q

$SUDO apt-get install -y -q --no-install-recommends \
  build-essential cmake ninja-build pkg-config git ca-certificates python3 \
  clang libclang-rt-14-dev clang-format \
  libvulkan-dev vulkan-validationlayers glslang-tools spirv-tools \
  libglm-dev \
  libgrpc++-dev protobuf-compiler protobuf-compiler-grpc libprotobuf-dev \
  libtinygltf-dev nlohmann-json3-dev libstb-dev fonts-dejavu-core \
  libturbojpeg0-dev libjpeg62-turbo-dev \
  libopenexr-dev \
  libcivetweb-dev \
  libopenimageio-dev \
  libgtest-dev \
  libsdl2-dev \
  xvfb xauth

$SUDO apt-get install -y -q --no-install-recommends -t bookworm-backports mesa-vulkan-drivers

# The web client's browser tests (tests/web): Debian's chromium, headless, and Node.js with npm
# for puppeteer-core (Debian's when the machine has none of its own).
$SUDO apt-get install -y -q --no-install-recommends chromium
if ! command -v npm >/dev/null; then
  $SUDO apt-get install -y -q --no-install-recommends nodejs npm
fi

echo "dependencies installed"
