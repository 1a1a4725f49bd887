# awk -v dir=DIR -f compose.awk TEMPLATE: the template with each //ENGINE::NAME line
# replaced by the piece DIR/name.glsl (what halo-validate link --pieces-dir writes).
/^\/\/ENGINE::/ {
    file = dir "/" tolower(substr($0, 11)) ".glsl"
    while ((getline line < file) > 0) print line
    close(file)
    next
}
{ print }
