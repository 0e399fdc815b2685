#!/bin/bash
# What `cmake --install` and `cpack -G DEB` give a user, checked from outside the source tree:
#   test_install.sh BUILD_DIR [--deb-install]
# installs BUILD_DIR into a temporary prefix and checks the layout, that the installed binary is
# stripped and runs from another directory with its installed data, the bash completion, and the
# .deb's dependencies and contents. With --deb-install (root only, CI) the .deb is also installed
# with dpkg, `mblab conform` run from /, and the package removed.
set -euo pipefail
build=$(cd "$1" && pwd)
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

prefix="$work/prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
for f in bin/mblab share/mblab/catalogue/policy-2.1.toml share/mblab/profiles/reference.toml \
    share/doc/mblab/README.md share/doc/mblab/LICENSE share/doc/mblab/catalogue.md \
    share/doc/mblab/http-api.yaml share/doc/mblab/copyright share/doc/mblab/changelog.gz \
    share/bash-completion/completions/mblab share/man/man1/mblab.1.gz; do
    [ -f "$prefix/$f" ] || fail "$f not installed"
done
if readelf -S "$prefix/bin/mblab" | grep -q '\.debug_'; then fail "installed binary has debug info"; fi

cd "$work"
listed=$("$prefix/bin/mblab" conform --list | sed -n 1p)
[ "$listed" = "policy-2.1 ($prefix/share/mblab/catalogue/policy-2.1.toml): Modbus/TCP Conformance Test Policy, version 2.1" ] ||
    fail "installed binary does not read its installed catalogue: $listed"
"$prefix/bin/mblab" conform --suite policy-2.1 >"$work/conform.txt" || fail "conform: $(cat "$work/conform.txt")"

# Completion: as bash would call it on a TAB after each word.
complete_words() {
    (
        # shellcheck disable=SC1091
        source "$prefix/share/bash-completion/completions/mblab"
        COMP_WORDS=("$@")
        COMP_CWORD=$(($# - 1))
        COMP_WORDS[0]="$prefix/bin/mblab"
        _mblab
        echo "${COMPREPLY[*]}"
    )
}
[ "$(complete_words mblab con)" = "conform conform-client" ] ||
    fail "completion of 'con': $(complete_words mblab con)"
[ "$(complete_words mblab conform-client --client-t)" = --client-timeout ] ||
    fail "completion of 'conform-client --client-t'"
[ "$(complete_words mblab conform --sui)" = --suite ] || fail "completion of 'conform --sui'"
[ "$(complete_words mblab serve --lis)" = --listen ] || fail "completion of 'serve --lis'"
[ "$(complete_words mblab fu)" = fuzz ] || fail "completion of 'fu'"
[ "$(complete_words mblab fuzz --check)" = --check-every ] || fail "completion of 'fuzz --check'"
[ "$(complete_words mblab sc)" = scan ] || fail "completion of 'sc'"
[ "$(complete_words mblab scan --for)" = --force ] || fail "completion of 'scan --for'"
[ "$(complete_words mblab conform --suite polic)" = policy-2.1 ] || fail "completion of suite names"
for command in conform conform-client serve read write diag devid raw watch load fuzz; do
    options=$(complete_words mblab "$command" --)
    case " $options " in *" --help "*) ;; *) fail "no options completed for $command: $options" ;; esac
done
[ "$(complete_words mblab conform --profile rs485)" = rs485-instrument ] ||
    fail "completion of profile names: $(complete_words mblab conform --profile rs485)"
[ "$(complete_words mblab serve mov)" = moving ] || fail "completion of 'serve mov'"
# Every document the README links is installed.
for doc in $(grep -oE '\]\(docs/[^)#]+' "$source_dir/README.md" | sed 's|](docs/||'); do
    [ -f "$prefix/share/doc/mblab/$doc" ] || fail "README links docs/$doc, which is not installed"
done
[ "$(complete_words mblab profile imp)" = import-csv ] || fail "completion of 'profile imp'"
[ "$(complete_words mblab profile import-csv --un)" = --unit ] ||
    fail "completion of 'profile import-csv --un': $(complete_words mblab profile import-csv --un)"

deb_dir="$work/deb"
cpack --config "$build/CPackConfig.cmake" -G DEB -B "$deb_dir" >"$work/cpack.log" 2>&1 ||
    fail "cpack: $(cat "$work/cpack.log")"
deb=$(ls "$deb_dir"/mblab_*.deb)
depends=$(dpkg-deb -f "$deb" Depends)
# libpcap is no dependency: conform writes its pcapng captures itself.
case "$depends" in *libpcap*) fail "Depends: $depends" ;; *libc6*) ;; *) fail "Depends: $depends" ;; esac
contents=$(dpkg-deb -c "$deb")
for f in ./usr/bin/mblab ./usr/share/mblab/catalogue/policy-2.1.toml ./usr/share/doc/mblab/LICENSE \
    ./usr/share/bash-completion/completions/mblab ./usr/share/man/man1/mblab.1.gz \
    ./usr/share/doc/mblab/copyright ./usr/share/doc/mblab/changelog.gz \
    ./usr/share/doc/mblab/http-api.yaml; do
    grep -q " $f\$" <<<"$contents" || fail "$f not in the .deb"
done
[ "$(dpkg-deb -f "$deb" Recommends)" = bash-completion ] || fail "Recommends: $(dpkg-deb -f "$deb" Recommends)"
case "$(dpkg-deb -f "$deb" Maintainer)" in *@localhost*) fail "Maintainer: $(dpkg-deb -f "$deb" Maintainer)" ;; esac
# lintian (Debian's package checker): no error. Warnings and notes are shown, not failed on.
if command -v lintian >/dev/null; then
    lintian --tag-display-limit 0 "$deb" >"$work/lintian.txt" 2>&1 || true
    if grep -q '^E: ' "$work/lintian.txt"; then fail "lintian errors: $(grep '^E: ' "$work/lintian.txt")"; fi
else
    fail "no lintian (scripts/install-deps.sh installs it)"
fi

if [ "${2:-}" = --deb-install ]; then
    dpkg -i "$deb" >/dev/null
    trap 'dpkg --purge mblab >/dev/null; rm -rf "$work"' EXIT
    (cd / && /usr/bin/mblab conform --suite policy-2.1 >"$work/deb-conform.txt") ||
        fail "conform from the .deb: $(cat "$work/deb-conform.txt")"
    grep -q '^Summary: 18 passed, 0 failed' "$work/deb-conform.txt" || fail "$(cat "$work/deb-conform.txt")"
fi
echo "install: ok"
