# xrun, sourced by the tests that need an X display (tests/tools/halo-view/, tests/adapters/vtk/); needs $tmp.
# xrun COMMAND...: runs it on a private X server (Xvfb, 24-bit screen). xvfb-run -a
# looks for a free display number from -n on, racing with other tests doing the same
# (make -j check): each test starts from its own number, and a server that failed to
# start is retried on another.
xdisplay=$((200 + $$ % 600))
xrun() {
    xattempt=0
    while :; do
        xattempt=$((xattempt + 1))
        xvfb-run -a -n "$xdisplay" -s "-screen 0 1280x1024x24" "$@" 2>"$tmp/xrun.err"
        xstatus=$?
        # xvfb-run itself can fail: Xvfb not starting, or (on a loaded machine) its own
        # temporary folder not removed in time, which replaces the command's status by 5
        if test "$xstatus" -ne 0 && test "$xattempt" -lt 5 &&
            grep -E -q "Xvfb failed to start|problem while cleaning up temporary directory" "$tmp/xrun.err"; then
            echo "    (xvfb-run failed on :$xdisplay: $(grep -E -o 'Xvfb failed to start|problem while cleaning up' "$tmp/xrun.err" | head -1); retrying)"
            xdisplay=$((xdisplay + 37))
            sleep 1
            continue
        fi
        cat "$tmp/xrun.err" >&2
        return "$xstatus"
    done
}

