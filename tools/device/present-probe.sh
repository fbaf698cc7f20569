#!/usr/bin/env bash
# Whether the GPU machine's Vulkan driver can present to an X11 window (docs/performance.md,
# "Presenting"). That machine has no display and no X server, so Xvfb and the libraries it
# loads travel in the bundle:
#
#   tools/device/present-probe.sh --fetch   # here: Debian 12's xvfb and its libraries into .devbundle/xvfb/
#   tools/device/present-probe.sh           # there (carry .devbundle, after bundle.sh): start Xvfb, build
#                                           # tools/device/present_probe.c against the bundle, run it
#
# The run needs xkbcomp at Xvfb's built-in path; it copies the carried one to /usr/bin only
# where there is none. Elsewhere nothing is written outside /tmp.
set -uo pipefail
cd "$(git rev-parse --show-toplevel 2>/dev/null || pwd)"
carried=.devbundle/xvfb
if [ "${1:-}" = "--fetch" ]; then
  mkdir -p "$carried" /tmp/present-probe-lists/partial
  apt=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/present-probe-lists)
  apt-get "${apt[@]}" update >/dev/null
  # Xvfb's own libraries (ldd /usr/bin/Xvfb) beyond what bundle.sh carries, and its keymap compiler.
  (cd "$carried" && apt-get "${apt[@]}" download xvfb xserver-common x11-xkb-utils xkb-data \
      libxfont2 libfontenc1 libfreetype6 libpng16-16 libbrotli1 libpixman-1-0 libxkbfile1 libxshmfence1 \
      libunwind8 libaudit1 libcap-ng0 libcap2 libgcrypt20 libgpg-error0 libselinux1 libpcre2-8-0 \
      libsystemd0 liblz4-1 libzstd1 libbz2-1.0 >/dev/null)
  echo "present-probe.sh: $(ls "$carried" | wc -l) packages, $(du -sh "$carried" | cut -f1) in $carried"
  exit 0
fi

root=/tmp/present-probe-root deps=/tmp/skygraph-deps
mkdir -p "$root" "$deps"
for deb in "$carried"/*.deb; do dpkg -x "$deb" "$root"; done
[ -d "$deps/usr" ] || tar -xJf .devbundle/deps.tar.xz -C "$deps"
[ -e /usr/bin/xkbcomp ] || cp "$root/usr/bin/xkbcomp" /usr/bin/xkbcomp
export LD_LIBRARY_PATH=$root/usr/lib/x86_64-linux-gnu:$root/lib/x86_64-linux-gnu:$deps/usr/lib/x86_64-linux-gnu
icd=$(find / -xdev -name 'nvidia_icd*.json' 2>/dev/null | head -1)
[ -n "$icd" ] && export VK_DRIVER_FILES=$icd
"$root/usr/bin/Xvfb" :99 -screen 0 1920x1080x24 -nolisten tcp -fp built-ins \
    -xkbdir "$root/usr/share/X11/xkb" > /tmp/present-probe-xvfb.log 2>&1 &
xvfb=$!
trap 'kill $xvfb 2>/dev/null' EXIT
sleep 3
export DISPLAY=:99
gcc -O2 tools/device/present_probe.c -I"$deps/usr/include" -L"$deps/usr/lib/x86_64-linux-gnu" -lglfw -lvulkan \
    -o /tmp/present_probe || exit 1
timeout 120 /tmp/present_probe
rc=$?
echo "present_probe exit status: $rc$([ $rc -ge 128 ] && echo " (signal $((rc - 128)))")"
exit $rc
