#!/bin/sh
# GLSL errors as GCC and clang print them: file:line:col at the token the message is
# about (not the first substring match, not column 1 for an empty token), a missing ';'
# at the end of the token before it, an error in a macro's expansion at the macro's use
# and one in a call split over lines at the call's name, no names of libhalo's own
# (renamed helpers, the check host), one message per problem (no cascade), an error
# found for several targets printed once naming them, and the caret gutter aligned past
# line 99 999.
. "$srcdir/tests/validate/common.sh"

# count_errors: the number of "error:" lines of the last command
count_errors() {
    grep -c ": error: " "$tmp/err"
}

cat >"$tmp/columns.frag" <<'EOF'
#version 330 core
out vec4 color;
float twice(float x) { return 2.0 * x; }
void main() {
    float value = 1.0;
    float v = value + valu;
    vec4 x = vec4(1.0) + vec4(2.0) + vec3(1.0);
    float w = twice(value, value) + twice(value);
    float y = 2.0
    color = x * v * w;
}
EOF
run 1 "$HALO_VALIDATE" check --target 330 "$tmp/columns.frag"
# 'valu' is the whole token at column 23, not the start of 'value' at 15
expect_stderr "columns\.frag:6:23: error: 'valu' : undeclared identifier"
# the second '+' (vec4 + vec3), not the first
expect_stderr "columns\.frag:7:36: error: '\+'"
# the call with two arguments: at its name
expect_stderr "columns\.frag:8:15: error: 'twice'"
# a missing ';': after '2.0' on line 9, not at column 1 of line 10
expect_stderr "columns\.frag:9:18: error: syntax error"
if grep -q "columns\.frag:10:" "$tmp/err"; then fail "the missing ';' is reported on the next line"; fi
if grep -q "'' :" "$tmp/err"; then fail "an empty token ('') in a message"; fi
# the caret under column 23 of line 6
grep -A2 "columns\.frag:6:23:" "$tmp/err" | tail -1 | grep -q '^       |                       \^$' ||
    fail "the caret of line 6 is not under column 23"

# An error inside a macro's expansion is at the macro's use, not at its ')'; an error in
# a call split over lines is at the call's name (glslang reports the call's last line).
cat >"$tmp/spans.frag" <<'EOF'
#version 330 core
#define SCALE(x) ((x) * undefined_factor)
out vec4 color;
float pair(float a, float b) { return a + b; }
void main() {
    float v = SCALE(2.0);
    float u = pair(1.0,
                   vec2(2.0));
    color = vec4(v + u);
}
EOF
run 1 "$HALO_VALIDATE" check --target 330 "$tmp/spans.frag"
expect_stderr "spans\.frag:6:15: error: 'undefined_factor' : undeclared identifier"
expect_stderr "spans\.frag:7:15: error: 'pair' : no matching overloaded function found"

# One problem, one message: the failed call's placeholder result and the syntax error
# after an unknown type name are not errors of their own.
cat >"$tmp/cascade.frag" <<'EOF'
#version 330 core
out vec4 color;
void main() {
    vec3 n = normalise(vec3(1.0));
    unknown_type x = 1.0;
    color = vec4(n, 1.0);
}
EOF
run 1 "$HALO_VALIDATE" check --target 330 "$tmp/cascade.frag"
test "$(count_errors)" -eq 2 || fail "cascade.frag: $(count_errors) errors for 2 problems"
expect_stderr "cascade\.frag:4:14: error: 'normalise'"
expect_stderr "cascade\.frag:5:5: error: 'unknown_type' : undeclared identifier"

# A module: its helper by the name it wrote, an entry that does not fit at the entry,
# each error once for the three default targets, naming them, in the words of the
# language (no glslang storage or precision bookkeeping in the types).
cat >"$tmp/names.glsl" <<'EOF'
#pragma halo module names_test
#pragma halo hook sample
#pragma halo summary "GLSL errors in a module"
float helper(float x)
{
    return 2.0 * x;
}
void apply(inout halo_sample s, float extra)
{
    s.opacity = helper(s.opacity, extra);
    int steps = 1.5;
}
EOF
run 1 "$HALO_VALIDATE" check "$tmp/names.glsl"
expect_stderr "names\.glsl:10:17: error: 'helper' : no matching overloaded function found \[330, 450, es300\]"
expect_stderr "names\.glsl:8:6: error: 'apply' : no matching overloaded function found \[330, 450, es300\]"
if grep -q "halo_names_test_\|<check-host>\|<libhalo>" "$tmp/err"; then fail "libhalo's own names in the messages"; fi
# glslang's bookkeeping (temp, global, precision) left out: the same text for ES 300
expect_stderr "names\.glsl:11:15: error: '=' : cannot convert from 'const float' to 'int' \[330, 450, es300\]"
test "$(count_errors)" -eq 3 || fail "names.glsl: $(count_errors) errors for 3 problems (each printed once?)"

# The gutter: as wide as the line number.
awk 'BEGIN { print "#version 330 core"; print "out vec4 color;"; print "void main() {";
             for (i = 0; i < 123452; i++) print ""; print "    color = vec4(missing);"; print "}" }' >"$tmp/long.frag"
run 1 "$HALO_VALIDATE" check --target 330 "$tmp/long.frag"
expect_stderr "long\.frag:123456:18: error: 'missing'"
source_bar=$(grep -n "123456 | " "$tmp/err" | head -1 | sed 's/^[0-9]*://' | awk -F'|' '{ print length($1) }')
caret_bar=$(grep "^ *| *\^" "$tmp/err" | head -1 | awk -F'|' '{ print length($1) }')
test -n "$source_bar" && test "$source_bar" = "$caret_bar" ||
    fail "the gutter of line 123456 is misaligned ('$source_bar' against '$caret_bar')"
finish
