#!/usr/bin/env bash
# Runs the packaged FMU binary under an older glibc than this machine's: Debian 11's
# glibc 2.31 (the glibc of Ubuntu 20.04; RHEL 8 has 2.28), the machines the portable
# build is for. Older glibc releases cannot be had here: Debian's mirror no longer serves
# buster (2.28) or anything before it.
#
# 1. Downloads Debian 11's libc6 package with apt-get (private state folders under
#    target/old-glibc; the machine's apt configuration and installed packages are left
#    alone) and unpacks it: ld.so, libc, libm, libpthread, libdl of glibc 2.31.
# 2. Builds scripts/old-glibc/driver.c, a minimal FMI 2.0 importer, with `zig cc` for
#    glibc 2.17, so that the driver itself runs under the old glibc.
# 3. Runs the paper scene in StickSlipBeam (modal and beam fidelity, exponential law and
#    plain network) through that driver under glibc 2.31's own dynamic loader, and again
#    under this machine's glibc, and requires the same tip deflection bits from both.
# 4. Tries the host build of the library (target/release) under glibc 2.31 too and shows
#    the loader's refusal: the problem the portable build solves.
#
# If the package cannot be downloaded (no network, or the suite moved to Debian's
# archive), it says SKIPPED and exits 0: the symbol-version test in
# fmu-build/tests/packaged/portable.rs is then the evidence. Any other failure exits 1.
#
# Needs the packaged FMUs (cargo run --release -p fmu-build). OLD_GLIBC_SUITE picks
# another Debian suite (default bullseye). Honours CARGO_TARGET_DIR.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
suite="${OLD_GLIBC_SUITE:-bullseye}"
target="${CARGO_TARGET_DIR:-target}"
case "$target" in /*) ;; *) target="$root/$target" ;; esac
work="$target/old-glibc"
fmu="$target/fmu/2.0/StickSlipBeam.fmu"
host_library="$target/release/libstickslip_fmi.so"
if [ ! -f "$fmu" ]; then
  echo "old-glibc: $fmu is missing; run cargo run --release -p fmu-build first" >&2
  exit 1
fi
zig="$(bash scripts/zig-env.sh)/zig"

echo "== old-glibc: Debian $suite's libc6 (apt-get download into $work)"
apt_dir="$work/apt"
mkdir -p "$apt_dir/lists/partial" "$apt_dir/cache/archives/partial" "$work/deb"
echo "deb [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian $suite main" \
  >"$apt_dir/sources.list"
apt=(-o "Dir::Etc::SourceList=$apt_dir/sources.list" -o Dir::Etc::SourceParts=/dev/null
  -o "Dir::State::Lists=$apt_dir/lists" -o "Dir::Cache=$apt_dir/cache"
  -o Dir::State::status=/dev/null -o APT::Sandbox::User=root -o Debug::NoLocking=1)
if ! apt-get "${apt[@]}" -qq update >"$work/apt.log" 2>&1 ||
  ! (cd "$work/deb" && rm -f libc6_*.deb && apt-get "${apt[@]}" -qq download libc6 >>"$work/apt.log" 2>&1); then
  echo "old-glibc: SKIPPED: cannot download Debian $suite's libc6 (see $work/apt.log)"
  exit 0
fi
deb="$(ls "$work"/deb/libc6_*.deb)"
echo "   $(basename "$deb")"
sysroot="$work/glibc"
rm -rf "$sysroot"
dpkg-deb -x "$deb" "$sysroot"
libs="$sysroot/lib/x86_64-linux-gnu"
old=("$libs/ld-linux-x86-64.so.2" --library-path "$libs")

echo "== old-glibc: driver (zig cc, glibc 2.17)"
"$zig" cc -target x86_64-linux-gnu.2.17 -O2 -Wall -Werror -o "$work/driver" scripts/old-glibc/driver.c

rm -rf "$work/fmu"
mkdir -p "$work/fmu"
python3 -m zipfile -e "$fmu" "$work/fmu"
# GUID, value references and choice codes from the FMU's own modelDescription.xml.
read -r guid tip fidelity model modal beam exponential neural < <(python3 - "$work/fmu/modelDescription.xml" <<'EOF'
import sys
import xml.etree.ElementTree as ET

root = ET.parse(sys.argv[1]).getroot()
vr = {v.get("name"): v.get("valueReference") for v in root.iter("ScalarVariable")}
# Choice codes: the <Choice> list in the stickslip tool's vendor annotations.
items = {
    (c.get("variable"), i.get("name")): i.get("code")
    for c in root.iter("Choice")
    for i in c.iter("Item")
}
print(
    root.get("guid"),
    vr["tip_deflection"],
    vr["fidelity.level"],
    vr["friction.law"],
    items[("fidelity.level", "modal")],
    items[("fidelity.level", "beam")],
    items[("friction.law", "exponential")],
    items[("friction.law", "neural")],
)
EOF
)
library="$work/fmu/binaries/linux64/StickSlipBeam.so"
resources="file://$work/fmu/resources"

status=0
for case in "modal exponential $modal $exponential" "modal neural $modal $neural" \
  "beam exponential $beam $exponential" "beam neural $beam $neural"; do
  read -r level law level_code law_code <<<"$case"
  args=("$guid" "$resources" "$tip" 1200 "$fidelity=$level_code" "$model=$law_code")
  if ! "${old[@]}" "$work/driver" "$library" "${args[@]}" >"$work/old.txt" 2>"$work/old.err"; then
    echo "   $level, $law: FAILED under glibc 2.31:" >&2
    cat "$work/old.err" >&2
    status=1
    continue
  fi
  "$work/driver" "$library" "${args[@]}" >"$work/host.txt"
  if cmp -s "$work/old.txt" "$work/host.txt"; then
    echo "   $level, $law: loads and runs under glibc 2.31; $(tail -n 1 "$work/old.txt"); the same bits as under this machine's glibc"
  else
    echo "   $level, $law: runs under glibc 2.31, but the output differs from this machine's glibc:" >&2
    diff "$work/old.txt" "$work/host.txt" | head -n 6 >&2
    status=1
  fi
done

if [ -f "$host_library" ]; then
  if "${old[@]}" "$work/driver" "$host_library" "$guid" "$resources" "$tip" 1 >/dev/null 2>"$work/host-build.err"; then
    echo "   the host build ($host_library) loads under glibc 2.31 as well"
  else
    echo "   the host build under glibc 2.31, for comparison: $(tail -n 1 "$work/host-build.err")"
  fi
fi
if [ "$status" -ne 0 ]; then
  echo "old-glibc: FAILED" >&2
  exit 1
fi
echo "old-glibc: ok"
