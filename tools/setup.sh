#!/usr/bin/env bash
# Installs what xfdem needs to build, test and reproduce its figures on
# Debian 12 (bookworm), with apt-get. Packages already installed are skipped,
# so a second run is fast and touches nothing. Run as root, or as a user with
# sudo. Prints one line on success; the apt log on failure.
set -euo pipefail

PACKAGES=(
  cmake g++ make                  # toolchain (CMake >= 3.25 for the presets)
  libeigen3-dev                   # Eigen 3.4
  libgtest-dev libgmock-dev       # GoogleTest / GoogleMock
  libbenchmark-dev                # Google Benchmark
  nlohmann-json3-dev              # scene files
  python3 python3-matplotlib python3-numpy   # validation report and figures
  clang libclang-rt-14-dev        # fuzzers: libFuzzer and the sanitizer runtimes
                                  # (a Recommends of clang-14, hence named here)
)

installed() {
  [[ "$(dpkg-query -W -f='${db:Status-Status}' "$1" 2>/dev/null)" == "installed" ]]
}

if ! command -v dpkg-query >/dev/null || ! command -v apt-get >/dev/null; then
  echo "setup: this script needs a Debian-based system (apt-get, dpkg-query)." >&2
  echo "setup: wanted packages: ${PACKAGES[*]}" >&2
  exit 1
fi

missing=()
for p in "${PACKAGES[@]}"; do
  installed "$p" || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "setup: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=()
if [[ $(id -u) -ne 0 ]]; then
  if ! command -v sudo >/dev/null; then
    echo "setup: missing packages (${missing[*]}) and not root, and no sudo" >&2
    exit 1
  fi
  SUDO=(sudo)
fi

echo "setup: installing ${missing[*]}"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
export DEBIAN_FRONTEND=noninteractive
if ! { "${SUDO[@]}" apt-get update -q \
       && "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"; \
     } </dev/null >"$log" 2>&1; then
  cat "$log" >&2
  echo "setup: apt-get failed" >&2
  exit 1
fi

still=()
for p in "${missing[@]}"; do
  installed "$p" || still+=("$p")
done
if [[ ${#still[@]} -ne 0 ]]; then
  cat "$log" >&2
  echo "setup: still missing after apt-get: ${still[*]}" >&2
  exit 1
fi
