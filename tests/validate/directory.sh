#!/bin/sh
# A folder where a file is expected: the message says so ("Is a directory"), never a bare
# "Input/output error" or "read error"; exit status 2 (I/O).
. "$srcdir/tests/validate/common.sh"
mkdir "$tmp/folder.json" "$tmp/folder.frag"
run 2 "$HALO_VALIDATE" check "$tmp/folder.frag"
expect_stderr "folder\.frag: error: cannot read file: Is a directory"
run 2 "$HALO_VALIDATE" link --host "$tmp/folder.frag"
expect_stderr "folder\.frag: error: cannot read file: Is a directory"
run 2 "$HALO_RENDER" --scene "$tmp/folder.json" --size 8x8 --quiet -o "$tmp/x.png"
expect_stderr "folder\.json: error: cannot read scene: Is a directory"
finish
