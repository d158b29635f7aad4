#!/bin/sh
# The axiom gate: runs `Print Assumptions` on each given theorem and
# requires every one to be "Closed under the global context".
#
# usage: assumptions.sh [-R DIR LIB]... [-Q DIR LIB]... [-r MODULE]... [-f FILE]... [NAME]...
#
#   -R/-Q DIR LIB   load paths for coqc (e.g. -R theories ROSGen)
#   -r MODULE       a module to Require first (e.g. ROSGen.Main)
#   -f FILE         read more theorem names from FILE, one per line
#   NAME            a theorem, as it is named after the Requires (Main.generate_node_ddc)
#
# `make -C coq check-assumptions` calls it with every `Theorem` of
# theories/Main.v.  On success it prints
#   proofs: N main theorems closed under the global context
# and exits 0.  Otherwise it prints, for each theorem that is not closed,
#   proofs: error: NAME depends on: AXIOM, AXIOM, ...
# and exits 1.  Exit 2: usage error, no theorem given, or coqc failed
# (e.g. an unknown name).  The axiom list that `coqchk -o` prints is that
# of everything *loaded* (Flocq loads Coq's classical reals); whether a
# theorem *uses* any of it is what `Print Assumptions` decides.
set -eu

usage() { sed -n '5p' "$0" | sed 's/^# //' >&2; exit 2; }

loadpath=""
requires=""
names=""
while [ $# -gt 0 ]; do
  case "$1" in
    -R|-Q) [ $# -ge 3 ] || usage
           [ -d "$2" ] || { echo "assumptions.sh: $2: no such directory" >&2; exit 2; }
           loadpath="$loadpath $1 $(cd "$2" && pwd) $3"; shift 3 ;;
    -r) [ $# -ge 2 ] || usage; requires="$requires $2"; shift 2 ;;
    -f) [ $# -ge 2 ] || usage
        [ -f "$2" ] || { echo "assumptions.sh: $2: no such file" >&2; exit 2; }
        names="$names $(grep -v '^[[:space:]]*\(#\|$\)' "$2" | tr '\n' ' ')"; shift 2 ;;
    -h|--help) usage ;;
    -*) echo "assumptions.sh: unknown option $1" >&2; usage ;;
    *) names="$names $1"; shift ;;
  esac
done
[ -n "$(echo $names)" ] || { echo "assumptions.sh: no theorem given" >&2; exit 2; }
for n in $names $requires; do
  case "$n" in
    *[!A-Za-z0-9_.\']*|.*|*.) echo "assumptions.sh: $n: not a qualified name" >&2; exit 2 ;;
  esac
done

work=$(mktemp -d "${TMPDIR:-/tmp}/rosgen-assumptions.XXXXXX")
trap 'rm -rf "$work"' EXIT INT TERM

# One marker line before each Print Assumptions, so that each answer can
# be told apart.
{
  for r in $requires; do echo "Require $r."; done
  for n in $names; do
    echo "Goal True. idtac \"@@assumptions $n\". Abort."
    echo "Print Assumptions $n."
  done
} > "$work/Assumptions.v"

# shellcheck disable=SC2086
if ! (cd "$work" && coqc -q $loadpath Assumptions.v) > "$work/out.log" 2>&1; then
  cat "$work/out.log" >&2
  echo "proofs: error: Print Assumptions failed (see above)" >&2
  exit 2
fi

# For each theorem: closed, or the names of the axioms it depends on (the
# lines of its answer that start in column 0 after "Axioms:"; a name is
# followed by " : type" or by its type on the next, indented lines).
count=$(echo $names | wc -w)
awk -v expected="$count" '
  function finish() {
    if (cur == "") return
    total++
    if (closed) ok++
    else {
      bad++
      printf "proofs: error: %s depends on: %s\n", cur, (deps == "" ? "(unknown)" : deps) > "/dev/stderr"
    }
  }
  /^@@assumptions / { finish(); cur = $2; closed = 0; deps = ""; next }
  cur == "" { next }
  /^Closed under the global context/ { closed = 1; next }
  /^(Axioms|Section Variables|Opaque constants|Transparent constants):/ { next }
  /^[^ \t]/ {
    name = $0; sub(/ : .*/, "", name); sub(/[ \t]+$/, "", name)
    deps = (deps == "" ? name : deps ", " name)
  }
  END {
    finish()
    if (total != expected) {
      printf "proofs: error: %d answers of Print Assumptions for %d theorems\n", total, expected > "/dev/stderr"
      exit 1
    }
    if (bad > 0) {
      printf "proofs: error: %d of %d main theorems depend on axioms\n", bad, total > "/dev/stderr"
      exit 1
    }
    printf "proofs: %d main theorems closed under the global context\n", ok
  }
' "$work/out.log"
