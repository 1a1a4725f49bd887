#!/bin/sh
# deps.sh DEST: builds jansson (libhalo's JSON library) for WebAssembly into DEST/lib and
# DEST/include, from Debian's source package of the jansson that the native build uses
# (`apt-get source`, which needs a deb-src entry: setup.sh adds one for Debian's main
# archive). EMCC names emscripten's compiler. Nothing is downloaded from anywhere else.
set -eu
dest=$1
emcc=${EMCC:-emcc}
tools=$(dirname "$emcc")
mkdir -p "$dest/src"
dest=$(cd "$dest" && pwd)
cd "$dest/src"
if ! ls jansson_*.orig.tar.* >/dev/null 2>&1; then
    if ! apt-get source --download-only jansson >apt.log 2>&1; then
        cat apt.log >&2
        echo "deps.sh: cannot fetch Debian's source of jansson: apt needs a deb-src entry for Debian's archive" \
            "(setup.sh adds /etc/apt/sources.list.d/libhalo-src.sources; then apt-get update)" >&2
        exit 1
    fi
fi
rm -rf jansson-src build
mkdir jansson-src
tar -xf jansson_*.orig.tar.* -C jansson-src --strip-components=1
# emscripten's tools run on node and need Debian's node-acorn (Debian's emscripten keeps
# its system libraries in its own, frozen cache: EM_CACHE stays unset)
NODE_PATH=/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}
export NODE_PATH
"$tools/emcmake" cmake -S jansson-src -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$dest" \
    -DJANSSON_BUILD_DOCS=OFF -DJANSSON_WITHOUT_TESTS=ON -DJANSSON_EXAMPLES=OFF >cmake.log 2>&1 ||
    { cat cmake.log >&2; exit 1; }
"$tools/emmake" make -C build -j2 install >make.log 2>&1 || { cat make.log >&2; exit 1; }
test -f "$dest/lib/libjansson.a"
