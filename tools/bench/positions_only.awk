# A positions-only OBJ that every tool reads: the `v` lines (first three coordinates, the author's text
# unchanged) and the `f` lines with only their vertex indices (v/vt/vn -> v). Texture coordinates,
# normals, groups, materials and OpenSubdiv tags are dropped.   awk -f positions_only.awk IN > OUT
$1 == "v" { print "v", $2, $3, $4; next }
$1 == "f" { printf "f"; for (i = 2; i <= NF; i++) { split($i, a, "/"); printf " %s", a[1] } printf "\n" }
