#!/bin/sh
# Installs mblab's dependencies from Debian 12 packages. Idempotent; run as root on a fresh machine.
#   install-deps.sh          everything: building, every test and its third-party peers (CI)
#   install-deps.sh --build  only what building and running mblab needs (the README's first command)
set -eu
# Configuring the build needs the test and benchmark libraries too (small header packages).
BUILD="build-essential cmake ninja-build pkg-config git \
 libasio-dev libcli11-dev libtomlplusplus-dev nlohmann-json3-dev \
 libfmt-dev libssl-dev libpcap-dev libgtest-dev libgmock-dev googletest libbenchmark-dev"
# The second compiler, sanitizers, the formatter, the peers the tests run against and the browser.
TEST="clang-14 clang-format-14 libclang-rt-14-dev \
 python3-pymodbus python3-serial python3-serial-asyncio libmodbus-dev mbpoll socat tshark \
 libxml2-utils prometheus curl iputils-ping man-db chromium chromium-driver lintian"
case "${1:-}" in
  --build) PKGS="$BUILD" ;;
  "") PKGS="$BUILD $TEST" ;;
  *) echo "usage: install-deps.sh [--build]" >&2; exit 2 ;;
esac
missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  if [ "$(id -u)" != 0 ]; then
    echo "install-deps: need root to install:$missing" >&2
    exit 2
  fi
  export DEBIAN_FRONTEND=noninteractive
  echo "wireshark-common wireshark-common/install-setuid boolean false" | debconf-set-selections
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends $missing
fi
