#!/usr/bin/env bash
# Installs every Debian package scanplan needs to build, test and run (Debian 12), the
# Python module's included (pybind11, numpy, pytest, matplotlib), then the report's web
# packages (three.js, esbuild, playwright-core) from the npm registry into
# web/node_modules, pinned by web/package-lock.json.
# Idempotent: installs only what is missing. Runs as root, or through sudo.
set -euo pipefail

packages=(
  g++ cmake ninja-build pkg-config
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
  libocct-ocaf-dev libocct-data-exchange-dev libocct-visualization-dev
  libembree-dev libeigen3-dev libtbb-dev libnanoflann-dev
  nlohmann-json3-dev libyaml-cpp-dev libcli11-dev libfmt-dev coinor-libcbc-dev libqhull-dev
  libopen3d-dev libtinygltf-dev libstb-dev libfcl-dev libompl-dev
  chromium
  python3-dev python3-venv python3-distributed pybind11-dev python3-numpy python3-pytest python3-matplotlib python3-yaml
  libgtest-dev libgmock-dev libbenchmark-dev
)

missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" ||
    missing+=("$package")
done
# Node.js and npm: the machine's own when it has them, else Debian's.
command -v npm >/dev/null || missing+=(nodejs npm)

install_web() {
  if [ ! -d web/node_modules/three ] || [ web/package-lock.json -nt web/node_modules/.package-lock.json ]; then
    echo "install-deps: installing the report's web packages (npm ci in web/)"
    (cd web && npm ci --no-audit --no-fund --loglevel=error)
  fi
}

cd "$(dirname "$0")/.."
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages are installed"
  install_web
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: run as root or install sudo" >&2; exit 1; }
  sudo="sudo"
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
install_web
