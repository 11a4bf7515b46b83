#!/usr/bin/env bash
# Installs everything vsculpt needs to build and test on Debian 12 (bookworm).
# Idempotent: apt-get skips packages that are already installed.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  # core: OpenVDB (its CMake config also needs Boost.Iostreams), oneTBB, GLM
  libopenvdb-dev libboost-iostreams-dev libtbb-dev libglm-dev
  # configs, CLI, logging
  nlohmann-json3-dev libcli11-dev libspdlog-dev libfmt-dev
  # exports (glTF writer), journal checksums, and the third-party loader the tests read
  # exports back with
  libtinygltf-dev zlib1g-dev libassimp-dev
  # rendering: GLFW window and GL context, GL loader, PNG screenshots; Xvfb + Mesa (llvmpipe)
  # give tests a real GL context on machines without a GPU
  libglfw3-dev libepoxy-dev libpng-dev xvfb xauth libgl1-mesa-dri
  # OpenXR headsets (docs/xr.md): the Khronos loader and headers; Xlib and GL headers for the
  # GLX graphics binding and the tests' scripted runtime; the core validation layer the XR
  # tests run under
  libopenxr-dev libopenxr-loader1 openxr-layer-corevalidation libx11-dev libgl-dev
  # on-screen UI (palette, help overlay, dialogs)
  libimgui-dev libstb-dev
  # ray-traced stills and picking
  libembree-dev
  # devices: libusb transport, udev for hidraw enumeration; umockdev emulates USB devices
  # for the transport tests
  libusb-1.0-0-dev libudev-dev umockdev libumockdev-dev
  # sketch geometry: constrained Delaunay triangulation and exact mesh booleans
  libcgal-dev libgmp-dev libmpfr-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev python3-ezdxf
  clang-format
  help2man
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${packages[@]}"
