#!/usr/bin/env bash
# Bad input must end with one line "signorini: error: ..." naming the culprit
# and a non-zero exit code, never an abort, a segfault or a backtrace.
# Usage: bad_input.sh SIGNORINI_EXECUTABLE SOURCE_DIR
set -u
exe=$1
src=$2
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
  { cat "$src/prm/block.prm"; printf '%s\n' "$text"; } > "$work/case.prm"
  printf 'set Output directory = %s/out\n' "$work" >> "$work/case.prm"
  check_exit "$want" "$name" "$expected" "$work/case.prm"
}
case_prm() {
  case_prm_exit 1 "$@"
}

printf 'not a mesh\n' > "$work/garbage.msh"

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

# --- non-finite data, parameter files, contact warnings ---

# --- output directory, size guard, failed computations ---

# and the good paths: the documented defaults parse back, --validate accepts
# the shipped examples
count=$((count + 1))
if "$exe" --print-parameters > "$work/defaults.prm" &&
   "$exe" --validate "$work/defaults.prm" > /dev/null &&
   "$exe" --validate "$src/prm/block.prm" > /dev/null &&
   "$exe" --validate "$src/prm/hertz.prm" > /dev/null; then
  echo "ok   defaults round trip and --validate of the examples"
else
  echo "FAIL defaults round trip or --validate"
  failures=$((failures + 1))
fi

echo "$((count - failures)) passed, $failures failed"
[ "$failures" -eq 0 ]
