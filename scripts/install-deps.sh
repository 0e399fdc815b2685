#!/bin/sh
# Installs every build and test dependency of mblab from Debian 12 packages.
# Idempotent; run as root on a fresh machine.
set -eu
PKGS="build-essential cmake ninja-build pkg-config git clang-14 clang-format-14 \
 libclang-rt-14-dev libasio-dev libcli11-dev libtomlplusplus-dev nlohmann-json3-dev \
 libfmt-dev libssl-dev libpcap-dev libgtest-dev libgmock-dev googletest libbenchmark-dev \
 python3-pymodbus python3-serial python3-serial-asyncio libmodbus-dev mbpoll socat tshark libxml2-utils \
 prometheus curl \
 iputils-ping man-db chromium chromium-driver"
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
