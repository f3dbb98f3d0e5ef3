#!/usr/bin/env bash
# CI leg "freecad11": the FreeCAD workbench tests (tests/freecad under freecadcmd, tests/gui under
# xvfb-run) on FreeCAD 1.1 (Qt6/PySide6, Python 3.14), in a Debian sid chroot.
#
# 1. Creates the chroot with debootstrap (--variant=minbase) unless it is already there, and
#    installs in it only what these tests need (FreeCAD, the build tools, the -dev packages of the
#    Python module, xvfb); packages already present are not fetched again.
# 2. Mounts proc, sys, dev and a tmpfs on its /tmp; a trap unmounts them on every exit.
# 3. Copies the tree into the chroot (rsync, so a second run rebuilds only what changed), builds
#    only the Python module and the build-tree workbench, and runs the ctest tests labelled
#    freecad and gui (cmake/freecad_workbench.cmake).
#
# With --prepare-only it stops after step 1 (chroot and packages ready, mounts undone): the
# network- and disk-bound part, which scripts/run_tests.sh runs in the background while the
# compiler-bound legs build and test.
#
# Needs root (debootstrap, mount, chroot): run as root or through sudo. Environment:
#   CURVEDSLICER_SID_ROOT    the chroot (default /srv/curvedslicer-sid; never inside the tree)
#   CURVEDSLICER_SID_MIRROR  the Debian mirror (default: the host's, else deb.debian.org)
#   CURVEDSLICER_SID_FRESH=1 delete the chroot first (a cold run)
# Exits non-zero if the set-up, the build or a test failed.
set -euo pipefail

prepare_only=0
case "${1:-}" in
  "") ;;
  --prepare-only) prepare_only=1 ;;
  *) printf 'freecad11: error: unknown argument: %s; the only option is --prepare-only\n' "$1" >&2
     exit 2 ;;
esac

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
root="${CURVEDSLICER_SID_ROOT:-/srv/curvedslicer-sid}"
jobs="$(nproc 2>/dev/null || echo 2)"

# Packages inside the chroot: FreeCAD 1.1 and xvfb for the tests; the compiler, CMake and the
# libraries the core, the OCCT tessellator and the pybind11 module link (CGAL/Boost: geom's AABB
# tree, FCL: robot/collision); CLI11 and GoogleTest because the top-level CMakeLists finds them.
packages=(
  freecad xvfb xauth python3-numpy
  build-essential cmake ninja-build pkg-config python3-dev pybind11-dev
  libeigen3-dev nlohmann-json3-dev libcli11-dev libgtest-dev
  libcgal-dev libboost-dev libfcl-dev
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
  libocct-data-exchange-dev
)

log() { printf 'freecad11: %s\n' "$*"; }
die() { printf 'freecad11: error: %s\n' "$*" >&2; exit 1; }

if [[ "$(id -u)" -ne 0 ]]; then
  command -v sudo >/dev/null 2>&1 || die "not root and no sudo; run this script as root"
  exec sudo --preserve-env=CURVEDSLICER_SID_ROOT,CURVEDSLICER_SID_MIRROR,CURVEDSLICER_SID_FRESH \
    bash "${BASH_SOURCE[0]}" "$@"
fi

root="$(realpath -m "$root")"
case "$root/" in
  "$repo"/*)
    die "chroot folder inside the source tree: $root; set CURVEDSLICER_SID_ROOT outside it" ;;
  / | /srv/ | /var/ | /tmp/)
    die "chroot folder is a system folder: $root; choose a folder of its own" ;;
esac
existing="$root"
while [[ ! -d "$existing" ]]; do existing="$(dirname "$existing")"; done
if command -v git >/dev/null 2>&1 &&
   tree="$(git -C "$existing" rev-parse --show-toplevel 2>/dev/null)"; then
  die "chroot folder inside the git work tree $tree: $root; set CURVEDSLICER_SID_ROOT outside it"
fi

mirror="${CURVEDSLICER_SID_MIRROR:-}"
if [[ -z "$mirror" ]]; then
  mirror="$(awk '/^URIs:/ && $2 ~ /\/debian\/?$/ {print $2; exit}' \
              /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)"
  mirror="${mirror:-http://deb.debian.org/debian}"
fi

# One run at a time per chroot: the mounts and the build folder are shared.
mkdir -p "$(dirname "$root")"
exec 9>"$root.lock"
flock -n 9 || die "another run holds $root.lock; wait for it to finish"

# ---- mounts, undone by the trap on every exit ---------------------------------------------------
mounted=()
unmount_all() {
  local i
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do
    umount -R "${mounted[$i]}" 2>/dev/null || umount -lR "${mounted[$i]}" 2>/dev/null ||
      echo "freecad11: could not unmount ${mounted[$i]}" >&2
  done
  mounted=()
}
trap unmount_all EXIT
trap 'exit 130' INT TERM

mount_in_chroot() {  # mount_in_chroot TARGET MOUNT-ARGS...
  local target="$root/$1"
  shift
  mkdir -p "$target"
  mountpoint -q "$target" && die "$target is already mounted; unmount it first"
  mount "$@" "$target"
  mounted+=("$target")
}

mount_all() {
  mount_in_chroot proc -t proc proc
  mount_in_chroot sys -t sysfs sysfs
  mount_in_chroot dev --rbind /dev
  mount --make-rslave "$root/dev"
  mount_in_chroot tmp -t tmpfs -o mode=1777 tmpfs
  cp -L /etc/resolv.conf "$root/etc/resolv.conf"
}

in_chroot() {
  chroot "$root" /usr/bin/env -i PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    HOME=/root LANG=C.UTF-8 DEBIAN_FRONTEND=noninteractive "$@"
}

# ---- 1. the chroot ----------------------------------------------------------------------------
t0=$(date +%s)
if grep -q " $root/" /proc/mounts; then
  die "file systems still mounted under $root (a run killed without clean-up?); unmount them"
fi
ready="$root/.curvedslicer-base-ready"
if [[ "${CURVEDSLICER_SID_FRESH:-0}" == 1 && -e "$root" ]]; then
  log "CURVEDSLICER_SID_FRESH=1: deleting $root"
  rm -rf --one-file-system "$root"
fi
if [[ ! -e "$ready" ]]; then
  if [[ -e "$root" ]]; then
    log "removing the unfinished chroot $root"
    rm -rf --one-file-system "$root"
  fi
  if ! command -v debootstrap >/dev/null 2>&1; then
    log "installing debootstrap on the host"
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends debootstrap
  fi
  log "debootstrap sid into $root from $mirror"
  debootstrap --variant=minbase sid "$root" "$mirror" >"$root.debootstrap.log" 2>&1 ||
    { tail -n 30 "$root.debootstrap.log"; die "debootstrap failed (log: $root.debootstrap.log)"; }
  # The archive may be a frozen snapshot whose Release files have expired.
  echo 'Acquire::Check-Valid-Until "false";' >"$root/etc/apt/apt.conf.d/99no-check-valid-until"
  # The chroot is a throw-away test bed, prepared while the compiler-bound legs run beside it:
  # dpkg without an fsync per file (its disk writes then stall the builds less) and without
  # manuals, documentation and message catalogues, which no test reads.
  cat >"$root/etc/dpkg/dpkg.cfg.d/90curvedslicer-test-bed" <<'CFG'
force-unsafe-io
path-exclude=/usr/share/doc/*
path-exclude=/usr/share/man/*
path-exclude=/usr/share/info/*
path-exclude=/usr/share/locale/*
CFG
  touch "$ready"
fi
t1=$(date +%s)

mount_all

missing=()
for pkg in "${packages[@]}"; do
  status="$(in_chroot dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)"
  [[ "$status" == "install ok installed" ]] || missing+=("$pkg")
done
if ((${#missing[@]} > 0)); then
  log "installing ${#missing[@]} packages in the chroot: ${missing[*]}"
  apt_log="$root.apt.log"
  if ! { in_chroot apt-get update -q && in_chroot apt-get install -y -q --no-install-recommends \
           "${missing[@]}" && in_chroot apt-get clean; } >"$apt_log" 2>&1; then
    tail -n 40 "$apt_log"
    die "apt-get in the chroot failed (log: $apt_log)"
  fi
else
  log "all ${#packages[@]} packages present in the chroot"
fi
t2=$(date +%s)
log "FreeCAD in the chroot: $(in_chroot dpkg-query -W -f='${Version}' freecad)"
if ((prepare_only)); then
  log "prepared: chroot $((t1 - t0)) s, packages $((t2 - t1)) s"
  exit 0
fi

# ---- 2. build the Python module from a copy of the tree ---------------------------------------
work=/var/tmp/curvedslicer
mkdir -p "$root$work/src"
rsync -a --delete --exclude='/build*/' --exclude='/out/' --exclude='/.git' \
  --exclude='__pycache__/' --exclude='*.pyc' "$repo/" "$root$work/src/"
# -O1 instead of Release's -O3: the module is built from scratch on every cold run and runs only
# the FreeCAD tests' small parts here, so its compile time counts, not its speed (measured in
# tests/bench/README.md, "CI run time").
in_chroot cmake -S "$work/src" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
  -DCURVEDSLICER_BUILD_BENCH=OFF -DCURVEDSLICER_BUILD_TESTS=ON -DCURVEDSLICER_BUILD_PYTHON=ON
in_chroot cmake --build "$work/build" -j "$jobs" --target _curvedslicer curvedslicer_workbench
t3=$(date +%s)

# ---- 3. the FreeCAD and GUI tests -------------------------------------------------------------
status=0
in_chroot ctest --test-dir "$work/build" -L '^(freecad|gui)$' --output-on-failure -j "$jobs" \
  --timeout 1200 || status=$?
t4=$(date +%s)
log "times: chroot $((t1 - t0)) s, packages $((t2 - t1)) s, build $((t3 - t2)) s," \
  "tests $((t4 - t3)) s, total $((t4 - t0)) s"
exit "$status"
