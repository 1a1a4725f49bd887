#!/bin/sh
# libhalo set-up: installs the Debian packages that are missing, builds, and runs the
# main job (halo-render with no arguments). Safe to run again.
#   HALO_CONFIGURE_FLAGS  extra flags for ./configure (e.g. --enable-sanitizers); they
#                         come last and win (--without-paraview builds without the plugin)
set -eu
cd "$(dirname "$0")"

# VTK comes with ParaView (paraview-dev carries ParaView's own VTK 9.2, which the VTK
# adapter then builds against): Debian's libvtk9-dev cannot be installed beside
# python3-paraview, which pvbatch needs. ParaView's CMake package needs development
# files that paraview-dev does not depend on: libopenmpi-dev (MPI::MPI_C's include
# folder), libfreetype-dev (VTK::freetype links Freetype::Freetype), libglew-dev (VTK's
# GLEW, for the VTK adapter too).
# tests/tree/setup_deps.sh reads this list: keep it one packages="..." of plain names.
packages="build-essential autoconf automake libtool pkg-config file
  glslang-dev libosmesa6-dev libegl-dev libegl-mesa0 mesa-common-dev libopenimageio-dev libjansson-dev
  clang libclang-rt-14-dev clang-format
  libnifti2-dev zlib1g-dev mricron-data
  libglfw3-dev xvfb xauth
  gnuplot-nox
  paraview paraview-dev python3-paraview openmpi-bin libopenmpi-dev libglew-dev libfreetype-dev cmake python3
  glslang-tools git time
  emscripten nodejs npm chromium"

# The web package builds jansson for WebAssembly from Debian's source package
# (adapters/web/deps.sh: apt-get source), which needs a deb-src entry for Debian's archive.
src_list=/etc/apt/sources.list.d/libhalo-src.sources
need_src=""
if ! grep -rqs "^Types:.*deb-src\|^deb-src " /etc/apt/sources.list /etc/apt/sources.list.d/; then
  need_src=yes
fi

# A machine whose Node.js is not Debian's (NodeSource's nodejs bundles npm and conflicts
# with Debian's npm package) already has what npm gives: an npm command counts as it.
missing=""
for p in $packages; do
  case $p in npm) command -v npm >/dev/null 2>&1 && continue ;; esac
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
sudo=""
[ "$(id -u)" -eq 0 ] || sudo=sudo
if [ -n "$need_src" ]; then
  echo "setup: adding Debian's source packages ($src_list, for apt-get source jansson)"
  printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: bookworm\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' |
    $sudo tee "$src_list" >/dev/null
fi
if [ -n "$missing" ] || [ -n "$need_src" ]; then
  $sudo apt-get update -q
fi
if [ -n "$missing" ]; then
  echo "setup: installing:$missing"
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends $missing
fi

# Every optional component whose packages are installed above is required: one that
# does not build then fails configure, instead of being left out without notice.
components="--with-egl --with-osmesa --with-glfw --with-vtk --with-paraview --with-web"
[ -x configure ] || autoreconf -fi
[ -f Makefile ] || ./configure $components ${HALO_CONFIGURE_FLAGS:-}
make -j"$(nproc)"

# The browser tests' packages (tests/adapters/web/browser.sh), from the lock file into
# tests/adapters/web/node_modules: puppeteer-core (it drives Debian's chromium; it downloads no
# browser), three (the three.js ray caster, adapters/web/three.mjs), NiiVue (pinned: the
# version adapters/web/niivue.mjs supports) and vtk.js (its UMD bundle, adapters/web/vtkjs.mjs).
for module in puppeteer-core three @niivue/niivue vtk.js; do
  if [ ! -d "tests/adapters/web/node_modules/$module" ]; then
    (cd tests/adapters/web && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error)
    break
  fi
done

# The main job: render the built-in volume with the default scene.
LP_NUM_THREADS=${LP_NUM_THREADS:-2} ./tools/halo-render
