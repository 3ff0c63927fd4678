#!/usr/bin/env bash
# Build Mesa's Bifrost/Valhall (Mali) shader compiler, `bifrost_compiler`, from
# Debian 12's `mesa` source package (22.3.6) with tools/mali/bifrost-spirv.patch
# applied (adds a `compile-spirv` command), into a cache directory.
#
#   tools/mali/build.sh            # builds if needed; prints the binary path on stdout
#
# Environment:
#   MALI_BUILD_DIR   cache directory (default: $HOME/.cache/dermis-mali)
#   MALI_JOBS        parallel compile jobs (default: nproc)
#
# Idempotent: when the binary exists and was built from the same patch it only
# prints the path. A changed patch is re-applied to the existing tree and only
# the affected objects are rebuilt. Needs Debian 12 (bookworm), root or sudo,
# and access to Debian's package archive. Everything but the path goes to stderr.
set -euo pipefail

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
PATCH="$HERE/bifrost-spirv.patch"
BUILD_DIR=${MALI_BUILD_DIR:-$HOME/.cache/dermis-mali}
JOBS=${MALI_JOBS:-$(nproc)}
MESA_UPSTREAM=22.3.6
SRC="$BUILD_DIR/src/mesa-$MESA_UPSTREAM"
BIN_DIR="$BUILD_DIR/bin"
BIN="$BIN_DIR/bifrost_compiler"

log() { echo "[mali-build] $*" >&2; }
die() { echo "[mali-build] error: $*" >&2; exit 1; }

[ -f "$PATCH" ] || die "missing $PATCH"
PATCH_SUM=$(sha256sum "$PATCH" | cut -d' ' -f1)

if [ -x "$BIN" ] && [ -f "$BIN_DIR/STAMP" ] && [ "$(cat "$BIN_DIR/STAMP")" = "$PATCH_SUM" ]; then
    echo "$BIN"
    exit 0
fi

START=$(date +%s)

SUDO=""
if [ "$(id -u)" != 0 ]; then
    command -v sudo >/dev/null || die "need root or sudo to install packages"
    SUDO="sudo"
fi
APT_ENV=(env DEBIAN_FRONTEND=noninteractive)

# ---------------------------------------------------------------- packages
PKGS=(dpkg-dev meson ninja-build python3-mako bison flex libdrm-dev zlib1g-dev
      libexpat1-dev pkg-config patch)
missing=()
for p in "${PKGS[@]}"; do
    status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
    [ "$status" = "install ok installed" ] || missing+=("$p")
done
updated=0
if [ ${#missing[@]} -gt 0 ]; then
    log "installing: ${missing[*]}"
    $SUDO "${APT_ENV[@]}" apt-get update -qq >&2
    updated=1
    $SUDO "${APT_ENV[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

# ---------------------------------------------------------------- source
if [ ! -f "$SRC/.dermis-extracted" ]; then
    # apt needs a deb-src entry; mirror the system's Debian binary entries.
    SHOWSRC=$(apt-cache showsrc mesa 2>/dev/null || true)
    if ! grep -q '^Package: mesa' <<<"$SHOWSRC"; then
        if [ -f /etc/apt/sources.list.d/debian.sources ]; then
            log "adding deb-src entries mirroring /etc/apt/sources.list.d/debian.sources"
            sed 's/^Types:.*/Types: deb-src/' /etc/apt/sources.list.d/debian.sources |
                $SUDO tee /etc/apt/sources.list.d/dermis-mali-src.sources >/dev/null
        elif grep -qs '^deb ' /etc/apt/sources.list; then
            log "adding deb-src lines mirroring /etc/apt/sources.list"
            grep '^deb ' /etc/apt/sources.list | sed 's/^deb /deb-src /' |
                $SUDO tee /etc/apt/sources.list.d/dermis-mali-src.list >/dev/null
        else
            echo "deb-src http://deb.debian.org/debian bookworm main" |
                $SUDO tee /etc/apt/sources.list.d/dermis-mali-src.list >/dev/null
        fi
        $SUDO "${APT_ENV[@]}" apt-get update -qq >&2
        updated=1
    fi
    if [ "$updated" = 0 ] && ! grep -q "^Version: $MESA_UPSTREAM-" <<<"$SHOWSRC"; then
        $SUDO "${APT_ENV[@]}" apt-get update -qq >&2
    fi

    DL="$BUILD_DIR/dl"
    rm -rf "$DL" "$SRC"
    mkdir -p "$DL" "$BUILD_DIR/src"
    log "fetching Debian's mesa source package"
    (cd "$DL" && apt-get source -q --download-only mesa) >&2
    DSC=$(ls "$DL"/mesa_*.dsc | head -n1)
    DEB_VERSION=$(sed -n 's/^Version: //p' "$DSC" | head -n1)
    case "$DEB_VERSION" in
        "$MESA_UPSTREAM"-*) ;;
        *) die "apt offers mesa $DEB_VERSION; the patch is for $MESA_UPSTREAM (Debian 12 bookworm)";;
    esac
    log "extracting mesa $DEB_VERSION (with Debian's patches)"
    dpkg-source -x "$DSC" "$SRC" >&2
    echo "$DEB_VERSION" > "$SRC/.dermis-extracted"
fi
DEB_VERSION=$(cat "$SRC/.dermis-extracted")

# ---------------------------------------------------------------- patch
cd "$SRC"
if [ -f .dermis-applied.patch ]; then
    if ! cmp -s .dermis-applied.patch "$PATCH"; then
        log "reverting the previously applied patch"
        patch -s -R -p1 < .dermis-applied.patch >&2
        rm -f .dermis-applied.patch
    fi
fi
if [ ! -f .dermis-applied.patch ]; then
    log "applying $(basename "$PATCH")"
    patch -s -p1 --dry-run < "$PATCH" >&2 || die "patch does not apply to mesa $DEB_VERSION"
    patch -s -p1 < "$PATCH" >&2
    cp "$PATCH" .dermis-applied.patch
fi

# ---------------------------------------------------------------- build
# Debian's python3 must come first: meson's generators need python3-mako.
export PATH="/usr/bin:$PATH"
if [ ! -f build/build.ninja ]; then
    log "configuring (meson)"
    meson setup build \
        -Dbuildtype=release -Db_ndebug=false \
        -Dgallium-drivers=panfrost -Dtools=panfrost -Dvulkan-drivers= \
        -Dllvm=disabled -Dplatforms= -Dglx=disabled -Degl=disabled -Dgbm=disabled \
        >"$BUILD_DIR/meson-setup.log" 2>&1 || { tail -n 40 "$BUILD_DIR/meson-setup.log" >&2; die "meson setup failed"; }
fi
log "building bifrost_compiler with $JOBS jobs (first time: ~460 steps, 6-10 minutes on 2 cores)"
ninja -C build -j"$JOBS" src/panfrost/bifrost_compiler >"$BUILD_DIR/ninja.log" 2>&1 ||
    { tail -n 40 "$BUILD_DIR/ninja.log" >&2; die "build failed (log: $BUILD_DIR/ninja.log)"; }

mkdir -p "$BIN_DIR"
cp build/src/panfrost/bifrost_compiler "$BIN.tmp"
mv "$BIN.tmp" "$BIN"
echo "$DEB_VERSION" > "$BIN_DIR/MESA_VERSION"
echo "$PATCH_SUM" > "$BIN_DIR/STAMP"
log "done in $(( $(date +%s) - START )) s (mesa $DEB_VERSION)"
echo "$BIN"
