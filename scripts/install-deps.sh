#!/usr/bin/env bash
# Install grainscale's build dependencies from Debian packages (idempotent).
# Usage: scripts/install-deps.sh [--with-liggghts]
#   --with-liggghts  also install Debian's LIGGGHTS, used only by bench/ for side-by-side timings.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libsundials-dev libhdf5-dev libgsl-dev libyaml-cpp-dev catch2
)
[[ "${1:-}" == "--with-liggghts" ]] && packages+=(liggghts)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo_cmd=()
[[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
echo "install-deps: installing ${missing[*]}"
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
