#!/bin/sh
# Fuzzes the module parser, the scene reader, the host checks, the polyline reader and the volume loaders
# (examples/volume_io.c: NIfTI and raw) with libFuzzer (clang,
# -fsanitize=fuzzer,address,undefined) for SECONDS each (default 20). Run from a
# configured and built source tree (it needs libhalo/embedded_modules.c). A crash leaves
# its input in tests/fuzz/crashes/; add it to tests/fuzz/corpus/TARGET/ as a regression.
set -eu
seconds=${1:-20}
top=$(cd "$(dirname "$0")/../.." && pwd)
cd "$top"
command -v clang >/dev/null || { echo "run-libfuzzer: clang not found (Debian: clang, libclang-rt-dev)" >&2; exit 77; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cflags="-g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined -DHALO_BUILDING
  -DPACKAGE_VERSION=\"fuzz\" -Ilibhalo -Itests/fuzz $(pkg-config --cflags jansson glslang)"
libs="$(pkg-config --libs jansson glslang) -lSPIRV -lglslang-default-resource-limits -lm -lstdc++ -lpthread"
sources="libhalo/diag.c libhalo/strbuf.c libhalo/glsl_lex.c libhalo/module.c libhalo/library.c libhalo/scene.c
  libhalo/link.c libhalo/link_entry.c libhalo/emit.c libhalo/host_check.c libhalo/program.c libhalo/segment.c libhalo/prepass.c libhalo/compose.c libhalo/piece_expression.c libhalo/contract.c libhalo/host_scan.c libhalo/validate.c libhalo/check.c libhalo/glsl_locate.c libhalo/setup.c libhalo/target.c
  libhalo/embedded_modules.c $out/glslang_parse.o"
mkdir -p tests/fuzz/crashes
# glslang's C++ interface: without RTTI, as glslang is built (UBSan's vptr check would
# need its type information)
# shellcheck disable=SC2086
clang++ $cflags -fno-rtti -c -o "$out/glslang_parse.o" libhalo/glslang_parse.cpp
status=0
for target in module scene host volume polyline; do
    if [ $target = polyline ]; then
        # shellcheck disable=SC2086
        clang $cflags -Iexamples -o "$out/fuzz_$target" tests/fuzz/fuzz_polyline.c examples/linegen.c $sources $libs
    elif [ $target = volume ]; then
        # shellcheck disable=SC2086
        clang $cflags -Iexamples -I/usr/include/nifti -o "$out/fuzz_$target" tests/fuzz/fuzz_volume.c \
            examples/volume_io.c -lnifti2 -lznz -lz -lm
    else
        # shellcheck disable=SC2086
        clang $cflags -o "$out/fuzz_$target" "tests/fuzz/fuzz_$target.c" $sources $libs
    fi
    mkdir -p "$out/corpus_$target"
    case $target in
    module) seeds="glsl/*.glsl glsl/*/*.glsl tests/data/modules/*" ;;
    scene) seeds="examples/scenes/*.json tests/data/scenes/*" ;;
    host) seeds="examples/hosts/*.frag examples/hosts/*.vert tests/data/hosts/*" ;;
    volume) seeds="tests/data/volumes/*" ;;
    polyline) seeds="" ;;
    esac
    # shellcheck disable=SC2086
    cp $seeds "$out/corpus_$target/" 2>/dev/null || true
    [ -d "tests/fuzz/corpus/$target" ] && cp "tests/fuzz/corpus/$target"/* "$out/corpus_$target/"
    echo "== fuzz_$target for ${seconds}s"
    if ! ASAN_OPTIONS=detect_leaks=0 "$out/fuzz_$target" -max_total_time="$seconds" -max_len=8192 \
        -artifact_prefix="tests/fuzz/crashes/${target}-" "$out/corpus_$target" 2>"$out/log_$target"; then
        tail -40 "$out/log_$target" >&2
        status=1
    else
        grep -E "^#[0-9]+.*(DONE|pulse)" "$out/log_$target" | tail -1
    fi
done
exit $status
