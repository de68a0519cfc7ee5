#!/usr/bin/env bash
# Installs every Debian 12 package the project builds, tests and runs with,
# then the viewer's npm packages (viewer/package-lock.json) into
# viewer/node_modules. Idempotent: packages already present are left alone,
# apt and npm are only touched when something is missing. Needs root (or
# sudo) when it installs Debian packages.
set -euo pipefail

PACKAGES=(
  # toolchain
  build-essential cmake pkg-config git clang-format
  lld  # the linker (cmake/HftsBuildSpeed.cmake)
  # libraries of docs/architecture.md
  libeigen3-dev libpcl-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libembree-dev libfcl-dev libompl-dev liburdfdom-dev liburdfdom-tools
  libassimp-dev libhdf5-dev hdf5-tools libqhull-dev nlohmann-json3-dev
  libasio-dev libcli11-dev libssl-dev libnanoflann-dev libhwy-dev
  libmujoco-dev libtinyxml2-dev libyaml-cpp-dev
  liboctomap-dev libpng-dev  # point-cloud obstacles (octrees in FCL) and depth images
  # tests and benchmarks; clang + libFuzzer and the sanitizer runtimes
  # (scripts/fuzz.sh, scripts/sanitize.sh); HAProxy (scripts/scale_out.sh)
  libgtest-dev libgmock-dev libbenchmark-dev
  clang libclang-rt-14-dev haproxy
  openssl  # self-signed certificates of the TLS tests (scripts/scale_out.sh --tls)
  # Python tooling (runs under /usr/bin/python3)
  python3 python3-numpy python3-h5py python3-matplotlib
  # the in-process Python module (python/, docs/python.md): pybind11 and the
  # headers it builds against; its wheel (python3 -m build, venv); the ROS
  # messages its results are shaped like (round-tripped in its tests)
  python3-dev pybind11-dev python3-pybind11 python3-build python3-venv python3-setuptools
  python3-wheel python3-trajectory-msgs python3-geometry-msgs
  # the viewer (viewer/): node and npm for three.js, esbuild, the glTF
  # validator and puppeteer-core (Debian's npm package is added below
  # unless the nodejs installed already brings npm); chromium for its tests
  nodejs chromium
)

# npm packages at the versions of viewer/package-lock.json, unless present,
# and the viewer's bundle (viewer/dist/viewer.js), unless up to date.
install_npm_packages() {
  local viewer
  viewer="$(cd "$(dirname "$0")/.." && pwd)/viewer"
  if [[ ! -f "$viewer/node_modules/.package-lock.json" ||
        "$viewer/package-lock.json" -nt "$viewer/node_modules/.package-lock.json" ]]; then
    echo "setup: installing the viewer's npm packages"
    (cd "$viewer" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
  fi
  if [[ ! -f "$viewer/dist/viewer.js" || "$viewer/src/main.js" -nt "$viewer/dist/viewer.js" ||
        "$viewer/node_modules/.package-lock.json" -nt "$viewer/dist/viewer.js" ]]; then
    echo "setup: bundling the viewer (viewer/dist/viewer.js)"
    (cd "$viewer" && npm run --silent build >/dev/null)
  fi
}

missing=()
for pkg in "${PACKAGES[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$pkg")
done
command -v npm >/dev/null || missing+=(npm)

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "setup: all ${#PACKAGES[@]} packages present"
  install_npm_packages
  exit 0
fi

SUDO=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO=(sudo)
fi

echo "setup: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" apt-get update -qq
"${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
install_npm_packages
echo "setup: done"
