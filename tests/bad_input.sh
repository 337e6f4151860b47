#!/usr/bin/env bash
# Bad input must end with one line "signorini: error: ..." naming the culprit
# and a non-zero exit code, never an abort, a segfault or a backtrace.
# Usage: bad_input.sh SIGNORINI_EXECUTABLE SOURCE_DIR
set -u
exe=$1
# (absolute: the cases name files from parameter files in other directories)
src=$(cd "$2" && pwd)
# the tests' copy of the block example (the line numbers in the expected
# messages below count its 49 lines); the tests do not read prm/
block=$src/tests/inputs/block.prm
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
count=0

# check_exit CODE NAME EXPECTED_SUBSTRING ARGS...: exit code CODE (1 for bad
# input, 2 for a computation that failed), one line on stderr
check_exit() {
  local want=$1 name=$2 expected=$3
  shift 3
  count=$((count + 1))
  "$exe" "$@" > "$work/stdout" 2> "$work/stderr"
  local code=$?
  local lines
  lines=$(wc -l < "$work/stderr")
  if [ "$code" -ne "$want" ] || [ "$lines" -ne 1 ] ||
     ! grep -q "^signorini: error: .*$expected" "$work/stderr" ||
     grep -q -i -E "stacktrace|aborted|segmentation" "$work/stderr" "$work/stdout"; then
    echo "FAIL $name (exit $code, expected $want):"
    cat "$work/stderr"
    failures=$((failures + 1))
  else
    echo "ok   $name: $(cat "$work/stderr")"
  fi
}

# check NAME EXPECTED_SUBSTRING ARGS...: an input error (exit 1)
check() {
  check_exit 1 "$@"
}

# case_prm NAME EXPECTED TEXT: the block example with TEXT appended, an input
# error; case_prm_exit CODE NAME EXPECTED TEXT: the same with exit code CODE
case_prm_exit() {
  local want=$1 name=$2 expected=$3 text=$4
  { cat "$block"; printf '%s\n' "$text"; } > "$work/case.prm"
  printf 'set Output directory = %s/out\n' "$work" >> "$work/case.prm"
  check_exit "$want" "$name" "$expected" "$work/case.prm"
}
case_prm() {
  case_prm_exit 1 "$@"
}

printf 'not a mesh\n' > "$work/garbage.msh"

# Dimension: read first; 3 with the defaults builds the 3D block, which
# nothing holds
printf 'set Dimension = 3\nset Output directory = %s/out\n' "$work" > "$work/dim3.prm"
check "Dimension = 3" "Dimension = 3: the body is free to move" \
  "$work/dim3.prm"
printf 'set Dimension = 3\nset Output directory = %s/out\nsubsection Mesh\n  set Block subdivisions = 4, 3\nend\n' "$work" > "$work/dim3-subdivisions.prm"
check "Dimension = 3, two subdivisions" "Dimension = 3: parameter file .*: line 4: Mesh/Block subdivisions: The entry value 4, 3" \
  "$work/dim3-subdivisions.prm"
case_prm "Dimension = 4" "Dimension: The entry value 4" "set Dimension = 4"
case_prm "Dimension = 3 with 2D data" "Dimension = 3: parameter file .*: line 13: Mesh/Block subdivisions: The entry value 4, 3" \
  "set Dimension = 3"

# remeshing_case NAME EXPECTED MESH [GEOMETRY]: the block example remeshed
# from the Gmsh file MESH with the .geo GEOMETRY (none if not given)
remeshing_case() {
  local geometry=""
  [ $# -ge 4 ] && geometry="
  set Geometry file = $4"
  case_prm "$1" "$2" "subsection Mesh
  set Source = file
  set File name = $3$geometry
end
subsection Mesh adaptation
  set Realisation = remeshing
end"
}
square="$src/tests/meshes/square-22.msh"
remeshing_case "remeshing a mesh file" \
  "Mesh adaptation/Realisation = remeshing needs the geometry" "$square"
remeshing_case "missing geometry file" "Mesh/Geometry file: cannot open" \
  "$square" no-such-file.geo
printf 'this is not a geometry\n' > "$work/garbage.geo"
remeshing_case "unreadable geometry file" \
  "Mesh/Geometry file: .*syntax error" "$square" "$work/garbage.geo"
# Gmsh's Exit command ends the program: an error, not a silent success
printf 'Point(1) = {0, 0, 0};\nExit;\n' > "$work/exit.geo"
remeshing_case "geometry file that calls Exit" \
  "Mesh/Geometry file <$work/exit.geo>: Gmsh ended the program" "$square" "$work/exit.geo"
sed 's/Physical Curve(2) = {1};/Physical Curve(7) = {1};/' \
  "$src/tests/meshes/hertz-geometry.geo" > "$work/retagged.geo"
remeshing_case "geometry without a boundary id in use" \
  "no physical curve has the tag 2" "$src/tests/meshes/hertz-coarse.msh" \
  "$work/retagged.geo"
case_prm "missing mesh file" "cannot open mesh file" \
  "subsection Mesh
  set Source = file
  set File name = no-such-file.msh
end"
case_prm "unreadable mesh file" "cannot read mesh file" \
  "subsection Mesh
  set Source = file
  set File name = $work/garbage.msh
end"
case_prm "optimal sizes without the estimator" "Mesh adaptation/Strategy" \
  "subsection Error estimator
  set Enable = false
end
subsection Mesh adaptation
  set Strategy = optimal size
  set Target error = 0.02
end"
case_prm "optimal sizes without a target" "Mesh adaptation/Target error" \
  "subsection Mesh adaptation
  set Strategy = optimal size
end"
case_prm "contact id absent" "Contact/Boundary ids: boundary id 9" \
  "subsection Contact
  set Boundary ids = 9
end"
case_prm "Dirichlet id absent" "Dirichlet: boundary id 42" \
  "subsection Boundary conditions
  subsection Dirichlet 1
    set Boundary ids = 42
  end
end"
case_prm "nu = 0.5" "Material/Poisson ratio" \
  "subsection Material
  set Poisson ratio = 0.5
end"
case_prm "nu > 0.5" "Material/Poisson ratio" \
  "subsection Material
  set Poisson ratio = 0.7
end"
case_prm "E = 0" "Material/Young modulus" \
  "subsection Material
  set Young modulus = 0
end"
case_prm "E < 0" "Material/Young modulus" \
  "subsection Material
  set Young modulus = -3
end"
case_prm "unknown parameter" "Poisson ration" \
  "subsection Material
  set Poisson ration = 0.3
end"
case_prm "malformed function" "Traction 1" \
  "subsection Boundary conditions
  subsection Traction 1
    set Function expression = 0; -p*(x
  end
end"
case_prm "wrong number of components" "Traction 2" \
  "subsection Boundary conditions
  subsection Traction 2
    set Function expression = -p
  end
end"
case_prm "unknown constant in gap" "Contact/Gap" \
  "subsection Contact
  subsection Gap
    set Function expression = gap0*x
  end
end"
case_prm "zero contact direction" "Contact/Direction" \
  "subsection Contact
  set Direction = 0, 0
end"
case_prm "invalid selection" "Condition" \
  "subsection Contact
  set Condition = mortar
end"
check "missing parameter file" "no-such-file.prm" "$work/no-such-file.prm"

# --- meshes: malformed and degenerate Gmsh files ---

# tests/meshes/square-22.msh and square-41.msh (from square.geo) are the unit
# square with the block's boundary ids: valid, then corrupted one way each.
msh22=$src/tests/meshes/square-22.msh
msh41=$src/tests/meshes/square-41.msh

# mesh_prm FILE: the Mesh subsection reading FILE
mesh_prm() {
  printf 'subsection Mesh\n  set Source    = file\n  set File name = %s\nend' "$1"
}
# mesh_case NAME EXPECTED FILE: reading FILE is an input error
mesh_case() {
  case_prm "$1" "$2" "$(mesh_prm "$3")"
}
# valid_prm NAME ARGS... PRM: signorini ARGS PRM exits 0 without a word on
# stderr
valid_prm() {
  local name=$1
  shift
  count=$((count + 1))
  "$exe" "$@" > "$work/stdout" 2> "$work/stderr"
  local code=$?
  if [ "$code" -ne 0 ] || [ -s "$work/stderr" ]; then
    echo "FAIL $name (exit $code):"
    cat "$work/stderr"
    failures=$((failures + 1))
  else
    echo "ok   $name: $(grep -E ': valid$' "$work/stdout" || echo 'exit 0')"
  fi
}
# mesh_ok NAME FILE: --validate accepts the block example on FILE
mesh_ok() {
  { cat "$block"; mesh_prm "$2"; echo
    printf 'set Output directory = %s/out\n' "$work"; } > "$work/case.prm"
  valid_prm "$1" --validate "$work/case.prm"
}

mesh_ok "Gmsh 2.2 mesh" "$msh22"
mesh_ok "Gmsh 4.1 mesh" "$msh41"
awk '$2 == 2 && NF == 8 { t = $7; $7 = $8; $8 = t } { print }' "$msh22" \
  > "$work/clockwise.msh"
mesh_ok "clockwise triangles" "$work/clockwise.msh"
sed 's/^12$/13/; s/^\$EndNodes$/13 3 3 0\n$EndNodes/' "$msh22" > "$work/unused.msh"
mesh_ok "a node no triangle uses" "$work/unused.msh"
sed 's/$/\r/; 3a $Comments\r\nwritten on Windows\r\n$EndComments\r' "$msh41" \
  > "$work/crlf.msh"
mesh_ok "CRLF line ends, a comment section" "$work/crlf.msh"
sed '3a $PhysicalNames\n1\n1 2 "contact zone"\n$EndPhysicalNames' "$msh22" \
  > "$work/names.msh"
mesh_ok "physical names" "$work/names.msh"
{ cat "$block"; mesh_prm "$msh41"; echo
  printf 'set Number of cycles = 1\nset Output directory = %s/out\n' "$work"
  printf 'subsection Output\n  set Write vtu = false\nend\n'; } > "$work/case.prm"
valid_prm "a computation on the Gmsh 4.1 mesh" "$work/case.prm"

# not a usable file
printf '$MeshFormat\n4.1 1 8\n\001\000\000\000\n$EndMeshFormat\n' > "$work/binary.msh"
mesh_case "binary Gmsh file" "is a binary Gmsh file; save it as ASCII" "$work/binary.msh"
: > "$work/empty.msh"
mesh_case "empty mesh file" "empty.msh> is empty" "$work/empty.msh"
mesh_case "mesh file is a directory" "it is a directory" "$work"
mesh_case "mesh file /dev/zero (endless)" "it is not a regular file" /dev/zero
sed '2s/^2.2 /3.0 /' "$msh22" > "$work/v3.msh"
mesh_case "msh 3" "version <3.0> is not supported" "$work/v3.msh"

# structure: counts, sections, numbers (deal.II's reader crashed, aborted or
# hung on the first ones)
sed '2s/^2.2 /4.1 /' "$msh22" > "$work/mixed.msh"
mesh_case "2.2 body under a 4.1 header" 'line 5: the header of $Nodes' "$work/mixed.msh"
sed '5s/^12$/14/' "$msh22" > "$work/more-nodes.msh"
mesh_case "2.2: node count too large" 'found <$EndNodes> where node 13 of 14' "$work/more-nodes.msh"
sed '5s/^12$/11/' "$msh22" > "$work/fewer-nodes.msh"
mesh_case "2.2: node count too small" 'line 17: expected $EndNodes, found <12 ' "$work/fewer-nodes.msh"
sed 's/^13 12 1 12$/13 14 1 12/' "$msh41" > "$work/more-nodes41.msh"
mesh_case "4.1: node count too large" '$Nodes announces 14 nodes, its blocks hold 12' "$work/more-nodes41.msh"
sed 's/^2 1 0 4$/2 1 0 3/' "$msh41" > "$work/short-block.msh"
mesh_case "4.1: node block count too small" "coordinates of node 9 " "$work/short-block.msh"
sed 's/^7 22 1 22$/8 22 1 22/' "$msh41" > "$work/more-blocks.msh"
mesh_case "4.1: element block count too large" \
  'found <$EndElements> where the header of element block 8 of 8' "$work/more-blocks.msh"
sed 's/^7 22 1 22$/6 22 1 22/' "$msh41" > "$work/fewer-blocks.msh"
mesh_case "4.1: element block count too small" \
  '$Elements announces 22 elements, its blocks hold 8' "$work/fewer-blocks.msh"
sed 's/^13 12 1 12$/13 -12 1 12/' "$msh41" > "$work/negative.msh"
mesh_case "negative node count" "number of nodes -12 is below 0" "$work/negative.msh"
sed '5s/^12$/1000000000000/' "$msh22" > "$work/huge.msh"
mesh_case "node count 1e12" "node 13 of 1000000000000 was expected" "$work/huge.msh"
sed 's/^2 1 0 4$/2 1 0 1000000000000/' "$msh41" > "$work/huge-block.msh"
mesh_case "node block of 1e12 nodes" \
  'node block 13 of 13 has 1000000000000 nodes, but $Nodes announces 12' "$work/huge-block.msh"
sed 's/^9 0.2937499999998369 /9 0.29x /' "$msh22" > "$work/letters.msh"
mesh_case "non-numeric coordinate" "line 14: coordinate of node 9 <0.29x> is not a finite number" \
  "$work/letters.msh"
sed 's/^9 0.2937499999998369 /9 nan /' "$msh22" > "$work/nan.msh"
mesh_case "NaN coordinate" "coordinate of node 9 <nan> is not a finite number" "$work/nan.msh"
sed 's/^22 2 2 1 1 8 9 11$/22 2 2 1 1 8 9 99/' "$msh22" > "$work/missing-node.msh"
mesh_case "element on a missing node" "line 42: element 22 refers to node 99, which is not in" \
  "$work/missing-node.msh"
head -n 70 "$msh41" > "$work/truncated.msh"
mesh_case "truncated between lines" 'line 70: the file ends where the header of element block 5 of 7' \
  "$work/truncated.msh"
head -c 1000 "$msh41" > "$work/truncated-in-line.msh"
mesh_case "truncated inside a line" "cannot read mesh file" "$work/truncated-in-line.msh"
sed '/^\$EndNodes$/d' "$msh22" > "$work/no-end.msh"
mesh_case "section not closed" 'expected $EndNodes, found <$Elements>' "$work/no-end.msh"
sed '3a $PhysicalNames\n1\n1 2 "contact zone"' "$msh22" > "$work/names-open.msh"
mesh_case "unclosed \$PhysicalNames (deal.II hung)" \
  'expected $EndPhysicalNames, found <$Nodes>' "$work/names-open.msh"
sed 's/^0 1 0 1$/0 1 1 1/' "$msh41" > "$work/parametric.msh"
mesh_case "parametric nodes" "has parametric coordinates" "$work/parametric.msh"
sed 's/^1 1 1 2$/1 9 1 2/' "$msh41" > "$work/entity.msh"
mesh_case "element block on an undeclared curve" "refers to entity 9 of dimension 1, which is not in" \
  "$work/entity.msh"
sed 's/^1 0 0 0 1 0 0 1 2 2 1 -2 $/1 0 0 0 1 0 0 2 2 7 2 1 -2/' "$msh41" > "$work/two-groups.msh"
mesh_case "curve in two physical groups" "curve 1 belongs to 2 physical groups" "$work/two-groups.msh"

# element types
sed 's/^9 2 2 1 1 5 6 11$/9 3 2 1 1 5 6 11 12/' "$msh22" > "$work/quad.msh"
mesh_case "quadrilateral" "line 29: quadrilateral elements (type 3) are not supported" "$work/quad.msh"
sed 's/^9 2 2 1 1 5 6 11$/9 4 2 1 1 5 6 11 12/' "$msh22" > "$work/tet.msh"
mesh_case "tetrahedron in 2D" "tetrahedra (type 4) are 3D elements: signorini reads them with Dimension = 3" "$work/tet.msh"
sed 's/^9 2 2 1 1 5 6 11$/9 9 2 1 1 5 6 11 1 2 3/' "$msh22" > "$work/tri6.msh"
mesh_case "6-node triangle" "high-order elements (type 9)" "$work/tri6.msh"
sed '/^[0-9]* 2 2 1 1 /d; s/^22$/8/' "$msh22" > "$work/lines.msh"
mesh_case "lines only (1D mesh)" "contains no triangles" "$work/lines.msh"

# degenerate meshes (--validate accepted them; the solver failed)
sed 's/^9 0.2937499999998369 0.293750000000552 0$/9 0.25 0 0/' "$msh22" > "$work/flat.msh"
mesh_case "zero-area triangle" "line 36: triangle 16 has zero area: its nodes 1 (0, 0), 7 (0.5, 0), 9 (0.25, 0)" \
  "$work/flat.msh"
sed 's/^12$/13/; s/^\$EndNodes$/13 0.499999999998694 0 0\n$EndNodes/
     s/^16 2 2 1 1 1 7 9$/16 2 2 1 1 1 13 9/' "$msh22" > "$work/twin.msh"
mesh_case "two nodes at one point (a crack)" "nodes 7 and 13 are at the same point (0.5, 0)" \
  "$work/twin.msh"
sed 's/^22$/23/; s/^\$EndElements$/23 2 2 1 1 8 9 11\n$EndElements/' "$msh22" > "$work/twice.msh"
mesh_case "repeated triangle" "triangles 22 and 23 overlap" "$work/twice.msh"
sed 's/^22$/23/; s/^\$EndElements$/23 1 2 7 1 9 11\n$EndElements/' "$msh22" > "$work/inner.msh"
mesh_case "boundary id on an interior edge" "line element 23 (physical tag 7, nodes 9 and 11) lies inside" \
  "$work/inner.msh"
sed 's/^12 0.71874999999981 0.71874999999981 0$/12 0.71874999999981 0.71874999999981 0.5/' \
  "$msh22" > "$work/warped.msh"
mesh_case "node out of the plane" "node 12 has z = 0.5 while node 1 has z = 0" "$work/warped.msh"
# node 5 halves the edge 2-3 of triangle 1 only: a T-junction
cat > "$work/hanging.msh" << 'MESH'
$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
5
1 0 0 0
2 2 0 0
3 0 2 0
4 2 2 0
5 1 1 0
$EndNodes
$Elements
3
1 2 2 1 1 1 2 3
2 2 2 1 1 2 4 5
3 2 2 1 1 5 4 3
$EndElements
MESH
mesh_case "hanging node" "line 10: node 5 (1, 1) lies on the edge between nodes 2 and 3" \
  "$work/hanging.msh"
awk '$2 == 1 && NF == 7 { $4 = 0 } { print }' "$msh22" > "$work/no-ids.msh"
mesh_case "no boundary ids" "boundary id 1 does not exist in the mesh" "$work/no-ids.msh"

# --- parameter files and numbers (B) ---
: > "$work/empty.prm"
check "empty parameter file" "empty.prm>: is empty" "$work/empty.prm"
printf '# nothing\n\n   # set Young modulus = 2\n' > "$work/comments.prm"
check "parameter file of comments" "comments.prm>: is empty (only comments)" "$work/comments.prm"
mkdir -p "$work/dir.prm"
check "parameter file is a directory" "dir.prm>: is a directory" "$work/dir.prm"
check "parameter file /dev/zero" "zero>: is not a regular file" /dev/zero
{ printf '\357\273\277'; cat "$block"
  printf 'set Output directory = %s/out\n' "$work"; } > "$work/bom.prm"
valid_prm "UTF-8 byte order mark" --validate "$work/bom.prm"
case_prm "constant p=0.1x" "Traction 1: Function constants = p=0.1x: the value <0.1x> of p" \
  "subsection Boundary conditions
  subsection Traction 1
    set Function constants = p=0.1x
  end
end"
case_prm "constant p=abc" "Traction 2: Function constants = p=abc: the value <abc> of p" \
  "subsection Boundary conditions
  subsection Traction 2
    set Function constants = p=abc
  end
end"
case_prm "constant defined twice" "Function constants = p=0.1, p=0.2: p is defined twice" \
  "subsection Boundary conditions
  subsection Traction 1
    set Function constants = p=0.1, p=0.2
  end
end"
for value in 1e-400 1e-310 nan inf -inf 1e400; do
  case_prm "Young modulus = $value" "Material/Young modulus" \
    "subsection Material
  set Young modulus = $value
end"
done
for value in 1e-400 nan inf 1e400; do
  case_prm "Poisson ratio = $value" "Material/Poisson ratio" \
    "subsection Material
  set Poisson ratio = $value
end"
done

# --- non-finite data, parameter files, contact warnings ---

# Functions are evaluated where they are used on each mesh (vertices and
# quadrature points): NaN or inf is an input error naming the parameter.
case_prm "gap NaN beyond x = 1/2" "Contact/Gap: Function expression is not finite (nan) at (" \
  "subsection Contact
  subsection Gap
    set Function expression = 1 - sqrt(1 - 4*x^2)
  end
end"
case_prm "gap finite on the first mesh, NaN on the refined one" \
  "Contact/Gap: Function expression is not finite (nan)" \
  "set Number of cycles = 2
subsection Output
  set Write vtu = false
end
subsection Contact
  subsection Gap
    set Function expression = sqrt((x - 0.005)*(x - 0.02))
  end
end"
case_prm "traction sqrt(-1)" \
  "Boundary conditions/Traction 1: Function expression is not finite (nan) at (" \
  "subsection Boundary conditions
  subsection Traction 1
    set Function expression = 0; sqrt(-1)
  end
end"
case_prm "traction 1/0" \
  "Boundary conditions/Traction 2: Function expression is not finite (inf)" \
  "subsection Boundary conditions
  subsection Traction 2
    set Function expression = 1/0; 0
  end
end"
case_prm "Dirichlet NaN on a prescribed component" \
  "Boundary conditions/Dirichlet 1: Function expression is not finite (nan)" \
  "subsection Boundary conditions
  subsection Dirichlet 1
    set Function expression = 0; sqrt(y - 0.5)
  end
end"
case_prm "body force inf at a vertex" \
  "Boundary conditions/Body force: Function expression is not finite (inf)" \
  "subsection Boundary conditions
  subsection Body force
    set Function expression = 0; 1/(x - 0.5)
  end
end"
case_prm "exact solution NaN" "Exact solution: Function expression is not finite (nan)" \
  "subsection Exact solution
  set Enable              = true
  set Function expression = 0; sqrt(x - 2)
end"
case_prm "contact direction nan" "Contact/Direction" \
  "subsection Contact
  set Direction = nan, -1
end"
case_prm "contact direction -inf" "Contact/Direction" \
  "subsection Contact
  set Direction = 0, -inf
end"
case_prm "two Dirichlet parts prescribe y on id 1" \
  "Boundary conditions/Dirichlet 2: boundary id 1, component y is already prescribed by Dirichlet 1" \
  "subsection Boundary conditions
  subsection Dirichlet 2
    set Boundary ids        = 1
    set Components          = y
    set Function expression = 0; 0
  end
end"

# run_ok NAME TEXT ARGS...: the block (one cycle unless TEXT says otherwise)
# with TEXT appended runs with exit 0; ARGS are put before the parameter file
# (e.g. --validate). Leaves the screen output in $work/stdout and the results
# in $work/out.
run_ok() {
  local name=$1 text=$2
  shift 2
  { cat "$block"
    printf 'set Number of cycles = 1\nset Output directory = %s/out\n' "$work"
    printf 'subsection Output\n  set Write vtu = false\nend\n'
    printf '%s\n' "$text"
  } > "$work/case.prm"
  rm -rf "$work/out"
  "$exe" "$@" "$work/case.prm" > "$work/stdout" 2> "$work/stderr"
  local code=$?
  if [ "$code" -ne 0 ] || [ -s "$work/stderr" ]; then
    echo "FAIL $name (exit $code):"
    cat "$work/stderr"
    return 1
  fi
}

# warns NAME EXPECTED TEXT: questionable data is run (exit 0) with exactly
# one screen line "Warning: ...EXPECTED"
warns() {
  local name=$1 expected=$2 text=$3
  count=$((count + 1))
  if ! run_ok "$name" "$text"; then
    failures=$((failures + 1))
  elif [ "$(grep -c "^Warning: .*$expected" "$work/stdout")" -ne 1 ]; then
    echo "FAIL $name: no single warning line with <$expected> on the screen"
    failures=$((failures + 1))
  else
    echo "ok   $name: $(grep "^Warning: " "$work/stdout")"
  fi
}

warns "negative gap, two cycles, one warning" \
  "Contact/Gap is negative (-0.01) at (" \
  "set Number of cycles = 2
subsection Contact
  subsection Gap
    set Function expression = -0.01
  end
end"
warns "contact direction into the body" "Contact/Direction points into the body" \
  "subsection Contact
  set Direction = 0, 1
end"
warns "contact direction tangent to GC" "Contact/Direction is nearly tangent" \
  "subsection Contact
  set Direction = 1, -0.05
end"

# eps_of NAME TEXT: the eps of the block's first cycle with TEXT appended
eps_of() {
  run_ok "$1" "$2" || return 1
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "eps") c = i }
           NR == 2 { print $c }' "$work/out/statistics.csv"
}

# same_eps NAME TEXT: the same eps (and so the same data) as the block itself
same_eps() {
  count=$((count + 1))
  local eps
  eps=$(eps_of "$1" "$2")
  if [ -n "$eps" ] && [ "$eps" = "$reference_eps" ]; then
    echo "ok   $1: eps = $eps"
  else
    echo "FAIL $1: eps = <$eps>, the block gives $reference_eps"
    failures=$((failures + 1))
  fi
}

# Every part naming a boundary id counts, in the estimator as in the solver
reference_eps=$(eps_of "block" "")
same_eps "Dirichlet 1 split into x and y parts" \
  "subsection Boundary conditions
  subsection Dirichlet 1
    set Components = x
  end
  subsection Dirichlet 2
    set Boundary ids        = 1
    set Components          = y
    set Function expression = 0; 0
  end
end"
same_eps "Traction 1 split into two halves" \
  "subsection Boundary conditions
  subsection Traction 1
    set Function expression = 0; -p/2
  end
  subsection Traction 3
    set Boundary ids        = 3
    set Function constants  = p=0.1
    set Function expression = 0; -p/2
  end
end"
# a direction whose squared norm overflows or underflows is still a direction
same_eps "contact direction 0, -1e300" \
  "subsection Contact
  set Direction = 0, -1e300
end"
same_eps "contact direction 0, -1e-300" \
  "subsection Contact
  set Direction = 0, -1e-300
end"

# --- output directory, size guard, failed computations ---

# outdir_prm FILE DIR [TEXT]: the block example with TEXT, writing into DIR
# (set last: case_prm's own directory would override a case's)
outdir_prm() {
  { cat "$block"; printf '%s\n' "${3:-}"
    printf 'set Output directory = %s\n' "$2"; } > "$1"
}
# expect NAME CONDITION...: a check of the files a run left
expect() {
  local name=$1
  shift
  count=$((count + 1))
  if "$@"; then
    echo "ok   $name"
  else
    echo "FAIL $name"
    failures=$((failures + 1))
  fi
}
quiet='subsection Output
  set Print timing = false
end'

printf 'a file\n' > "$work/afile"
outdir_prm "$work/od.prm" "$work/afile"
check "output directory is a file" "Output directory: <.*afile> exists and is not a directory" \
  "$work/od.prm"
check "output directory is a file (--validate)" "Output directory: <.*afile> exists" \
  --validate "$work/od.prm"
outdir_prm "$work/od.prm" "$work/afile/out"
check "output directory under a file" "Output directory: cannot create <.*afile/out>: Not a directory" \
  "$work/od.prm"
outdir_prm "$work/od.prm" ""
check "output directory empty" "Output directory: empty" "$work/od.prm"
# /proc refuses new files even to root
outdir_prm "$work/od.prm" /proc
check "output directory not writable (/proc)" "Output directory: </proc> is not writable" \
  --validate "$work/od.prm"
if [ "$(id -u)" -eq 0 ]; then
  echo "ok   (skipped: root) read-only output directory (chmod 555)"
else
  mkdir "$work/readonly" && chmod 555 "$work/readonly"
  outdir_prm "$work/od.prm" "$work/readonly"
  check "read-only output directory" "Output directory: <.*readonly> is not writable" \
    "$work/od.prm"
  chmod 755 "$work/readonly"
fi
# --validate checks the directory by creating it, and removes it again
outdir_prm "$work/od.prm" "$work/new/deeper"
expect "--validate leaves no directory behind" \
  eval '"$exe" --validate "$work/od.prm" > /dev/null && [ ! -e "$work/new" ]'

# Maximum cells: the sizes known from the input are refused before any mesh
case_prm "too many uniform cycles" \
  "Number of cycles: 12 uniform cycles need 402653184 cells .*Maximum cells = 4000000 (at most 8 cycles)" \
  "set Number of cycles = 12"
check "too many uniform cycles (--validate)" "Number of cycles: 12" \
  --validate "$work/case.prm"
case_prm "100 uniform cycles" "Number of cycles: 100 uniform cycles" \
  "set Number of cycles = 100"
case_prm "too many initial refinements" \
  "Mesh/Initial refinements: 9 refinements of the 96 initial cells give 25165824 cells, more than Maximum cells" \
  "subsection Mesh
  set Initial refinements = 9
end"
case_prm "reference on the initial mesh too fine" \
  "Reference solution/Extra refinements: 6 extra refinements give a reference mesh of 6291456 cells, more than Maximum cells" \
  "set Number of cycles = 3
subsection Reference solution
  set Extra refinements = 6
end"
case_prm "a lower Maximum cells" "Number of cycles: 4 uniform cycles need 6144 cells" \
  "set Maximum cells = 2000"
# an adapted mesh: refused before it is built, the earlier cycles kept
case_prm_exit 2 "adapted mesh beyond Maximum cells" \
  "Maximum cells: the adapted mesh of cycle 2 would have about 6291456 cells, more than Maximum cells = 4000000" \
  "set Number of cycles = 3
subsection Mesh adaptation
  set Strategy     = optimal size
  set Target error = 1e-4
end
$quiet"
expect "adapted mesh beyond Maximum cells: cycles 0 and 1 written" \
  eval '[ -f "$work/out/contact-00.csv" ] && [ -f "$work/out/contact-01.csv" ] &&
        [ ! -e "$work/out/contact-02.csv" ] &&
        [ "$(cut -d, -f1 "$work/out/statistics.csv" | tr "\n" " ")" = "cycle 0 1 " ]'

# An output directory holds one run: a rerun with fewer cycles deletes what
# the earlier run wrote (its manifest), and nothing the user put there (a
# file with a name the run writes is refused: see the hostile section)
mkdir "$work/rerun"
printf 'mine\n' > "$work/rerun/notes.txt"
printf 'mine\n' > "$work/rerun/contact.csv"
outdir_prm "$work/rerun.prm" "$work/rerun" "set Number of cycles = 3
$quiet"
"$exe" "$work/rerun.prm" > /dev/null 2>&1
outdir_prm "$work/rerun.prm" "$work/rerun" "set Number of cycles = 1
$quiet"
"$exe" "$work/rerun.prm" > /dev/null 2>&1
want=".signorini-manifest contact-00.csv contact.csv notes.txt \
parameters.prm solution-00.vtu solution.pvd statistics.csv "
listing=$(LC_ALL=C ls -A "$work/rerun" | tr '\n' ' ')
expect "rerun with fewer cycles leaves no file of the earlier run" \
  [ "$listing" = "$want" ]
[ "$listing" = "$want" ] || echo "     (left: $listing)"
expect "user files in the output directory survive a rerun" \
  eval '[ "$(cat "$work/rerun/notes.txt" "$work/rerun/contact.csv")" = "mine
mine" ]'

# a full disk mid-run (a file of cycle 1 is a /dev/full node, listed as an
# earlier run's: a link would be refused, a listed regular file deleted): a
# failed computation naming the file, cycle 0 written
mkdir "$work/full"
if mknod "$work/full/contact-01.csv" c 1 7 2> /dev/null; then
  printf 'contact-01.csv\n' > "$work/full/.signorini-manifest"
  outdir_prm "$work/full.prm" "$work/full" "$quiet"
  check_exit 2 "disk full in cycle 1" "cannot write <.*full/contact-01.csv>: No space left on device" \
    "$work/full.prm"
  expect "disk full in cycle 1: cycle 0 written" \
    [ -f "$work/full/contact-00.csv" -a -f "$work/full/solution-00.vtu" ]
else
  echo "ok   (skipped: no mknod) disk full in cycle 1"
fi

# --- hostile output directories and MPI ---

# A run writes only files it owns, never through a link
mkdir "$work/mlink"
printf 'keep\n' > "$work/victim"
ln -s "$work/victim" "$work/mlink/.signorini-manifest"
outdir_prm "$work/od.prm" "$work/mlink" "$quiet"
check "manifest is a symbolic link" \
  "Output directory: <.*mlink/.signorini-manifest> is a symbolic link" \
  "$work/od.prm"
expect "manifest link: its target untouched" \
  eval '[ "$(cat "$work/victim")" = keep ]'
mkdir -p "$work/mdir/.signorini-manifest"
outdir_prm "$work/od.prm" "$work/mdir" "$quiet"
check "manifest is a directory (--validate)" \
  "Output directory: <.*mdir/.signorini-manifest> is a directory" \
  --validate "$work/od.prm"
mkdir "$work/own"
printf 'mine\n' > "$work/own/parameters.prm"
outdir_prm "$work/od.prm" "$work/own" "$quiet"
check "user's parameters.prm in the output directory" \
  "Output directory: <.*own> holds parameters.prm, which no earlier run listed in .signorini-manifest; choose another directory or remove it" \
  "$work/od.prm"
check "user's parameters.prm (--validate)" "holds parameters.prm, which no" \
  --validate "$work/od.prm"
rm "$work/own/parameters.prm"
printf 'mine\n' > "$work/own/solution-03.002.vtu"
check "user's solution piece in the output directory" \
  "holds solution-03.002.vtu, which no earlier run listed" "$work/od.prm"
expect "user's files untouched" \
  eval '[ "$(cat "$work/own/solution-03.002.vtu")" = mine ] &&
        [ ! -e "$work/own/.signorini-manifest" ]'
mkdir "$work/slink"
ln -s "$work/victim" "$work/slink/statistics.csv"
printf 'statistics.csv\n' > "$work/slink/.signorini-manifest"
outdir_prm "$work/od.prm" "$work/slink" "$quiet"
check "statistics.csv a symbolic link (listed)" \
  "holds statistics.csv, a symbolic link the run would write through" \
  "$work/od.prm"
expect "statistics.csv link: its target untouched" \
  eval '[ "$(cat "$work/victim")" = keep ]'
# the good paths: a fresh directory, then a rerun into it
outdir_prm "$work/od.prm" "$work/fresh/dir" "set Number of cycles = 2
$quiet"
expect "run into a fresh directory, then a rerun into it" \
  eval '"$exe" "$work/od.prm" > /dev/null && "$exe" "$work/od.prm" > /dev/null &&
        [ -f "$work/fresh/dir/contact-01.csv" ]'

# --validate refuses a direct solver package this Trilinos lacks
case_prm "direct package not built into Trilinos (--validate)" \
  "Linear solver/Direct solver package = Amesos_Umfpack: not available in this Trilinos build (available: Amesos_Klu" \
  "subsection Linear solver
  set Direct solver package = Amesos_Umfpack
end"
check "direct package (--validate)" "Amesos_Umfpack: not available" \
  --validate "$work/case.prm"

# Under MPI, an error met by every rank is one line and a normal exit (no
# abort). Without -q, Open MPI's mpirun adds its own 9-line note that a
# process exited non-zero ("Primary job  terminated normally, but 1 process
# returned a non-zero exit code..."): -q silences it, leaving our line alone.
# check_mpi CODE NAME EXPECTED NP ARGS...
check_mpi() {
  local want=$1 name=$2 expected=$3 np=$4
  shift 4
  count=$((count + 1))
  mpirun -q --oversubscribe -np "$np" "$exe" "$@" > "$work/stdout" 2> "$work/stderr"
  local code=$?
  if [ "$code" -ne "$want" ] || [ "$(wc -l < "$work/stderr")" -ne 1 ] ||
     ! grep -q "^signorini: error: .*$expected" "$work/stderr" ||
     grep -q -i -E "MPI_ABORT|stacktrace|aborted|segmentation" "$work/stderr" "$work/stdout"; then
    echo "FAIL $name (exit $code, expected $want):"
    cat "$work/stderr"
    failures=$((failures + 1))
  else
    echo "ok   $name: $(grep "signorini: error: " "$work/stderr")"
  fi
}
if command -v mpirun > /dev/null; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  check_mpi 1 "MPI: missing parameter file" "nothere.prm" 2 "$work/nothere.prm"
  case_prm "Poisson ratio 0.7" "Material/Poisson ratio" \
    "subsection Material
  set Poisson ratio = 0.7
end"
  check_mpi 1 "MPI: Poisson ratio 0.7" "Material/Poisson ratio" 2 "$work/case.prm"
  check_mpi 1 "MPI: Poisson ratio 0.7 (--validate, 3 ranks)" \
    "Material/Poisson ratio" 3 --validate "$work/case.prm"
  case_prm_exit 2 "adapted mesh beyond Maximum cells (serial)" \
    "Maximum cells: the adapted mesh of cycle 2" \
    "set Number of cycles = 3
subsection Mesh adaptation
  set Strategy     = optimal size
  set Target error = 1e-4
end
$quiet"
  check_mpi 2 "MPI: adapted mesh beyond Maximum cells" \
    "Maximum cells: the adapted mesh of cycle 2" 2 "$work/case.prm"
  # an error on rank 1 alone (its piece of the solution is a /dev/full
  # node): it names itself and aborts the job, rank 0 knowing nothing
  mkdir "$work/piece"
  if mknod "$work/piece/solution-00.001.vtu" c 1 7 2> /dev/null; then
    printf 'solution-00.001.vtu\n' > "$work/piece/.signorini-manifest"
    outdir_prm "$work/od.prm" "$work/piece" "set Number of cycles = 1
$quiet"
    count=$((count + 1))
    mpirun --oversubscribe -np 2 "$exe" "$work/od.prm" > "$work/stdout" 2> "$work/stderr"
    code=$?
    if [ "$code" -eq 2 ] &&
       [ "$(grep -c "signorini: error: " "$work/stderr")" -eq 1 ] &&
       grep -q "^signorini: error: (rank 1) cannot write <.*solution-00.001.vtu>: No space left" "$work/stderr"; then
      echo "ok   MPI: write failure on rank 1 alone: $(grep "signorini: error: " "$work/stderr")"
    else
      echo "FAIL MPI: write failure on rank 1 alone (exit $code):"
      cat "$work/stderr"
      failures=$((failures + 1))
    fi
  else
    echo "ok   (skipped: no mknod) MPI: write failure on rank 1 alone"
  fi
else
  echo "ok   (skipped: no mpirun) MPI cases"
fi

# --- hostile parameter files ---

# includes: deal.II recurses without limit (a loop was a segfault)
mkdir -p "$work/inc"
printf 'include %s/inc/self.prm\n' "$work" > "$work/inc/self.prm"
check "include of itself" \
  "include <.*inc/self.prm> line 1 -> <.*inc/self.prm>: the files include each other in a cycle" \
  "$work/inc/self.prm"
printf 'include %s/inc/b.prm\n' "$work" > "$work/inc/a.prm"
printf '# b\ninclude %s/inc/a.prm\n' "$work" > "$work/inc/b.prm"
check "includes in a loop" \
  "<.*inc/a.prm> line 1 -> <.*inc/b.prm> line 2 -> <.*inc/a.prm>: the files include each other in a cycle" \
  "$work/inc/a.prm"
for i in 0 1 2 3 4 5 6 7 8 9 10 11; do
  printf '  include %s/inc/d%d.prm\n' "$work" $((i + 1)) > "$work/inc/d$i.prm"
done
printf 'set Output directory = %s/out\n' "$work" > "$work/inc/d12.prm"
check "includes nested too deep" "includes nested deeper than 10" \
  "$work/inc/d0.prm"
case_prm "included file missing" \
  "include <.*case.prm> line 50 -> <no-such.prm>: the included file (relative to the working directory) does not exist" \
  "include no-such.prm"
printf 'include %s/inc/none.prm\n' "$work" > "$work/inc/c.prm"
check "nested included file missing" \
  "<.*inc/c.prm> line 1 -> <.*inc/none.prm>: the included file does not exist" \
  "$work/inc/c.prm"
{ sed '/Output directory/d' "$block"
  printf 'set Output directory = %s/out\n' "$work"; } > "$work/inc/body.prm"
printf '# the block\n\tinclude %s/inc/body.prm\n' "$work" > "$work/inc/ok.prm"
valid_prm "include (indented, by tab)" --validate "$work/inc/ok.prm"

# function constants: a clash with a variable was an uncaught
# mu::ParserError (abort), a constant pi silently 3.14159
traction_constants() { # CONSTANTS [VARIABLES]: Traction 1 with these
  printf 'subsection Boundary conditions\n  subsection Traction 1\n'
  printf '    set Function constants = %s\n' "$1"
  [ -n "${2:-}" ] && printf '    set Variable names = %s\n' "$2"
  printf '    set Function expression = 0; -0.1\n  end\nend\n'
}
case_prm "constant named x" \
  "Traction 1: Function constants = p=0.1, x=5: <x> is the name of a variable" \
  "$(traction_constants 'p=0.1, x=5')"
case_prm "constant named t" "<t> is the name of a variable" \
  "$(traction_constants 'p=0.1, t=3')"
case_prm "constant named like a variable name" \
  "<u> is the name of a variable (x, y, z, t or Variable names = u,v,t)" \
  "$(traction_constants 'u=1' 'u,v,t')"
case_prm "variable named pi" \
  "Traction 1: Variable names = pi,y,t: <pi> is a predefined constant" \
  "$(traction_constants '' 'pi,y,t')"
case_prm "constant named pi" "Function constants = pi=0.1: <pi> is a predefined constant" \
  "$(traction_constants 'pi=0.1')"
case_prm "constant named Pi" "<Pi> is a predefined constant" \
  "$(traction_constants 'Pi=0.1')"
case_prm "constant named _e" "<_e> is a predefined constant" \
  "$(traction_constants 'p=0.1, _e=3')"
case_prm "constant named _pi" "<_pi> is a predefined constant" \
  "$(traction_constants '_pi=3')"

# command line: one line naming the mistake, with the usage
usage='; usage: signorini \[--validate\] FILE.prm | --print-parameters | --help$'
check "no arguments" "no parameter file given$usage"
check "two files" "too many arguments (2), one parameter file expected$usage" \
  a.prm b.prm
check "--validate alone" "--validate needs a parameter file$usage" --validate
check "unknown option" "unknown option <--frobnicate>$usage" --frobnicate
check "standard input" "unknown option <->$usage" -

# messages: named file and line, no truncation, no megabyte lines
printf '[1,2,3]\n' > "$work/array.json"
check "JSON array" \
  "<.*array.json>: line 1: a JSON array is not a deal.II parameter file entry" \
  "$work/array.json"
printf '{"Material":\n {"Young modulus": [1,2]}}\n' > "$work/value.json"
check "JSON array value" "<.*value.json>: line 2: a JSON array" "$work/value.json"
{ cat "$block"
  printf 'subsection Material\n  set Poisson ratio = 0.3\0abc\nend\n'; } \
  > "$work/nul.prm"
check "NUL byte" "<.*nul.prm>: contains a NUL byte (binary file?)" "$work/nul.prm"
case_prm "1 MB parameter name" "line 50: A\{200\}\.\.\.: No entry with name <A\{200\}\.\.\.> was declared" \
  "set $(head -c 1000000 /dev/zero | tr '\0' A) = 1"
expect "1 MB parameter name: short message" [ "$(wc -c < "$work/stderr")" -lt 2100 ]
case_prm "unknown subsection" \
  "<.*case.prm>: line 50: There is no such subsection to be entered: Materials$" \
  "subsection Materials
end"

# --- hostile meshes ---

# the block's cells are counted before it is built: refused at once
case_prm "3000 x 3000 block (was OOM)" \
  "Mesh/Block subdivisions: 3000 x 3000 rectangles give 72000000 triangles, more than Maximum cells" \
  "subsection Mesh
  set Block subdivisions = 3000, 3000
end"
case_prm "largest block subdivisions" \
  "Mesh/Block subdivisions: 2147483647 x 2147483647 rectangles give 3.69e+19" \
  "subsection Mesh
  set Block subdivisions = 2147483647, 2147483647
end"
case_prm "block beyond 32-bit cell numbers" \
  "Mesh/Block subdivisions: 65536 x 65536 rectangles and 0 initial refinements give more than 2e9" \
  "subsection Mesh
  set Block subdivisions = 65536, 65536
end
set Maximum cells = 1e12
set Number of cycles = 1"
case_prm "refinements of a fine block" \
  "Mesh/Initial refinements: 2 refinements of the 720000 initial cells" \
  "subsection Mesh
  set Block subdivisions = 300, 300
  set Initial refinements = 2
end"

# msh22_nodes FILE AWK: square-22.msh with AWK applied to each node's x, y
msh22_nodes() {
  awk "/^\\\$Nodes/ { n = 1; print; next } /^\\\$EndNodes/ { n = 0 }
       n && NF == 4 { $2; printf \"%s %.17g %.17g %s\\n\", \$1, x, y, \$4; next }
       { print }" "$msh22" > "$1"
}
# one body only: a second triangle apart, or touching at a corner
awk '/^\$EndNodes/ { print "13 2 0 0\n14 3 0 0\n15 2 1 0" }
     $0 == "12" && !n { $0 = "15"; n = 1 } $0 == "22" { $0 = "23" }
     /^\$EndElements/ { print "23 2 2 1 1 13 14 15" } { print }' "$msh22" \
  > "$work/two-bodies.msh"
mesh_case "two separate bodies" \
  "two-bodies.msh> has 2 separate parts (one body is modelled); part 2 contains the triangle 23 at (2.33333, 0.333333)" \
  "$work/two-bodies.msh"
awk '/^\$EndNodes/ { print "13 2 1 0\n14 2 2 0" }
     $0 == "12" && !n { $0 = "14"; n = 1 } $0 == "22" { $0 = "23" }
     /^\$EndElements/ { print "23 2 2 1 1 4 13 14" } { print }' "$msh22" \
  > "$work/corner.msh"
mesh_case "two bodies sharing a corner" \
  "corner.msh> has 2 separate parts (one body is modelled); part 2 contains the triangle 23 at (1.66667, 1.33333)" \
  "$work/corner.msh"

# extreme scales: refused before the solver sees overflowing numbers
msh22_nodes "$work/big.msh" 'x = $2 * 1e200; y = $3 * 1e200'
mesh_case "mesh 1e200 across" \
  "big.msh>: the mesh is 1.41421e+200 across, outside .1e-100, 1e100.: change the units" \
  "$work/big.msh"
msh22_nodes "$work/small.msh" 'x = $2 * 1e-200; y = $3 * 1e-200'
mesh_case "mesh 1e-200 across" \
  "small.msh>: the mesh is 1.41421e-200 across, outside .1e-100, 1e100.: change the units" \
  "$work/small.msh"
msh22_nodes "$work/far.msh" 'x = $2 * 1e90 + 1e160; y = $3 * 1e90'
mesh_case "coordinates of 1e160" \
  "far.msh>: line 6: node 1 has the coordinate 1e+160, beyond 1e150 in absolute value" \
  "$work/far.msh"
for scale in 1e90 1e-90; do
  msh22_nodes "$work/scaled.msh" "x = \$2 * $scale; y = \$3 * $scale"
  { cat "$block"; mesh_prm "$work/scaled.msh"; echo
    printf 'set Number of cycles = 1\nset Output directory = %s/out\n' "$work"
    printf 'subsection Output\n  set Write vtu = false\nend\n'; } > "$work/case.prm"
  valid_prm "a computation on the square scaled by $scale" "$work/case.prm"
done

# --- bodies held by the contact alone; solution checks decide ---

case_prm "no Dirichlet part: sliding is free" \
  "free to move: the translation along (1, 0)" \
  "subsection Boundary conditions
  subsection Dirichlet 1
    set Boundary ids = 
  end
end"
case_prm "roller, load pulling away from the foundation" \
  "no equilibrium: .*translation along (0, 1)" \
  "subsection Boundary conditions
  subsection Dirichlet 1
    set Components = x
  end
  subsection Traction 1
    set Function expression = 0; p
  end
  subsection Traction 2
    set Function expression = 0; 0
  end
end"
case_prm "roller, Frank-Wolfe, load pulling away" "no equilibrium" \
  "subsection Boundary conditions
  subsection Dirichlet 1
    set Components = x
  end
  subsection Traction 1
    set Function expression = 0; p
  end
end
subsection Contact
  set Solver = Frank-Wolfe
end"
case_prm "roller, no load" "no equilibrium" \
  "subsection Boundary conditions
  subsection Dirichlet 1
    set Components = x
  end
  subsection Traction 1
    set Function expression = 0; 0
  end
  subsection Traction 2
    set Function expression = 0; 0
  end
end"
# --validate finds them before any solve
check "--validate: roller, no load (the case above)" "no equilibrium" \
  --validate "$work/case.prm"
# finite data whose products overflow in the solve are refused as input
case_prm "traction too large to compute with" "stresses of order 1e160 " \
  "subsection Boundary conditions
  subsection Traction 1
    set Function constants = p=1e160
  end
end"
case_prm "body force too large to compute with" "stresses of order 1e308 " \
  "subsection Boundary conditions
  subsection Body force
    set Function expression = 0; -1e308*x
  end
end"
case_prm "prescribed displacement too large" "stresses of order 1e200 " \
  "subsection Boundary conditions
  subsection Dirichlet 1
    set Function expression = 1e200; 0
  end
end"
case_prm_exit 2 "solution checks beyond their tolerance" \
  "cycle 0: the solution checks fail: feasibility .* > Contact/Check tolerance" \
  "subsection Contact
  set Solver = Frank-Wolfe
  subsection Frank-Wolfe
    set Tolerance = 0.5
  end
end"
case_prm_exit 2 "Frank-Wolfe stopped early" \
  "cycle 0: the Frank-Wolfe solver did not converge" \
  "subsection Contact
  set Solver = Frank-Wolfe
  subsection Frank-Wolfe
    set Maximum iterations = 3
  end
end"

# --- 3D meshes: tetrahedra read with Dimension = 3 ---

# tests/meshes/cube.msh (from cube.geo): the unit cube in 100 tetrahedra,
# boundary ids 1 (x = 0), 2 (z = 0), 3 (z = 1); valid, then corrupted one way
# each. cube_prm FILE: a 3D case clamped on 1, loaded on 3, contact on 2.
cube=$src/tests/meshes/cube.msh
cube_prm() {
  printf 'set Dimension = 3\nset Output directory = %s/out\n' "$work"
  printf 'subsection Mesh\n  set Source = file\n  set File name = %s\nend\n' "$1"
  printf 'subsection Boundary conditions\n  subsection Dirichlet 1\n    set Boundary ids = 1\n'
  printf '    set Function expression = 0; 0; 0\n  end\n  subsection Traction 1\n'
  printf '    set Boundary ids = 3\n    set Function expression = 0; 0; -0.01\n  end\nend\n'
  printf 'subsection Contact\n  set Boundary ids = 2\n  set Direction = 0, 0, -1\n'
  printf '  subsection Gap\n    set Function expression = 0.001\n  end\nend\n'
  printf 'subsection Error estimator\n  set Enable = false\nend\n'
}
# cube_case NAME EXPECTED FILE: reading FILE in 3D is an input error
cube_case() {
  cube_prm "$3" > "$work/cube.prm"
  check "$1" "$2" "$work/cube.prm"
}
cube_prm "$cube" > "$work/cube.prm"
valid_prm "3D mesh" --validate "$work/cube.prm"
# tetrahedra in the other orientation are turned, as in 2D
awk '$2 == 4 && NF == 9 { t = $8; $8 = $9; $9 = t } { print }' "$cube" > "$work/cube-turned.msh"
cube_prm "$work/cube-turned.msh" > "$work/cube.prm"
valid_prm "3D mesh, tetrahedra turned" --validate "$work/cube.prm"
# add_elements FILE N LINES...: the cube with N more elements (LINES)
add_elements() {
  local out=$1 n=$2
  shift 2
  sed "s/^142\$/$((142 + n))/" "$cube" | sed '/^\$EndElements$/,$d' > "$out"
  printf '%s\n' "$@" '$EndElements' >> "$out"
}
add_elements "$work/cube-twice.msh" 1 "1000 4 2 1 1 24 32 23 45"
cube_case "3D: repeated tetrahedron" \
  "line 196: tetrahedra 43 and 1000 overlap: they lie on the same side of their face" "$work/cube-twice.msh"
add_elements "$work/cube-flat.msh" 1 "1000 4 2 1 1 1 2 3 4"
cube_case "3D: zero-volume tetrahedron" \
  "tetrahedron 1000 has zero volume: its nodes 1 (0, 0, 0), 2 (1, 0, 0), 3 (1, 1, 0), 4 (0, 1, 0) are coplanar" \
  "$work/cube-flat.msh"
add_elements "$work/cube-hanging.msh" 1 "1000 4 2 1 1 46 1 9 47"
sed -i 's/^45$/47/; s/^\$EndNodes$/46 0.2916666666666667 0.125 0\n47 0.2916666666666667 0.125 -0.3\n$EndNodes/' \
  "$work/cube-hanging.msh"
cube_case "3D: hanging node on a boundary face" \
  "node 46 (0.291667, 0.125, 0) lies on the boundary face between nodes 1, 9 and 22 without being a corner of its tetrahedron (a hanging node)" \
  "$work/cube-hanging.msh"
add_elements "$work/cube-two.msh" 1 "1000 4 2 1 1 46 47 48 49"
sed -i 's/^45$/49/; s/^\$EndNodes$/46 5 5 5\n47 6 5 5\n48 5 6 5\n49 5 5 6\n$EndNodes/' "$work/cube-two.msh"
cube_case "3D: two bodies" \
  "cube-two.msh> has 2 separate parts (one body is modelled); part 2 contains the tetrahedron 1000 at (5.25, 5.25, 5.25)" \
  "$work/cube-two.msh"
add_elements "$work/cube-inner.msh" 1 "1000 2 2 5 5 24 32 45"
cube_case "3D: boundary id inside the body" \
  "triangle element 1000 (physical tag 5, nodes 24 .*) lies inside the mesh, between tetrahedra" "$work/cube-inner.msh"
add_elements "$work/cube-stray.msh" 1 "1000 2 2 5 5 1 7 45"
cube_case "3D: boundary id on no face" "triangle element 1000 .* is not a face of any tetrahedron" \
  "$work/cube-stray.msh"
add_elements "$work/cube-hex.msh" 1 "1000 5 2 1 1 1 2 3 4 5 6 7 8"
cube_case "3D: hexahedron" \
  "line 196: hexahedra, prisms and pyramids (type 5) are not supported: signorini needs a mesh of 4-node tetrahedra" \
  "$work/cube-hex.msh"
cube_case "3D: a 2D mesh" \
  "square-22.msh> contains no tetrahedra (Gmsh type 4): with Dimension = 3 signorini needs a 3D mesh" "$msh22"
# a .geo is meshed by Gmsh first
cube_case "3D: missing geometry" "Mesh/File name: cannot open geometry file <$work/none.geo>" "$work/none.geo"
printf 'Point(1) = {0, 0, 0;\n' > "$work/broken.geo"
cube_case "3D: geometry Gmsh cannot read" "Mesh/File name: geometry file <$work/broken.geo>: Gmsh failed" \
  "$work/broken.geo"
cube_case "3D: geometry of a square" "square.geo as meshed by Gmsh> contains no tetrahedra" \
  "$src/tests/meshes/square.geo"
# the star patch on tetrahedra: P2 patches only
{ cube_prm "$cube"; printf 'subsection Error estimator\n  set Enable = true\n'
  printf '  set Stress reconstruction = star patch\n  subsection Star patch\n'
  printf '    set Local degree = 3\n  end\nend\n'; } > "$work/cube.prm"
check "3D: star patch of degree 3" \
  "Error estimator/Star patch/Local degree = 3: at most 2 on tetrahedra" "$work/cube.prm"
# the element equilibration on tetrahedra: displacement element problems of
# degree >= 3 and the enhanced or least squares densities only.
# eet_case NAME EXPECTED ENTRY VALUE [ENTRY VALUE]
eet_case() {
  { cube_prm "$cube"; printf 'subsection Error estimator\n  set Enable = true\n'
    printf '  subsection Element equilibration\n    set %s = %s\n' "$3" "$4"
    [ $# -ge 6 ] && printf '    set %s = %s\n' "$5" "$6"
    printf '  end\nend\n'; } > "$work/cube.prm"
  check "$1" "$2" "$work/cube.prm"
}
eet_case "3D: minimised densities" \
  "Traction densities = minimised is written for triangles" "Traction densities" minimised
eet_case "3D: displacement element problems of degree 2" \
  "Local degree must be at least 3 on tetrahedra" "Local degree" 2 "Element stress" displacement
eet_case "3D: element problems of degree 5" \
  "Local degree is at most 4 on tetrahedra" "Local degree" 5
cube_case "3D: geometry that calls Exit" \
  "Mesh/File name: geometry file <$work/exit.geo>: Gmsh ended the program" "$work/exit.geo"
# adapted meshes of tetrahedra: remeshing only, with a geometry of a volume
# whose physical surfaces carry the ids in use. cube_adaptive REALISATION
# [GEOMETRY]: the cube adapted to 10 % with the star patch
cube_adaptive() {
  cube_prm "$cube"
  printf 'subsection Error estimator\n  set Enable = true\n'
  printf '  set Stress reconstruction = star patch\nend\n'
  printf 'subsection Mesh adaptation\n  set Strategy = optimal size\n'
  printf '  set Target error = 0.1\n  set Realisation = %s\nend\n' "$1"
  [ $# -ge 2 ] && printf 'subsection Mesh\n  set Geometry file = %s\nend\n' "$2"
}
cube_adaptive refinement "$src/tests/meshes/cube.geo" > "$work/cube.prm"
check "3D: adapted by refinement" \
  "Mesh adaptation/Realisation: adapted meshes of tetrahedra are made by remeshing" "$work/cube.prm"
cube_adaptive remeshing > "$work/cube.prm"
check "3D: remeshing without a geometry" \
  "Mesh adaptation/Realisation = remeshing needs the geometry of the domain" "$work/cube.prm"
cube_adaptive remeshing "$src/tests/meshes/square.geo" > "$work/cube.prm"
check "3D: remeshing a geometry without a volume" \
  "Mesh/Geometry file: <$src/tests/meshes/square.geo>: it defines no volume to mesh" "$work/cube.prm"
sed 's/Physical Surface(2) = {1};/Physical Surface(7) = {1};/' \
  "$src/tests/meshes/cube.geo" > "$work/cube-retagged.geo"
cube_adaptive remeshing "$work/cube-retagged.geo" > "$work/cube.prm"
check "3D: remeshing a geometry without a boundary id in use" \
  "no physical surface has the tag 2, a boundary id of the input" "$work/cube.prm"
cube_adaptive remeshing "$src/tests/meshes/cube.geo" > "$work/cube.prm"
valid_prm "3D: remeshing the cube" --validate "$work/cube.prm"

# --- units, zero loads and tolerances (issue 34, classes 3, 6-12) ---

# A problem without stress is solved exactly: eps = 0, not 0/0 or the ratio
# of two round-off errors, and the checks are relative to the forces of the
# imposed displacements when there is no load. zero_stress NAME PRM: PRM
# runs (exit 0), converged, with eps = 0 and the screen saying why.
zero_stress() {
  count=$((count + 1))
  rm -rf "$work/out"
  "$exe" "$2" > "$work/stdout" 2> "$work/stderr"
  local code=$?
  local eps converged
  eps=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "eps") c = i }
                 NR == 2 { print $c }' "$work/out/statistics.csv" 2> /dev/null)
  converged=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "converged") c = i }
                       NR == 2 { print $c }' "$work/out/statistics.csv" 2> /dev/null)
  if [ "$code" -ne 0 ] || [ -s "$work/stderr" ] || [ "$converged" != 1 ] ||
     ! awk -v e="$eps" 'BEGIN { exit !(e == 0) }' ||
     ! grep -q "eps = 0 % .*no stress (to round-off), the solution is exact" "$work/stdout"; then
    echo "FAIL $1 (exit $code, converged <$converged>, eps <$eps>):"
    cat "$work/stderr"
    grep "eps =\|checks" "$work/stdout"
    failures=$((failures + 1))
  else
    echo "ok   $1: $(grep -o "eps = 0 %.*" "$work/stdout" | head -n 1)"
  fi
}
unloaded="subsection Boundary conditions
  subsection Traction 1
    set Function constants = p=0
  end
  subsection Traction 2
    set Function constants = p=0
  end
end"
translated="$unloaded
subsection Boundary conditions
  subsection Dirichlet 1
    set Function expression = 0; -0.01
  end
end
subsection Contact
  subsection Gap
    set Function expression = 1
  end
end"
{ cat "$block"; printf '%s\nset Number of cycles = 2\nset Output directory = %s/out\n' "$unloaded" "$work"; } > "$work/zero.prm"
zero_stress "no load: eps = 0, two cycles" "$work/zero.prm"
{ cat "$block"; printf '%s\nset Number of cycles = 1\nset Output directory = %s/out\n' "$translated" "$work"; } > "$work/zero.prm"
zero_stress "rigid translation imposed, no load" "$work/zero.prm"
# the same with the prescribed translation in other units of length
sed 's/0; -0.01/0; -1e-9/' "$work/zero.prm" > "$work/zero-small.prm"
zero_stress "rigid translation of 1e-9, no load" "$work/zero-small.prm"
# in 3D: the extruded block, unloaded, then translated (z held by rollers)
block3d() { # TEXT: the tests' 3D block, one cycle, with TEXT
  { cat "$src/tests/runs/block_3d_uniaxial.prm"
    printf 'set Number of cycles = 1\nset Output directory = %s/out\n%s\n' "$work" "$1"
  } > "$work/zero3d.prm"
}
block3d "subsection Boundary conditions
  subsection Dirichlet 1
    set Components          = x, y, z
    set Function expression = 0; -0.01; 0
  end
  subsection Dirichlet 2
    set Function expression = 0; 0; 0
  end
  subsection Traction 1
    set Function expression = 0; 0; 0
  end
end
subsection Exact solution
  set Enable = false
end
subsection Contact
  subsection Gap
    set Function expression = 1
  end
end
subsection Error estimator
  set Enable = true
end"
zero_stress "3D: rigid translation imposed, no load" "$work/zero3d.prm"
# a deformation at the level of round-off of a large rigid motion: computed,
# with a warning that eps is polluted
warns "translation of 1 with loads of 1e-12" "the strains are within 1e5 round-offs" \
  "subsection Boundary conditions
  subsection Dirichlet 1
    set Function expression = 1; 1
  end
  subsection Traction 1
    set Function constants = p=1e-12
  end
  subsection Traction 2
    set Function constants = p=1e-12
  end
end
subsection Contact
  subsection Gap
    set Function expression = 10
  end
end"

# Data whose stresses or displacements double precision cannot square are
# refused by name, before the first solve
case_prm "Young modulus 1e300" "Material/Young modulus: the data give displacements of order 1e-301 " \
  "subsection Material
  set Young modulus = 1e300
end"
case_prm "Young modulus 1e-300" "displacements of order 1e299 " \
  "subsection Material
  set Young modulus = 1e-300
end"
case_prm "loads of 1e-300" "stresses of order 1e-300 " \
  "subsection Boundary conditions
  subsection Traction 1
    set Function constants = p=1e-300
  end
  subsection Traction 2
    set Function constants = p=1e-300
  end
end"
# units E P: the block's Young modulus E and its two pressures P
units() {
  printf 'subsection Material\n  set Young modulus = %s\nend\n' "$1"
  printf 'subsection Boundary conditions\n'
  printf '  subsection Traction %s\n    set Function constants = p=%s\n  end\n' 1 "$2" 2 "$2"
  printf 'end\n'
}
command -v mpirun > /dev/null && check_mpi 1 "MPI: loads of 1e-300 (3 ranks)" "stresses of order 1e-300 " 3 "$work/case.prm"
case_prm "loads of 1e-160 with E = 1e-159" "stresses of order 1e-160 " \
  "$(units 1e-159 1e-160)"
case_prm "loads of 1e150 with E = 1e151" "stresses of order 1e150 " \
  "$(units 1e151 1e150)"

# Values beyond single precision are not written as inf in the VTU file
case_prm "loads of 1e39: the VTU cannot hold the displacement" \
  "cycle 0: the field displacement reaches values beyond the single precision of the VTU output" \
  "subsection Boundary conditions
  subsection Traction 1
    set Function constants = p=1e39
  end
  subsection Traction 2
    set Function constants = p=1e39
  end
end"

# The estimate does not depend on the unit of stress: E and the loads
# scaled together give the block's eps (without VTU, which cannot hold
# stresses of 4e39). close_eps NAME TEXT: eps within 1e-9 of the block's.
close_eps() {
  count=$((count + 1))
  local eps
  eps=$(eps_of "$1" "$2")
  if [ -n "$eps" ] && awk -v a="$eps" -v b="$reference_eps" \
       'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-9 * b) }'; then
    echo "ok   $1: eps = $eps (the block: $reference_eps)"
  else
    echo "FAIL $1: eps = <$eps>, the block gives $reference_eps"
    failures=$((failures + 1))
  fi
}
for E in -130 -50 -20 35 40 80 130; do
  close_eps "units of stress: E = 1e$E" "$(units "1e$E" "1e$((E - 1))")"
done
# in 3D (the estimate on tetrahedra): the extruded block with E = 1e40 or
# 1e-50 and its loads in the same units gives the eps of E = 1, to 1e-8
# relative: the few hundred conjugate gradient iterations of the
# enhancement carry the round-off of the scaled data (1e40 is no power of
# 2) to about 1e-9
eps_3d() { # SED_SCRIPT: eps of tests/runs/estimator_3d_equilibration.prm so changed
  sed -e "$1" -e 's/set Extra refinements = 1/set Extra refinements = 0/' \
    "$src/tests/runs/estimator_3d_equilibration.prm" > "$work/units3d.prm"
  printf 'set Output directory = %s/out\nsubsection Output\n  set Write vtu = false\nend\n' "$work" >> "$work/units3d.prm"
  rm -rf "$work/out"
  "$exe" "$work/units3d.prm" > /dev/null 2>&1 &&
    awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "eps") c = i }
             NR == 2 { print $c }' "$work/out/statistics.csv"
}
eps_e1=$(eps_3d 's/p=0.1/p=0.1/')
for E in 40 -50; do
  count=$((count + 1))
  eps_scaled=$(eps_3d "s/p=0.1/p=1e$((E - 1))/; s/Young modulus = 1/Young modulus = 1e$E/")
  if [ -n "$eps_e1" ] && [ -n "$eps_scaled" ] && awk -v a="$eps_scaled" -v b="$eps_e1" \
       'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-8 * b) }'; then
    echo "ok   3D: units of stress, E = 1e$E: eps = $eps_scaled (E = 1: $eps_e1)"
  else
    echo "FAIL 3D: units of stress: eps = <$eps_scaled> at E = 1e$E, <$eps_e1> at E = 1"
    failures=$((failures + 1))
  fi
done
# with a gap (the active rows are displacement constraints: the solver's
# tolerance is relative to the forces of the free rows, not to the gap)
gap="subsection Contact
  subsection Gap
    set Function expression = 0.001*x
  end
end"
count=$((count + 1))
gap_e1=$(eps_of "gap, E = 1" "$gap")
gap_e20=$(eps_of "gap, E = 1e-20" "$gap
$(units 1e-20 1e-21)")
if [ -n "$gap_e1" ] && awk -v a="$gap_e20" -v b="$gap_e1" \
     'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-9 * b) }'; then
  echo "ok   units of stress with a gap, E = 1e-20: eps = $gap_e20 (E = 1: $gap_e1)"
else
  echo "FAIL units of stress with a gap: eps = <$gap_e20> at E = 1e-20, <$gap_e1> at E = 1"
  failures=$((failures + 1))
fi

# Tolerances that round-off cannot meet
case_prm "Frank-Wolfe/Tolerance = 0" "Contact/Frank-Wolfe/Tolerance: The entry value 0" \
  "subsection Contact
  set Solver = Frank-Wolfe
  subsection Frank-Wolfe
    set Tolerance = 0
  end
end"
case_prm "Check tolerance = 0" "Contact/Check tolerance: The entry value 0" \
  "subsection Contact
  set Check tolerance = 0
end"

# Line endings: CR alone would make the file one comment line
tr '\n' '\r' < "$block" > "$work/cr.prm"
check "parameter file with CR line endings" "cr.prm>: has lines ended by a lone carriage return" "$work/cr.prm"
sed 's/$/\r/' "$block" > "$work/crlf.prm"
printf 'set Output directory = %s/out\r\n' "$work" >> "$work/crlf.prm"
valid_prm "parameter file with CR LF line endings" --validate "$work/crlf.prm"
printf 'set Number of cycles = 1\r' > "$work/included-cr.prm"
case_prm "included file with CR line endings" "the included file: has lines ended by a lone carriage return" \
  "include $work/included-cr.prm"

# Variable names that would silently rename a coordinate or the time
printf 'set Dimension = 3\nset Output directory = %s/out\nsubsection Contact\n  subsection Gap\n    set Variable names = x,y,t\n  end\nend\n' "$work" > "$work/vars3d.prm"
check "3D: Variable names = x,y,t" "Dimension = 3: Contact/Gap: Variable names = x,y,t: in 3D <t> would be the coordinate z" \
  --validate "$work/vars3d.prm"
case_prm "2D: Variable names = x,y,z" "Contact/Gap: Variable names = x,y,z: in 2D <z> would be the time" \
  "subsection Contact
  subsection Gap
    set Variable names = x,y,z
  end
end"
case_prm "2D: Variable names = y,x" "Variable names = y,x: in 2D <y> would be the coordinate x" \
  "subsection Boundary conditions
  subsection Body force
    set Variable names = y,x
  end
end"
# the 3D defaults name the 3D variables and parse back in 3D
count=$((count + 1))
"$exe" --print-parameters 3 > "$work/defaults3d.prm"
if grep -q "set Variable names *= x,y,z,t" "$work/defaults3d.prm" &&
   ! grep -q "set Variable names *= x,y,t" "$work/defaults3d.prm" &&
   "$exe" --validate "$work/defaults3d.prm" 2>&1 | grep -q "Dimension = 3: the body is free to move"; then
  echo "ok   --print-parameters 3: x,y,z,t, parses back in 3D"
else
  echo "FAIL --print-parameters 3"
  failures=$((failures + 1))
fi
check "--print-parameters 4" "print-parameters 4: the dimension is 2 or 3" --print-parameters 4

# --- Gmsh on hostile geometry (issue 34) ---
# Gmsh runs on a user's .geo in a child process: an abort, a segfault or an
# Exit there is one error line, exit 1; sizes <= 0 and sizes that would make
# more than Maximum cells are refused before meshing; a remeshing geometry
# must be the domain of the mesh (one body, box, measure, boundary ids).
geo_neg=$work/cube-negative.geo
sed 's/, 0.5};/, -0.5};/' "$src/tests/meshes/cube.geo" > "$geo_neg"
cube_case "Gmsh: negative sizes" \
  "Mesh/File name: geometry file <$geo_neg>: Point(1) has the mesh size -0.5: sizes must be positive" "$geo_neg"
check "Gmsh: negative sizes, --validate" "Point(1) has the mesh size -0.5" --validate "$work/cube.prm"
{ grep -v '^//' "$src/tests/meshes/cube.geo"
  printf 'Mesh.RecombineAll = 1;\nMesh.Recombine3DAll = 1;\nMesh.Algorithm = 8;\n'; } > "$work/cube-recombined.geo"
cube_case "Gmsh: segfault on recombined 3D meshing" \
  "Mesh/File name: geometry file <$work/cube-recombined.geo>: Gmsh failed: it crashed (signal 11, SIGSEGV)" \
  "$work/cube-recombined.geo"
sed 's/, 0.5};/, 1e-3};/' "$src/tests/meshes/cube.geo" > "$work/cube-tiny.geo"
cube_case "Gmsh: tiny sizes in 3D, refused before meshing" \
  "geometry file <$work/cube-tiny.geo>: its mesh sizes would make at least about 1.6e+07 tetrahedra .*more than Maximum cells = 4000000; refused before meshing" \
  "$work/cube-tiny.geo"
sed 's/, 0.5};/, 1e-12};/' "$src/tests/meshes/cube.geo" > "$work/cube-tinier.geo"
cube_case "Gmsh: sizes of 1e-12 in 3D" \
  "its mesh sizes would make at least about .* tetrahedra .*more than Maximum cells" "$work/cube-tinier.geo"
{ cube_prm "$src/tests/meshes/cube.geo"; printf 'set Maximum cells = 20\n'; } > "$work/cube.prm"
check "Gmsh: the cube beyond a small Maximum cells" \
  "cube.geo>: its mesh sizes would make at least about .* tetrahedra .*more than Maximum cells = 20" "$work/cube.prm"
sed 's/^lc = 0.5;/lc = 1e-4;/' "$src/tests/meshes/square.geo" > "$work/square-tiny.geo"
case_prm "Gmsh: tiny sizes in 2D" \
  "Mesh/File name: geometry file <$work/square-tiny.geo>: its mesh sizes would make at least about .* triangles" \
  "subsection Mesh
  set Source = file
  set File name = $work/square-tiny.geo
end"
# the sizes Gmsh computes times the file's Mesh.MeshSizeFactor
{ cat "$src/tests/meshes/square.geo"; printf 'Mesh.MeshSizeFactor = 0.003;\n'; } > "$work/square-factor.geo"
case_prm "Gmsh: Mesh.MeshSizeFactor = 0.003" \
  "square-factor.geo>: its mesh sizes would make at least about 1e+06 triangles .*more than Maximum cells = 100000; refused before meshing" \
  "set Maximum cells = 1e5
subsection Mesh
  set Source = file
  set File name = $work/square-factor.geo
end"
sed 's/^lc = 0.5;/lc = -1;/' "$src/tests/meshes/square.geo" > "$work/square-negative.geo"
case_prm "Gmsh: negative sizes in 2D" "Point(1) has the mesh size -1: sizes must be positive" \
  "subsection Mesh
  set Source = file
  set File name = $work/square-negative.geo
end"
# the remeshing geometry against the mesh. hertz_remeshing NAME EXPECTED
# GEOMETRY [MESH]: the adaptive Hertz test with GEOMETRY and MESH (by default
# its coarse mesh), an input error
hertz_geo=$src/tests/meshes/hertz-geometry.geo
hertz_coarse=$src/tests/meshes/hertz-coarse.msh
hertz_remeshing() {
  sed -e "s|set File name *=.*|set File name = ${4:-$hertz_coarse}|" \
      -e "s|set Geometry file *=.*|set Geometry file = $3|" \
      -e "s|set Output directory *=.*|set Output directory = $work/out|" \
      "$src/tests/runs/hertz_adaptive.prm" > "$work/hertz.prm"
  check "$1" "$2" "$work/hertz.prm"
}
sed 's/^R = 1;/R = 2;/' "$hertz_geo" > "$work/hertz-twice.geo"
hertz_remeshing "Gmsh: geometry twice the mesh" \
  "Mesh/Geometry file: <$work/hertz-twice.geo> is not the domain of the mesh <$hertz_coarse>: its domain spans \[0, 2\] x \[-2, 0\], the mesh's \[0, 1\] x \[-1, 0\]" \
  "$work/hertz-twice.geo"
sed 's/^R = 1;/R = 3;/' "$hertz_geo" > "$work/hertz-thrice.geo"
hertz_remeshing "Gmsh: geometry three times the mesh" "hertz-thrice.geo> is not the domain of the mesh" \
  "$work/hertz-thrice.geo"
sed 's/^R = 1;/R = 1.1;/' "$hertz_geo" > "$work/hertz-larger.geo"
hertz_remeshing "Gmsh: geometry 10 % larger" "hertz-larger.geo> is not the domain of the mesh" \
  "$work/hertz-larger.geo"
sed -e 's/Physical Curve(2) = {1};/Physical Curve(3) = {1};/' \
    -e 's/Physical Curve(3) = {2};/Physical Curve(2) = {2};/' "$hertz_geo" > "$work/hertz-swapped.geo"
hertz_remeshing "Gmsh: contact and loaded tags swapped" \
  "hertz-swapped.geo> is not the domain of the mesh .*: its boundary id 2 has the length 1, the mesh's 1.57" \
  "$work/hertz-swapped.geo"
# (the symmetry line in two halves, ids 1 and 8)
sed -e 's/^Line(3) = {1, 3};/Point(4) = {0, -R \/ 2, 0};\nLine(3) = {1, 4};\nLine(4) = {4, 3};/' \
    -e 's/^Curve Loop(1) = {1, 2, 3};/Curve Loop(1) = {1, 2, 3, 4};/' \
    -e 's/^Physical Curve(1) = {3};/Physical Curve(1) = {3};\nPhysical Curve(8) = {4};/' \
    "$hertz_geo" > "$work/hertz-extra-id.geo"
hertz_remeshing "Gmsh: geometry with a boundary id the mesh lacks" \
  "its boundary ids (physical curves) are {1, 2, 3, 8}, the mesh's {1, 2, 3}" \
  "$work/hertz-extra-id.geo"
hertz_remeshing "Gmsh: a mesh as the geometry" \
  "Mesh/Geometry file: <$hertz_coarse> is not a Gmsh geometry (.geo) file" "$hertz_coarse"
{ cat "$hertz_geo"
  printf 'Point(11) = {3, 0, 0};\nPoint(12) = {4, 0, 0};\nPoint(13) = {4, 1, 0};\n'
  printf 'Line(11) = {11, 12};\nLine(12) = {12, 13};\nLine(13) = {13, 11};\n'
  printf 'Curve Loop(11) = {11, 12, 13};\nPlane Surface(11) = {11};\nPhysical Surface(2) = {11};\n'; } > "$work/hertz-two.geo"
hertz_remeshing "Gmsh: geometry of two bodies" \
  "hertz-two.geo> is not the domain of the mesh .*: it holds 2 separate bodies" "$work/hertz-two.geo"
sed -e 's/Physical Surface(2) = {1};/Physical Surface(3) = {1};/' \
    -e 's/Physical Surface(3) = {out\[0\]};/Physical Surface(2) = {out[0]};/' \
    "$src/tests/meshes/cube.geo" > "$work/cube-swapped.geo"
cube_adaptive remeshing "$work/cube-swapped.geo" > "$work/cube.prm"
check "Gmsh: 3D geometry with contact and loaded faces swapped (same areas)" \
  "cube-swapped.geo> is not the domain of the mesh .*: its boundary id 2 spans \[0, 1\] x \[0, 1\] x \[1, 1\], the mesh's \[0, 1\] x \[0, 1\] x \[0, 0\]" \
  "$work/cube.prm"
sed 's/Extrude {0, 0, 1}/Extrude {0, 0, 2}/' "$src/tests/meshes/cube.geo" > "$work/cube-tall.geo"
cube_adaptive remeshing "$work/cube-tall.geo" > "$work/cube.prm"
check "Gmsh: 3D geometry twice as tall" "its domain spans \[0, 1\] x \[0, 1\] x \[0, 2\]" "$work/cube.prm"
# the remeshing sets its own options: those that crash Gmsh in the file are
# overridden, the geometry is valid
cube_adaptive remeshing "$work/cube-recombined.geo" > "$work/cube.prm"
valid_prm "Gmsh: remeshing a geometry with crashing options" --validate "$work/cube.prm"
cube_adaptive remeshing "$geo_neg" > "$work/cube.prm"
valid_prm "Gmsh: remeshing a geometry with negative sizes (remeshing brings its own)" \
  --validate "$work/cube.prm"
# the same on 2 MPI ranks: one line, exit 1, every rank stops cleanly
if command -v mpirun > /dev/null; then
  printf '#!/bin/sh\nOMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 exec mpirun -q -np 2 %s "$@"\n' \
    "$(readlink -f "$exe")" > "$work/mpirun2.sh"
  chmod +x "$work/mpirun2.sh"
  serial_exe=$exe
  exe=$work/mpirun2.sh
  cube_case "Gmsh, 2 ranks: negative sizes" "Point(1) has the mesh size -0.5" "$geo_neg"
  cube_case "Gmsh, 2 ranks: segfault" "Gmsh failed: it crashed (signal 11, SIGSEGV)" "$work/cube-recombined.geo"
  cube_case "Gmsh, 2 ranks: tiny sizes" "more than Maximum cells = 4000000; refused before meshing" "$work/cube-tiny.geo"
  hertz_remeshing "Gmsh, 2 ranks: contact and loaded tags swapped" \
    "hertz-swapped.geo> is not the domain of the mesh" "$work/hertz-swapped.geo"
  exe=$serial_exe
fi

# the documented defaults parse back; they name no support, so --validate
# says what is missing (the defaults are a template, not a case)
"$exe" --print-parameters > "$work/defaults.prm"
check "defaults: parse back, no support" "the body is free to move" \
  --validate "$work/defaults.prm"

# and the good paths: --validate accepts the tests' copies of the examples
# (from $work: their relative output directories are the current
# directory's, and one left there by an older version, without a manifest,
# is refused; hertz.prm reads its mesh by a relative path)
count=$((count + 1))
if (exe=$(readlink -f "$exe") && src=$(readlink -f "$src") && cd "$work" &&
    "$exe" --validate "$src/tests/inputs/block.prm" > /dev/null &&
    "$exe" --validate "$src/tests/inputs/manufactured.prm" > /dev/null &&
    "$exe" --validate "$src/tests/inputs/hertz.prm" > /dev/null &&
    "$exe" --validate "$src/tests/inputs/hertz-sphere.prm" > /dev/null); then
  echo "ok   --validate of the example copies"
else
  echo "FAIL --validate of the example copies"
  failures=$((failures + 1))
fi

echo "$((count - failures)) passed, $failures failed"
[ "$failures" -eq 0 ]
