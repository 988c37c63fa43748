#!/usr/bin/env bash
# Installs the Debian packages cagewrap needs, only those that are missing.
# Idempotent and quick when everything is present (one dpkg-query call).
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libglfw3-dev libimgui-dev libglm-dev libtinygltf-dev libopenmesh-dev libeigen3-dev
  libepoxy-dev libgl-dev libgl1-mesa-dri libglx-mesa0 mesa-utils
  libegl-dev libegl1 libegl-mesa0
  libtbb-dev nlohmann-json3-dev libcli11-dev libstb-dev libmeshoptimizer-dev libassimp-dev assimp-testmodels
  libgtest-dev libgmock-dev libbenchmark-dev
  xvfb xauth
  python3
  clang libclang-rt-14-dev
)

missing=()
while read -r name status; do
  [[ "$status" == "installed" ]] || missing+=("$name")
done < <(for p in "${PACKAGES[@]}"; do
           s=$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null || true)
           echo "$p ${s:-absent}"
         done)

# The Khronos glTF validator and three.js (npm packages, pinned in tests/gltf_validate/package.json) for
# the glTF tests (validation; what a runtime shows); node and npm come from Debian when absent.
install_gltf_validator() {
  local dir
  dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/tests/gltf_validate"
  [[ -d "$dir/node_modules/gltf-validator" && -d "$dir/node_modules/three" ]] && return 0
  if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
    echo "setup: installing nodejs npm"
    local sudo=""
    [[ $(id -u) -ne 0 ]] && sudo="sudo"
    DEBIAN_FRONTEND=noninteractive $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends nodejs npm
  fi
  echo "setup: npm install in tests/gltf_validate"
  (cd "$dir" && npm install --no-audit --no-fund --silent)
}

if ((${#missing[@]} == 0)); then
  install_gltf_validator
  exit 0
fi

echo "setup: installing ${#missing[@]} missing package(s): ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
install_gltf_validator
